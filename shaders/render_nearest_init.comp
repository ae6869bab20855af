// Initialises the nearest-depth image of the point-sprite passes (render_points.frag) with the depth
// buffer so far (the stage and the quad impostors), as float bits.
#include "render_params.glsl"

layout(local_size_x = 64) in;
layout(binding = SPHFX_TEX_RENDER_SCENE_DEPTH) uniform sampler2D sceneDepth;
layout(binding = SPHFX_IMAGE_RENDER_NEAREST, r32ui) uniform writeonly uimage2D nearestDepth;

void main() {
  int width = int(renderViewport.x);
  int index = int(gl_GlobalInvocationID.x);
  if (index >= width * int(renderViewport.y)) return;
  ivec2 pixel = ivec2(index % width, index / width);
  imageStore(nearestDepth, pixel, uvec4(floatBitsToUint(texelFetch(sceneDepth, pixel, 0).r)));
}
