#pragma once
/// @file shader_program.h
/// @brief Programs assembled from embedded sources: `#version`, the scene's `#define`s, the shared
/// includes (bindings.h, common.glsl), then the stage file with its own `#include "x.glsl"` lines resolved.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sphfx/gpu/shader_sources.h"

namespace sphfx {

/// Per-scene feature switches and constants prepended to every program. Ordered, so the assembled
/// text (and hence the shader cache key) is deterministic.
class ShaderDefines {
 public:
  ShaderDefines& set(const std::string& name, const std::string& value = "1");
  ShaderDefines& set(const std::string& name, int value);
  ShaderDefines& set(const std::string& name, unsigned value);
  ShaderDefines& set(const std::string& name, float value);
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  /// "#define NAME VALUE" lines.
  std::string text() const;

 private:
  std::map<std::string, std::string> values_;
};

/// Assembled GLSL plus the file behind each `#line` source number (for error messages).
struct AssembledShader {
  std::string text;
  std::vector<std::string> files;  ///< files[i] is source string number i + 1
};

/// Assembles `stageFile` from `stage`'s embedded sources (shared includes from gpuShaderTable()). Pure
/// text work, no GL needed.
/// @throws GLError for a missing file or an include cycle.
AssembledShader assembleShader(const ShaderTable& stage, const std::string& stageFile,
                               const ShaderDefines& defines);

/// A linked GL program (owns the GL name). Needs a current context.
class ShaderProgram {
 public:
  ShaderProgram() = default;
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  /// Builds a compute program from `stageFile` (e.g. "sim_density.comp") of `stage`'s sources.
  /// @throws GLError with the compiler log, lines mapped back to file names.
  static ShaderProgram compute(const ShaderTable& stage, const std::string& stageFile,
                               const ShaderDefines& defines = {});
  /// Builds a vertex + fragment program. @throws GLError as compute().
  static ShaderProgram graphics(const ShaderTable& stage, const std::string& vertexFile,
                                const std::string& fragmentFile, const ShaderDefines& defines = {});

  uint32_t id() const { return id_; }
  void use() const;
  /// Location of a uniform, or -1 when the compiler removed it.
  int uniform(const char* name) const;
  /// Local work group size of a compute program.
  std::array<int, 3> workGroupSize() const;

 private:
  explicit ShaderProgram(uint32_t id) : id_(id) {}
  uint32_t id_ = 0;
};

/// Runs `program` (already in use) over `count` invocations in groups of its local size along x, then
/// with debug checks on, checks GL errors naming `label`.
void dispatchCompute1D(const ShaderProgram& program, uint32_t count, const char* label);

}  // namespace sphfx
