#pragma once
/// @file sim_shaders.h
/// @brief The simulation stage's embedded GPU sources (shaders/sim_*, sph_*), generated at build time.
#include "sphfx/gpu/shader_sources.h"

namespace sphfx {
const ShaderTable& simShaderTable();
}  // namespace sphfx
