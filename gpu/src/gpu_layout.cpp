#include "sphfx/gpu/gpu_layout.h"

namespace sphfx {

std::vector<GpuBlockLayout> coreGpuLayouts() {
  return {GpuBlockLayout{"SelfTestParams",
                         true,
                         SPHFX_UBO_SELFTEST,
                         sizeof(SelfTestParams),
                         "selftest.comp",
                         {SPHFX_GPU_MEMBER(SelfTestParams, scale, "selftestScale"),
                          SPHFX_GPU_MEMBER(SelfTestParams, count, "selftestCount"),
                          SPHFX_GPU_MEMBER(SelfTestParams, offset, "selftestOffset")}}};
}

}  // namespace sphfx
