#include "sphfx/gpu/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/gpu/gl.h"

namespace sphfx {
namespace {

bool gDebugChecks = false;
constexpr int kMinMajor = 4, kMinMinor = 3;

std::string eglErrorText(EGLint code) {
  switch (code) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return fmt::format("EGL error 0x{:x}", code);
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

void GLAD_API_PTR debugCallback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message,
                                const void*) {
  if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return logVerbose(std::string("GL: ") + message);
  if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
    return logWarning(std::string("GL debug: ") + message);
  logVerbose(std::string("GL debug: ") + message);
}

/// Fails with a reason unless the current context is GL >= 4.3 core.
std::string checkVersion() {
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < kMinMajor * 10 + kMinMinor)
    return fmt::format("GL {}.{} is below the 4.3 needed for compute shaders", major, minor);
  return {};
}

// ---------------------------------------------------------------------------------------------- EGL

class EglContext final : public GLContext {
 public:
  ~EglContext() override {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }

  /// Initializes `display`, creates a core context and makes it current without a surface.
  /// Returns an empty string on success, else why it failed.
  std::string open(EGLDisplay display, bool debug) {
    display_ = display;
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display_, &major, &minor)) {
      const std::string why = "eglInitialize failed: " + eglErrorText(eglGetError());
      display_ = EGL_NO_DISPLAY;
      return why;
    }
    const char* ext = eglQueryString(display_, EGL_EXTENSIONS);
    if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) return "display lacks EGL_KHR_surfaceless_context";
    if (!eglBindAPI(EGL_OPENGL_API))
      return "eglBindAPI(EGL_OPENGL_API) failed: " + eglErrorText(eglGetError());

    EGLConfig config = nullptr;
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display_, configAttribs, &config, 1, &count) || count == 0) {
      if (!hasExtension(ext, "EGL_KHR_no_config_context")) return "no EGL config renders OpenGL";
      config = EGL_NO_CONFIG_KHR;  // surfaceless contexts need no config where this extension exists
    }
    // Ask for the newest version first; drivers may refuse a version they do not have.
    for (const auto& [maj, min] : {std::pair{4, 6}, std::pair{4, 5}, std::pair{4, 3}}) {
      const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                       maj,
                                       EGL_CONTEXT_MINOR_VERSION,
                                       min,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_CONTEXT_OPENGL_DEBUG,
                                       debug ? EGL_TRUE : EGL_FALSE,
                                       EGL_NONE};
      context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, contextAttribs);
      if (context_ != EGL_NO_CONTEXT) break;
    }
    if (context_ == EGL_NO_CONTEXT) return "no OpenGL >= 4.3 core context: " + eglErrorText(eglGetError());
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      return "eglMakeCurrent failed: " + eglErrorText(eglGetError());
    if (!gladLoadGL(reinterpret_cast<GLADloadfunc>(eglGetProcAddress)))
      return "glad could not load GL functions";
    return checkVersion();
  }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

/// The EGL device platform: enumerates devices and takes the first hardware one. Mesa also lists a
/// software device (EGL_MESA_device_software); that is the surfaceless backend's job, so it is skipped.
std::unique_ptr<EglContext> tryEglDevice(bool debug, std::string& why) {
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  // EGL_EXT_device_base is enumeration and query in one name; NVIDIA's driver behind glvnd lists only it.
  if (!hasExtension(clientExt, "EGL_EXT_platform_device") ||
      !(hasExtension(clientExt, "EGL_EXT_device_enumeration") ||
        hasExtension(clientExt, "EGL_EXT_device_base"))) {
    why =
        fmt::format("EGL lacks EGL_EXT_platform_device / EGL_EXT_device_enumeration (client extensions: {})",
                    clientExt ? clientExt : "none");
    return nullptr;
  }
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto queryDeviceString =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!queryDevices || !queryDeviceString || !getPlatformDisplay) {
    why = "EGL device functions not found";
    return nullptr;
  }
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!queryDevices(16, devices, &count) || count == 0) {
    why = "no EGL device";
    return nullptr;
  }
  std::vector<std::string> reasons;
  for (EGLint i = 0; i < count; ++i) {
    const char* devExt = queryDeviceString(devices[i], EGL_EXTENSIONS);
    if (hasExtension(devExt, "EGL_MESA_device_software")) {
      reasons.push_back(fmt::format("device {}: software (skipped)", i));
      continue;
    }
    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    if (display == EGL_NO_DISPLAY) {
      reasons.push_back(fmt::format("device {}: no display", i));
      continue;
    }
    auto ctx = std::make_unique<EglContext>();
    const std::string err = ctx->open(display, debug);
    if (err.empty()) {
      why = fmt::format("device {} of {}", i, count);
      return ctx;
    }
    reasons.push_back(fmt::format("device {}: {}", i, err));
  }
  why.clear();
  for (const auto& r : reasons) why += (why.empty() ? "" : "; ") + r;
  return nullptr;
}

std::unique_ptr<EglContext> tryEglSurfaceless(bool debug, std::string& why) {
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(clientExt, "EGL_MESA_platform_surfaceless")) {
    why = "EGL lacks EGL_MESA_platform_surfaceless (Mesa's EGL is not installed)";
    return nullptr;
  }
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  EGLDisplay display = getPlatformDisplay
                           ? getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)
                           : EGL_NO_DISPLAY;
  if (display == EGL_NO_DISPLAY) {
    why = "no surfaceless display: " + eglErrorText(eglGetError());
    return nullptr;
  }
  auto ctx = std::make_unique<EglContext>();
  why = ctx->open(display, debug);
  return why.empty() ? std::move(ctx) : nullptr;
}

// ------------------------------------------------------------------------------------------- OSMesa

// OSMesa's API, declared here because the library is opened at run time: the binary must start on
// systems whose Mesa (25.1+) no longer ships it.
using OSMesaContextHandle = void*;
constexpr int kOsmesaFormat = 0x22, kOsmesaRgba = 0x1908, kOsmesaDepthBits = 0x30, kOsmesaProfile = 0x33,
              kOsmesaCoreProfile = 0x34, kOsmesaMajor = 0x36, kOsmesaMinor = 0x37;
using OSMesaCreateContextAttribsFn = OSMesaContextHandle (*)(const int*, OSMesaContextHandle);
using OSMesaMakeCurrentFn = unsigned char (*)(OSMesaContextHandle, void*, unsigned, int, int);
using OSMesaDestroyContextFn = void (*)(OSMesaContextHandle);
using OSMesaGetProcAddressFn = GLADapiproc (*)(const char*);

OSMesaGetProcAddressFn gOsmesaGetProcAddress = nullptr;
GLADapiproc osmesaLoad(const char* name) {
  return gOsmesaGetProcAddress(name);
}

class OSMesaContext final : public GLContext {
 public:
  ~OSMesaContext() override {
    if (context_) destroy_(context_);
    // The library stays loaded: Mesa does not support being unloaded and reloaded in one process.
  }

  std::string open() {
    for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"})
      if ((library_ = dlopen(name, RTLD_NOW | RTLD_LOCAL)) != nullptr) break;
    if (!library_) return "libOSMesa not found (Debian: libosmesa6; removed from Mesa 25.1)";
    auto create =
        reinterpret_cast<OSMesaCreateContextAttribsFn>(dlsym(library_, "OSMesaCreateContextAttribs"));
    auto makeCurrent = reinterpret_cast<OSMesaMakeCurrentFn>(dlsym(library_, "OSMesaMakeCurrent"));
    destroy_ = reinterpret_cast<OSMesaDestroyContextFn>(dlsym(library_, "OSMesaDestroyContext"));
    gOsmesaGetProcAddress = reinterpret_cast<OSMesaGetProcAddressFn>(dlsym(library_, "OSMesaGetProcAddress"));
    if (!create || !makeCurrent || !destroy_ || !gOsmesaGetProcAddress)
      return "libOSMesa lacks OSMesaCreateContextAttribs (too old)";
    for (const auto& [maj, min] : {std::pair{4, 5}, std::pair{4, 3}}) {
      const int attribs[] = {kOsmesaFormat,
                             kOsmesaRgba,
                             kOsmesaDepthBits,
                             24,
                             kOsmesaProfile,
                             kOsmesaCoreProfile,
                             kOsmesaMajor,
                             maj,
                             kOsmesaMinor,
                             min,
                             0};
      context_ = create(attribs, nullptr);
      if (context_) break;
    }
    if (!context_) return "OSMesaCreateContextAttribs gave no core context >= 4.3";
    // A 1x1 colour buffer: all real rendering goes to framebuffer objects.
    if (!makeCurrent(context_, pixel_, 0x1401 /*GL_UNSIGNED_BYTE*/, 1, 1)) return "OSMesaMakeCurrent failed";
    if (!gladLoadGL(osmesaLoad)) return "glad could not load GL functions";
    return checkVersion();
  }

 private:
  void* library_ = nullptr;
  OSMesaContextHandle context_ = nullptr;
  OSMesaDestroyContextFn destroy_ = nullptr;
  unsigned char pixel_[4] = {};
};

std::unique_ptr<GLContext> tryBackend(GLBackend backend, bool debug, std::string& why) {
  switch (backend) {
    case GLBackend::EglDevice:
      return tryEglDevice(debug, why);
    case GLBackend::EglSurfaceless:
      return tryEglSurfaceless(debug, why);
    case GLBackend::OSMesa: {
      auto ctx = std::make_unique<OSMesaContext>();
      why = ctx->open();
      return why.empty() ? std::move(ctx) : nullptr;
    }
    case GLBackend::Auto:
      break;
  }
  why = "not a backend";
  return nullptr;
}

GLInfo queryInfo() {
  GLInfo info;
  auto str = [](GLenum e) {
    const auto* s = reinterpret_cast<const char*>(glGetString(e));
    return std::string(s ? s : "");
  };
  info.vendor = str(GL_VENDOR);
  info.renderer = str(GL_RENDERER);
  info.version = str(GL_VERSION);
  info.glslVersion = str(GL_SHADING_LANGUAGE_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &info.major);
  glGetIntegerv(GL_MINOR_VERSION, &info.minor);
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &info.maxComputeWorkGroupInvocations);
  for (GLuint i = 0; i < 3; ++i) {
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, i, &info.maxComputeWorkGroupSize[i]);
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, i, &info.maxComputeWorkGroupCount[i]);
  }
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &info.maxComputeSharedMemory);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &info.maxShaderStorageBlockSize);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &info.maxShaderStorageBindings);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &info.maxTextureSize);
  glGetIntegerv(GL_MAX_SAMPLES, &info.maxSamples);
  return info;
}

}  // namespace

std::string toString(GLBackend backend) {
  switch (backend) {
    case GLBackend::Auto:
      return "auto";
    case GLBackend::EglDevice:
      return "egl-device";
    case GLBackend::EglSurfaceless:
      return "egl-surfaceless";
    case GLBackend::OSMesa:
      return "osmesa";
  }
  return "?";
}

std::vector<std::string> glBackendNames() {
  return {"auto", "egl-device", "egl-surfaceless", "osmesa"};
}

GLBackend parseGLBackend(const std::string& name) {
  for (GLBackend b : {GLBackend::Auto, GLBackend::EglDevice, GLBackend::EglSurfaceless, GLBackend::OSMesa})
    if (toString(b) == name) return b;
  throw InputError("--gl: expected one of auto, egl-device, egl-surfaceless, osmesa, got \"" + name + "\"");
}

bool isSoftwareRenderer(const std::string& renderer) {
  for (const char* s : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
    if (renderer.find(s) != std::string::npos) return true;
  return false;
}

bool GLInfo::softwareRenderer() const {
  return isSoftwareRenderer(renderer);
}

std::unique_ptr<GLContext> GLContext::create(const GLContextOptions& options) {
  const std::vector<GLBackend> order =
      options.backend == GLBackend::Auto
          ? std::vector<GLBackend>{GLBackend::EglDevice, GLBackend::EglSurfaceless, GLBackend::OSMesa}
          : std::vector<GLBackend>{options.backend};
  std::vector<GLAttempt> attempts;
  for (GLBackend b : order) {
    std::string why;
    std::unique_ptr<GLContext> ctx = tryBackend(b, options.debug, why);
    attempts.push_back({b, ctx != nullptr, why});
    if (ctx) {
      ctx->finishSetup(b, std::move(attempts), options.debug);
      return ctx;
    }
  }
  std::string message = "no OpenGL >= 4.3 core context could be created:";
  for (const auto& a : attempts) message += "\n  " + toString(a.backend) + ": " + a.detail;
  throw GLError(message);
}

GLContext::~GLContext() {
  gDebugChecks = false;
}

void GLContext::finishSetup(GLBackend backend, std::vector<GLAttempt> attempts, bool debug) {
  backend_ = backend;
  attempts_ = std::move(attempts);
  debug_ = debug;
  gDebugChecks = debug;
  info_ = queryInfo();
  if (debug) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
  }
}

bool glDebugChecksEnabled() {
  return gDebugChecks;
}

void glCheck(const char* where) {
  if (!gDebugChecks) return;
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR) throw GLError(fmt::format("GL error 0x{:04x} after {}", err, where));
}

}  // namespace sphfx
