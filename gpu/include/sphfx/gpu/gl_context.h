#pragma once
/// @file gl_context.h
/// @brief Headless OpenGL 4.3+ core contexts: EGL device platform (GPUs, render nodes), EGL surfaceless
/// (Mesa llvmpipe on machines without a GPU), OSMesa (legacy fallback, loaded at run time).

#include <memory>
#include <string>
#include <vector>

namespace sphfx {

enum class GLBackend { Auto, EglDevice, EglSurfaceless, OSMesa };

/// "auto", "egl-device", "egl-surfaceless", "osmesa".
std::string toString(GLBackend backend);
/// Parses a backend name. @throws InputError for an unknown name (lists the valid ones).
GLBackend parseGLBackend(const std::string& name);
/// The valid names, for CLI help and checks.
std::vector<std::string> glBackendNames();

/// One backend that was tried and what happened.
struct GLAttempt {
  GLBackend backend;
  bool succeeded = false;
  std::string detail;  ///< why it failed, or the device it picked
};

/// What the chosen context is and can do.
struct GLInfo {
  std::string vendor, renderer, version, glslVersion;
  int major = 0, minor = 0;
  int maxComputeWorkGroupInvocations = 0;
  int maxComputeWorkGroupSize[3] = {0, 0, 0};
  int maxComputeWorkGroupCount[3] = {0, 0, 0};
  int maxComputeSharedMemory = 0;
  int maxShaderStorageBlockSize = 0;
  int maxShaderStorageBindings = 0;
  int maxTextureSize = 0;
  int maxSamples = 0;
  bool softwareRenderer() const;  ///< llvmpipe / softpipe / swrast
};

/// Whether a GL_RENDERER string names a CPU rasteriser (llvmpipe, softpipe, swrast, SwiftShader).
bool isSoftwareRenderer(const std::string& renderer);

struct GLContextOptions {
  GLBackend backend = GLBackend::Auto;
  /// Enables KHR_debug messages and a glGetError check after every dispatch and draw (slow).
  bool debug = false;
};

/// An OpenGL context made current on the calling thread for the object's lifetime. GL functions are
/// loaded (glad) when it is created. One context per process at a time.
class GLContext {
 public:
  /// Tries the backends in order (Auto: EGL device, EGL surfaceless, OSMesa) or the one forced.
  /// @throws GLError listing every backend tried and why it failed, if none gives GL >= 4.3 core.
  static std::unique_ptr<GLContext> create(const GLContextOptions& options = {});
  virtual ~GLContext();

  GLBackend backend() const { return backend_; }
  const std::vector<GLAttempt>& attempts() const { return attempts_; }
  const GLInfo& info() const { return info_; }
  bool debug() const { return debug_; }

 protected:
  GLContext() = default;

 private:
  void finishSetup(GLBackend backend, std::vector<GLAttempt> attempts, bool debug);

  GLBackend backend_ = GLBackend::Auto;
  std::vector<GLAttempt> attempts_;
  GLInfo info_;
  bool debug_ = false;
};

/// Whether debug checks are on for the current context (set by GLContext::create).
bool glDebugChecksEnabled();
/// With debug checks on: throws GLError naming `where` if glGetError reports an error. Otherwise free.
void glCheck(const char* where);

}  // namespace sphfx
