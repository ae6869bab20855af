// Opaque solids: colliders, the ground (with a faint checker for scale) and the tank walls.
#include "render_params.glsl"

in vec3 vWorld;
in vec3 vNormal;

uniform vec3 uAlbedo;
uniform int uPattern;  // 0 plain, 1 checker of uCheckerSize metres on the xz plane
uniform float uCheckerSize;

out vec4 fragColor;

void main() {
  vec3 n = normalize(vNormal);
  vec3 v = renderOrthographic() ? -renderCamForward.xyz : normalize(renderEye.xyz - vWorld);
  if (dot(n, v) < 0.0) n = -n;  // two-sided lighting: the inside of a wall is lit like its outside
  vec3 albedo = uAlbedo;
  if (uPattern == 1) {
    ivec2 cell = ivec2(floor(vWorld.xz / uCheckerSize));
    albedo *= ((cell.x + cell.y) & 1) == 0 ? 1.0 : 0.82;
  }
  vec3 h = normalize(renderLight.xyz + v);
  float spec = pow(max(dot(n, h), 0.0), 60.0) * 0.08 * renderLight.w;
  fragColor = vec4(renderDiffuse(albedo, n) + spec, 1.0);
}
