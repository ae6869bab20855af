// The render stage's per-frame uniform block and the shading helpers every render program shares.
// C++ mirror: sphfx::render::RenderParams (render/include/sphfx/render/gpu_layouts.h).

layout(std140, binding = SPHFX_UBO_RENDER_PARAMS) uniform RenderParams {
  mat4 renderViewProj;
  mat4 renderView;
  mat4 renderInvViewProj;
  vec4 renderEye;         // xyz camera position; w: 1 orthographic, 0 perspective
  vec4 renderCamRight;    // xyz; w: near plane
  vec4 renderCamUp;       // xyz; w: far plane
  vec4 renderCamForward;  // xyz (the direction the camera looks); w: particle radius
  vec4 renderLight;       // xyz unit vector toward the key light; w: its intensity
  vec4 renderViewport;    // width, height, 1/width, 1/height
  vec4 renderRamp;        // height min, height max, speed scale, mode (0 height, 1 speed)
  vec4 renderDomainMin;
  vec4 renderDomainMax;
  vec4 renderProjection;  // projection matrix entries [0][0], [1][1], [2][2], [3][2] (column-major)
};

bool renderOrthographic() { return renderEye.w > 0.5; }

// View-axis distance (m) of a window-space depth value in [0, 1].
float renderLinearDepth(float windowDepth) {
  float n = renderCamRight.w, f = renderCamUp.w;
  if (renderOrthographic()) return n + windowDepth * (f - n);
  float ndc = windowDepth * 2.0 - 1.0;
  return 2.0 * f * n / ((f + n) - ndc * (f - n));
}

// Window-space depth of a world-space point, as the fixed-function pipeline would compute it.
float renderWindowDepth(vec3 world) {
  vec4 clip = renderViewProj * vec4(world, 1.0);
  return clamp(clip.z / clip.w * 0.5 + 0.5, 0.0, 1.0);
}

// Direction of the camera ray through a window position (pixel units).
vec3 renderRayDirection(vec2 fragCoord) {
  if (renderOrthographic()) return renderCamForward.xyz;
  vec2 ndc = fragCoord * renderViewport.zw * 2.0 - 1.0;
  vec4 far = renderInvViewProj * vec4(ndc, 1.0, 1.0);
  return normalize(far.xyz / far.w - renderEye.xyz);
}

// A simple procedural environment: zenith blue to a pale horizon, a dull ground below the horizon, and
// a sun disc with a soft glow in the key light's direction. Linear radiance.
vec3 renderSky(vec3 d) {
  const vec3 zenith = vec3(0.10, 0.26, 0.62);
  const vec3 horizon = vec3(0.62, 0.72, 0.84);
  const vec3 ground = vec3(0.16, 0.15, 0.14);
  vec3 c = d.y >= 0.0 ? mix(horizon, zenith, pow(d.y, 0.6)) : mix(horizon, ground, pow(-d.y, 0.35));
  float s = max(dot(d, renderLight.xyz), 0.0);
  c += vec3(1.0, 0.9, 0.75) * (pow(s, 1500.0) * 30.0 + pow(s, 12.0) * 0.25);
  return c;
}

// Diffuse lighting of a surface with normal n: key light plus a sky/ground hemisphere ambient.
vec3 renderDiffuse(vec3 albedo, vec3 n) {
  float key = max(dot(n, renderLight.xyz), 0.0) * renderLight.w;
  vec3 ambient = mix(vec3(0.10, 0.09, 0.08), vec3(0.30, 0.36, 0.45), n.y * 0.5 + 0.5);
  return albedo * (key * vec3(1.0, 0.95, 0.88) + ambient);
}
