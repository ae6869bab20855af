#pragma once
/// @file shader_sources.h
/// @brief GPU sources from shaders/, embedded into the binary at build time (cmake/EmbedShaders.cmake).

#include <string_view>
#include <vector>

namespace sphfx {

struct EmbeddedShader {
  std::string_view name;    ///< file name under shaders/, e.g. "density.comp"
  std::string_view source;  ///< file contents
};

/// Every embedded file (generated).
const std::vector<EmbeddedShader>& embeddedShaderTable();

/// The source of one embedded file. @throws GLError if no such file was embedded.
std::string_view shaderSource(std::string_view name);

}  // namespace sphfx
