#include <cstdlib>

#include "gpu_layout_check.h"
#include "sphfx/gpu/gl_context.h"

TEST(GpuLayout, CoreBlocksMatchGlsl) {
  const char* name = std::getenv("SPHFX_GL");
  auto ctx = sphfx::GLContext::create({sphfx::parseGLBackend(name ? name : "auto"), false});
  sphfx::test::checkGpuLayouts(sphfx::gpuShaderTable(), sphfx::coreGpuLayouts());
}
