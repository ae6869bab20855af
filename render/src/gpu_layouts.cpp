#include "sphfx/render/gpu_layouts.h"

namespace sphfx::render {

std::vector<GpuBlockLayout> renderGpuLayouts() {
  using P = RenderParams;
  return {GpuBlockLayout{
              "RenderParams",
              true,
              SPHFX_UBO_RENDER_PARAMS,
              sizeof(P),
              "render_particles.vert+render_particles.frag",
              {SPHFX_GPU_MEMBER(P, viewProj, "renderViewProj"), SPHFX_GPU_MEMBER(P, view, "renderView"),
               SPHFX_GPU_MEMBER(P, invViewProj, "renderInvViewProj"), SPHFX_GPU_MEMBER(P, eye, "renderEye"),
               SPHFX_GPU_MEMBER(P, camRight, "renderCamRight"), SPHFX_GPU_MEMBER(P, camUp, "renderCamUp"),
               SPHFX_GPU_MEMBER(P, camForward, "renderCamForward"), SPHFX_GPU_MEMBER(P, light, "renderLight"),
               SPHFX_GPU_MEMBER(P, viewport, "renderViewport"), SPHFX_GPU_MEMBER(P, ramp, "renderRamp"),
               SPHFX_GPU_MEMBER(P, domainMin, "renderDomainMin"),
               SPHFX_GPU_MEMBER(P, domainMax, "renderDomainMax")}},
          // A runtime-sized array: the block's data size is the stride, not sizeof a C++ struct.
          GpuBlockLayout{"RenderParticles",
                         false,
                         SPHFX_SSBO_RENDER_PARTICLES,
                         sizeof(RenderParticle),
                         "render_particles.vert+render_particles.frag",
                         {{"renderParticles[0]", 0, sizeof(RenderParticle)}}}};
}

}  // namespace sphfx::render
