// Particles as point sprites, one vertex per particle (the fast path; render_particles.vert is the
// fallback). The point square is centred on the screen-space bounding box of the sphere's exact
// perspective silhouette and covers it; render_points.frag casts each pixel's camera ray at the sphere.
// The CPU (splitImpostors in renderer.cpp, the same maths in double precision) sends here only spheres
// wholly in front of the near plane whose box centre is on screen (GL clips a point by its centre) and
// whose square fits GL_POINT_SIZE_RANGE. Drawn in passes (SPHFX_IMPOSTOR_PASS, see render_points.frag):
// the rasterised depth is the sphere's farthest view depth in the occluder pass, its nearest otherwise.
#include "render_params.glsl"
#include "render_points.glsl"

flat out vec3 vCenter;
flat out float vScalar;

void main() {
  vec4 p = renderParticles[gl_VertexID];
  vCenter = p.xyz;
  vScalar = p.w;
  PointSprite s = pointSprite(p.xyz);
  // Pixels whose centre lies in the box are inside the square; half a pixel more absorbs rounding.
  vec2 sizePixels = (s.hi - s.lo) * 0.5 * renderViewport.xy;
  gl_PointSize = max(sizePixels.x, sizePixels.y) + 0.5;
#if SPHFX_IMPOSTOR_PASS == SPHFX_IMPOSTOR_OCCLUDE
  float depth = s.viewDepth + renderCamForward.w;
#else
  float depth = s.viewDepth - renderCamForward.w;
#endif
  gl_Position = vec4(0.5 * (s.lo + s.hi), pointNdcDepth(depth), 1.0);
}
