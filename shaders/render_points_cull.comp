// Occlusion cull of point-sprite impostors after the occluder pass (render_points.frag): a sphere whose
// nearest depth is no nearer than the farthest depth over every tile its silhouette box touches is hidden
// there (that depth bounds the true nearest surface from above). The others are appended to the visible
// list and counted into the indirect draw command of the later passes.
#include "render_params.glsl"
#include "render_points.glsl"

layout(local_size_x = 64) in;
layout(binding = SPHFX_IMAGE_RENDER_DEPTH_MAX, r32f) uniform readonly image2D depthMax;

layout(std430, binding = SPHFX_SSBO_RENDER_VISIBLE) writeonly buffer RenderVisible {
  vec4 renderVisible[];
};
// glDrawArraysIndirect's command: count, instance count, first, base instance.
layout(std430, binding = SPHFX_SSBO_RENDER_DRAW) buffer RenderDraw {
  uint renderDrawCount;
  uint renderDrawInstances;
  uint renderDrawFirst;
  uint renderDrawBaseInstance;
};

uniform uint uCount;

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= uCount) return;
  vec4 p = renderParticles[index];
  PointSprite s = pointSprite(p.xyz);
  float nearest = pointNdcDepth(s.viewDepth - renderCamForward.w) * 0.5 + 0.5;
  // Pixels whose centres the box (grown like the point square) may cover, then their tiles.
  ivec2 size = imageSize(depthMax);
  vec2 lo = (s.lo * 0.5 + 0.5) * renderViewport.xy - 1.0, hi = (s.hi * 0.5 + 0.5) * renderViewport.xy + 1.0;
  ivec2 tlo = clamp(ivec2(floor(lo)) / SPHFX_RENDER_CULL_TILE, ivec2(0), size - 1);
  ivec2 thi = clamp(ivec2(floor(hi)) / SPHFX_RENDER_CULL_TILE, ivec2(0), size - 1);
  float farthest = 0.0;
  for (int y = tlo.y; y <= thi.y; ++y)
    for (int x = tlo.x; x <= thi.x; ++x) farthest = max(farthest, imageLoad(depthMax, ivec2(x, y)).r);
  if (nearest >= farthest) return;
  renderVisible[atomicAdd(renderDrawCount, 1u)] = p;
}
