// Sphere impostor on a camera-facing quad (the fallback path, see render_particles.vert): discard outside
// the unit circle, then the shared ray-sphere hit, depth and shading.
#include "render_params.glsl"
#include "render_impostor.glsl"

in vec2 vQuad;
in vec3 vWorld;
flat in vec3 vCenter;
flat in float vScalar;

out vec4 fragColor;

void main() {
  if (dot(vQuad, vQuad) > 1.0) discard;
  float r = renderCamForward.w;
  vec3 dir = renderOrthographic() ? renderCamForward.xyz : normalize(vWorld - renderEye.xyz);
  vec3 origin = renderOrthographic() ? vWorld - dir * (2.0 * r) : renderEye.xyz;
  vec3 hit;
  impostorHit(origin, dir, vCenter, 1e30, hit);
  gl_FragDepth = impostorDepth(hit);
  fragColor = impostorColour(hit, dir, vCenter, vScalar);
}
