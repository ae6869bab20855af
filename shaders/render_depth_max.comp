// One level of a max-depth pyramid for the impostor occlusion cull (render_points_cull.comp): each texel
// holds the farthest window depth of a SPHFX_RENDER_CULL_TILE-pixel square tile of the depth buffer.
#include "render_params.glsl"

layout(local_size_x = 64) in;
layout(binding = SPHFX_TEX_RENDER_SCENE_DEPTH) uniform sampler2D sceneDepth;
layout(binding = SPHFX_IMAGE_RENDER_DEPTH_MAX, r32f) uniform writeonly image2D depthMax;

void main() {
  ivec2 size = imageSize(depthMax);
  int index = int(gl_GlobalInvocationID.x);
  if (index >= size.x * size.y) return;
  ivec2 tile = ivec2(index % size.x, index / size.x);
  ivec2 lo = tile * SPHFX_RENDER_CULL_TILE;
  ivec2 hi = min(lo + SPHFX_RENDER_CULL_TILE, ivec2(renderViewport.xy));
  float farthest = 0.0;
  for (int y = lo.y; y < hi.y; ++y)
    for (int x = lo.x; x < hi.x; ++x) farthest = max(farthest, texelFetch(sceneDepth, ivec2(x, y), 0).r);
  imageStore(depthMax, tile, vec4(farthest));
}
