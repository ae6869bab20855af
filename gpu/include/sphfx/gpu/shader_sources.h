#pragma once
/// @file shader_sources.h
/// @brief GPU sources from shaders/, embedded into the binary at build time (cmake/EmbedShaders.cmake).
///
/// Each library embeds the files it runs: the GPU layer the shared includes (bindings.h and the
/// stages' binding headers it includes, common.glsl) and the self-test, each stage its own programs.
/// A program is assembled from its stage's table, with the shared includes from the GPU layer's.

#include <string_view>
#include <vector>

namespace sphfx {

struct EmbeddedShader {
  std::string_view name;    ///< file name under shaders/, e.g. "sim_density.comp"
  std::string_view source;  ///< file contents
};

/// The embedded files of one library (generated).
using ShaderTable = std::vector<EmbeddedShader>;

/// The GPU layer's files: shared includes and the self-test programs (generated).
const ShaderTable& gpuShaderTable();

/// The source of `name`, looked up in `stage`, then in gpuShaderTable().
/// @throws GLError if neither embeds it.
std::string_view shaderSource(const ShaderTable& stage, std::string_view name);

}  // namespace sphfx
