// Particles as sphere impostors, pulled from an SSBO by gl_VertexID (4 vertices per particle, indexed as
// two triangles): no vertex attributes, no instancing (which llvmpipe runs one instance at a time).
// Perspective: the quad faces the eye through the sphere centre and is sized to the tangent cone, so
// that the unit circle in quad coordinates is exactly the sphere's silhouette.
#include "render_params.glsl"

layout(std430, binding = SPHFX_SSBO_RENDER_PARTICLES) readonly buffer RenderParticles {
  vec4 renderParticles[];  // xyz position, w colour scalar (speed)
};

out vec2 vQuad;
out vec3 vWorld;
flat out vec3 vCenter;
flat out float vScalar;

void main() {
  vec4 p = renderParticles[gl_VertexID >> 2];
  int corner = gl_VertexID & 3;
  vQuad = vec2(float(corner & 1) * 2.0 - 1.0, float(corner >> 1) * 2.0 - 1.0);
  vCenter = p.xyz;
  vScalar = p.w;
  float r = renderCamForward.w;
  vec3 right = renderCamRight.xyz, up = renderCamUp.xyz;
  float extent = r;
  if (!renderOrthographic()) {
    vec3 toEye = renderEye.xyz - p.xyz;
    float d = length(toEye);
    if (d <= r * 1.0001) {  // the camera is inside this sphere: drop it (clipped away)
      gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
      return;
    }
    vec3 w = toEye / d;
    right = normalize(cross(renderCamUp.xyz, w));
    up = cross(w, right);
    extent = r * d / sqrt(d * d - r * r);
  }
  vWorld = p.xyz + extent * (vQuad.x * right + vQuad.y * up);
  gl_Position = renderViewProj * vec4(vWorld, 1.0);
}
