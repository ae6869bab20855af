// Sphere impostors on point sprites, with early depth tests although the true depth is per pixel.
// A fragment shader that writes gl_FragDepth gets its depth test after shading (llvmpipe ignores
// conservative depth), so every covered pixel of every sphere would be shaded. Instead, three passes over
// the same points, each with the GL's early depth test on the point's flat rasterised depth:
//  SPHFX_IMPOSTOR_OCCLUDE: rasterised at the sphere's farthest depth (never nearer than any of its pixels),
//    written where the pixel's ray hits it: an upper bound of the nearest surface per pixel.
//  SPHFX_IMPOSTOR_NEAREST: rasterised at the sphere's nearest depth (never farther than any of its pixels),
//    tested against that bound without writing, so only spheres that may be in front survive; they
//    imageAtomicMin their true window depth into the nearest-depth image (initialised to the scene's
//    depth: stage and quad impostors).
//  SPHFX_IMPOSTOR_SHADE: the same test; the sphere whose true depth is the pixel's nearest shades it.
// Front-to-back order (splitImpostors sorts) lets the occluder pass reject most hidden pixels too.
#include "render_params.glsl"
#include "render_impostor.glsl"

#if SPHFX_IMPOSTOR_PASS != SPHFX_IMPOSTOR_OCCLUDE
layout(early_fragment_tests) in;
layout(binding = SPHFX_IMAGE_RENDER_NEAREST, r32ui) uniform coherent uimage2D nearestDepth;
#endif

flat in vec3 vCenter;
flat in float vScalar;

out vec4 fragColor;

void main() {
  vec3 dir = renderRayDirection(gl_FragCoord.xy);
  vec3 hit;
  if (!impostorHit(impostorRayOrigin(gl_FragCoord.xy), dir, vCenter, 0.0, hit)) discard;
#if SPHFX_IMPOSTOR_PASS == SPHFX_IMPOSTOR_OCCLUDE
  fragColor = vec4(0.0);  // colour writes are masked off
#else
  uint depthBits = floatBitsToUint(impostorDepth(hit));  // depths in [0, 1]: bits order as values
  ivec2 pixel = ivec2(gl_FragCoord.xy);
#if SPHFX_IMPOSTOR_PASS == SPHFX_IMPOSTOR_NEAREST
  imageAtomicMin(nearestDepth, pixel, depthBits);
  fragColor = vec4(0.0);
#else
  // Equal bits, give or take a few ulps should a compiler round the two programs differently.
  if (abs(int(depthBits - imageLoad(nearestDepth, pixel).r)) > 4) discard;
  fragColor = impostorColour(hit, dir, vCenter, vScalar);
#endif
#endif
}
