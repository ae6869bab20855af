// Sphere impostor: discard outside the unit circle, intersect the camera ray with the sphere for the
// normal and the true depth (gl_FragDepth), shade with the ramp colour.
#include "render_params.glsl"

in vec2 vQuad;
in vec3 vWorld;
flat in vec3 vCenter;
flat in float vScalar;

out vec4 fragColor;

// Height: dark navy at the bottom of the domain to bright blue at the top (the seed's look).
// Speed: deep blue at rest, through cyan, to white at the speed scale.
vec3 rampColour(float height, float speed) {
  if (renderRamp.w < 0.5) {
    float t = clamp((height - renderRamp.x) / max(renderRamp.y - renderRamp.x, 1e-6), 0.0, 1.0);
    return mix(vec3(0.004, 0.008, 0.04), vec3(0.08, 0.32, 1.0), t);
  }
  float t = clamp(speed / max(renderRamp.z, 1e-6), 0.0, 1.0);
  return t < 0.5 ? mix(vec3(0.01, 0.04, 0.3), vec3(0.05, 0.6, 0.9), t * 2.0)
                 : mix(vec3(0.05, 0.6, 0.9), vec3(1.0), t * 2.0 - 1.0);
}

void main() {
  if (dot(vQuad, vQuad) > 1.0) discard;
  float r = renderCamForward.w;
  vec3 dir = renderOrthographic() ? renderCamForward.xyz : normalize(vWorld - renderEye.xyz);
  vec3 origin = renderOrthographic() ? vWorld - dir * (2.0 * r) : renderEye.xyz;
  vec3 oc = origin - vCenter;
  float b = dot(oc, dir);
  float h = max(b * b - (dot(oc, oc) - r * r), 0.0);  // >= 0 inside the circle up to rounding
  vec3 hit = origin + (-b - sqrt(h)) * dir;
  vec3 n = (hit - vCenter) / r;
  gl_FragDepth = renderWindowDepth(hit);

  vec3 albedo = rampColour(vCenter.y, vScalar);
  vec3 halfway = normalize(renderLight.xyz - dir);
  float spec = pow(max(dot(n, halfway), 0.0), 40.0) * 0.25 * renderLight.w;
  fragColor = vec4(renderDiffuse(albedo, n) + spec, 1.0);
}
