#include "gpu_layouts.h"

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
               SPHFX_GPU_MEMBER(P, domainMax, "renderDomainMax"),
               SPHFX_GPU_MEMBER(P, projection, "renderProjection")}},
          // A runtime-sized array: the block's data size is the stride, not sizeof a C++ struct.
          GpuBlockLayout{"RenderParticles",
                         false,
                         SPHFX_SSBO_RENDER_PARTICLES,
                         sizeof(RenderParticle),
                         "render_particles.vert+render_particles.frag",
                         {{"renderParticles[0]", 0, sizeof(RenderParticle)}}},
          // The point-sprite path reads the same block (and the same RenderParams).
          GpuBlockLayout{"RenderParticles",
                         false,
                         SPHFX_SSBO_RENDER_PARTICLES,
                         sizeof(RenderParticle),
                         "render_points.vert+render_points.frag",
                         {{"renderParticles[0]", 0, sizeof(RenderParticle)}}},
          GpuBlockLayout{"RenderVisible",
                         false,
                         SPHFX_SSBO_RENDER_VISIBLE,
                         sizeof(RenderParticle),
                         "render_points_cull.comp",
                         {{"renderVisible[0]", 0, sizeof(RenderParticle)}}},
          GpuBlockLayout{"RenderDraw",
                         false,
                         SPHFX_SSBO_RENDER_DRAW,
                         4 * sizeof(uint32_t),
                         "render_points_cull.comp",
                         {{"renderDrawCount", 0, sizeof(uint32_t)},
                          {"renderDrawInstances", 4, sizeof(uint32_t)},
                          {"renderDrawFirst", 8, sizeof(uint32_t)},
                          {"renderDrawBaseInstance", 12, sizeof(uint32_t)}}}};
}

}  // namespace sphfx::render
