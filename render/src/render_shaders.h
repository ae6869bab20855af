#pragma once
/// @file render_shaders.h
/// @brief The render stage's embedded GPU sources (shaders/render_*), generated at build time.
#include "sphfx/gpu/shader_sources.h"

namespace sphfx {
const ShaderTable& renderShaderTable();
}  // namespace sphfx
