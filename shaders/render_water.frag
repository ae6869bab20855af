// Water surface: Schlick-Fresnel reflection of the environment, and a refraction-like view of the opaque
// scene behind it (offset along the normal) attenuated by Beer-Lambert absorption over the water
// thickness (nearest surface to the farthest water surface or the opaque scene, whichever is nearer),
// plus the key light's specular highlight.
#include "render_params.glsl"

in vec3 vWorld;
in vec3 vNormal;

layout(binding = SPHFX_TEX_RENDER_BACKGROUND) uniform sampler2D uBackground;
layout(binding = SPHFX_TEX_RENDER_OPAQUE_DEPTH) uniform sampler2D uOpaqueDepth;
layout(binding = SPHFX_TEX_RENDER_BACK_DEPTH) uniform sampler2D uBackDepth;

out vec4 fragColor;

const float kWaterF0 = 0.02;                        // reflectance at normal incidence, n = 1.33
const vec3 kAbsorption = vec3(7.0, 2.2, 1.1);  // 1/m, exaggerated for lab-sized tanks: red goes first
const vec3 kScatter = vec3(0.01, 0.07, 0.12);     // in-scattered colour of deep water
const float kRefractionShift = 0.04;                // screen-space offset per metre of thickness

void main() {
  vec3 n = normalize(vNormal);
  vec3 v = renderOrthographic() ? -renderCamForward.xyz : normalize(renderEye.xyz - vWorld);
  if (dot(n, v) < 0.0) n = -n;  // the nearest surface faces the camera; interpolation can tip it over

  vec2 uv = gl_FragCoord.xy * renderViewport.zw;
  float front = renderLinearDepth(gl_FragCoord.z);
  float opaque = renderLinearDepth(texture(uOpaqueDepth, uv).r);
  float back = texture(uBackDepth, uv).r > 0.0 ? renderLinearDepth(texture(uBackDepth, uv).r) : front;
  float thickness = max(min(back, opaque) - front, 0.0);

  vec3 nView = mat3(renderView) * n;
  vec2 shifted = clamp(uv - nView.xy * kRefractionShift * min(thickness, 1.0), vec2(0.0), vec2(1.0));
  vec3 behind = texture(uBackground, shifted).rgb;
  vec3 transmittance = exp(-kAbsorption * thickness);
  vec3 body = behind * transmittance + kScatter * (1.0 - transmittance);

  float cosine = clamp(dot(n, v), 0.0, 1.0);
  float fresnel = kWaterF0 + (1.0 - kWaterF0) * pow(1.0 - cosine, 5.0);
  vec3 reflected = renderSky(reflect(-v, n));
  vec3 h = normalize(renderLight.xyz + v);
  vec3 specular = vec3(1.0, 0.95, 0.85) * pow(max(dot(n, h), 0.0), 400.0) * 4.0 * renderLight.w;

  fragColor = vec4(mix(body, reflected, fresnel) + specular * fresnel * 8.0, 1.0);
}
