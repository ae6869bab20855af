#include "sphfx/gpu/shader_program.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <set>
#include <sstream>

#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"
#include "sphfx/gpu/shader_sources.h"

namespace sphfx {

std::string_view shaderSource(const ShaderTable& stage, std::string_view name) {
  for (const ShaderTable* table : {&stage, &gpuShaderTable()})
    for (const auto& s : *table)
      if (s.name == name) return s.source;
  throw GLError(
      fmt::format("shader file \"{}\" is not embedded by this stage (is it under shaders/ with the "
                  "stage's prefix?)",
                  name));
}

ShaderDefines& ShaderDefines::set(const std::string& name, const std::string& value) {
  values_[name] = value;
  return *this;
}
ShaderDefines& ShaderDefines::set(const std::string& name, int value) {
  return set(name, std::to_string(value));
}
ShaderDefines& ShaderDefines::set(const std::string& name, unsigned value) {
  return set(name, std::to_string(value) + "u");
}
ShaderDefines& ShaderDefines::set(const std::string& name, float value) {
  // Round-trip exact, and always a float literal in GLSL.
  return set(name, fmt::format("{:.9g}", value) +
                       (fmt::format("{:.9g}", value).find_first_of(".e") == std::string::npos ? ".0" : ""));
}

std::string ShaderDefines::text() const {
  std::string out;
  for (const auto& [name, value] : values_) out += "#define " + name + " " + value + "\n";
  return out;
}

namespace {

constexpr const char* kVersionLine = "#version 430 core\n";
constexpr const char* kSharedIncludes[] = {"bindings.h", "common.glsl"};

/// Appends `file` with its `#include "x"` lines replaced by the files' text (each file once).
void appendFile(const ShaderTable& stage, const std::string& file, AssembledShader& out,
                std::set<std::string>& included, std::vector<std::string>& stack) {
  if (std::find(stack.begin(), stack.end(), file) != stack.end())
    throw GLError("shader include cycle through \"" + file + "\"");
  if (!included.insert(file).second) return;
  stack.push_back(file);
  out.files.push_back(file);
  const int sourceNumber = int(out.files.size());
  out.text += fmt::format("#line 1 {}\n", sourceNumber);
  std::istringstream in{std::string(shaderSource(stage, file))};
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    const auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line.compare(first, 8, "#include") == 0) {
      const auto open = line.find('"'), close = line.rfind('"');
      if (open == std::string::npos || close <= open)
        throw GLError(fmt::format("{}:{}: malformed #include", file, lineNumber));
      appendFile(stage, line.substr(open + 1, close - open - 1), out, included, stack);
      out.text += fmt::format("#line {} {}\n", lineNumber + 1, sourceNumber);
      continue;
    }
    out.text += line + "\n";
  }
  stack.pop_back();
}

std::string legend(const AssembledShader& s) {
  std::string out = "(source numbers: ";
  for (size_t i = 0; i < s.files.size(); ++i)
    out += fmt::format("{}{} = {}", i ? ", " : "", i + 1, s.files[i]);
  return out + ")";
}

GLuint compileStage(GLenum type, const AssembledShader& src, const std::string& file) {
  GLuint shader = glCreateShader(type);
  const char* text = src.text.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw GLError(fmt::format("{} does not compile {}:\n{}", file, legend(src), log.c_str()));
  }
  return shader;
}

GLuint link(const std::vector<GLuint>& shaders, const std::string& what) {
  GLuint program = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(program, s);
  glLinkProgram(program);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    glDeleteProgram(program);
    throw GLError(fmt::format("{} does not link:\n{}", what, log.c_str()));
  }
  return program;
}

}  // namespace

AssembledShader assembleShader(const ShaderTable& stage, const std::string& stageFile,
                               const ShaderDefines& defines) {
  AssembledShader out;
  out.text = kVersionLine;
  out.text += defines.text();
  std::set<std::string> included;
  std::vector<std::string> stack;
  for (const char* shared : kSharedIncludes) appendFile(gpuShaderTable(), shared, out, included, stack);
  appendFile(stage, stageFile, out, included, stack);
  return out;
}

ShaderProgram::~ShaderProgram() {
  if (id_) glDeleteProgram(id_);
}
ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept : id_(other.id_) {
  other.id_ = 0;
}
ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (id_) glDeleteProgram(id_);
    id_ = other.id_;
    other.id_ = 0;
  }
  return *this;
}

ShaderProgram ShaderProgram::compute(const ShaderTable& stage, const std::string& stageFile,
                                     const ShaderDefines& defines) {
  const AssembledShader src = assembleShader(stage, stageFile, defines);
  return ShaderProgram(link({compileStage(GL_COMPUTE_SHADER, src, stageFile)}, stageFile));
}

ShaderProgram ShaderProgram::graphics(const ShaderTable& stage, const std::string& vertexFile,
                                      const std::string& fragmentFile, const ShaderDefines& defines) {
  const GLuint vs = compileStage(GL_VERTEX_SHADER, assembleShader(stage, vertexFile, defines), vertexFile);
  GLuint fs = 0;
  try {
    fs = compileStage(GL_FRAGMENT_SHADER, assembleShader(stage, fragmentFile, defines), fragmentFile);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  return ShaderProgram(link({vs, fs}, vertexFile + " + " + fragmentFile));
}

void ShaderProgram::use() const {
  glUseProgram(id_);
}

int ShaderProgram::uniform(const char* name) const {
  return glGetUniformLocation(id_, name);
}

std::array<int, 3> ShaderProgram::workGroupSize() const {
  std::array<int, 3> size{};
  glGetProgramiv(id_, GL_COMPUTE_WORK_GROUP_SIZE, size.data());
  return size;
}

void dispatchCompute1D(const ShaderProgram& program, uint32_t count, const char* label) {
  if (count == 0) return;
  const uint32_t local = uint32_t(program.workGroupSize()[0]);
  glDispatchCompute((count + local - 1) / local, 1, 1);
  glCheck(label);
}

}  // namespace sphfx
