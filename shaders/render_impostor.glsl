// Sphere impostors shared by the two particle paths (render_particles.* quads, render_points.* point
// sprites): the colour ramp, the camera ray through a pixel, the ray-sphere hit with its true depth, and
// the shading. Needs render_params.glsl first.

// Height: dark navy at the bottom of the domain to bright blue at the top.
// Speed: deep blue at rest, through cyan, to white at the speed scale.
vec3 impostorRamp(float height, float speed) {
  if (renderRamp.w < 0.5) {
    float t = clamp((height - renderRamp.x) / max(renderRamp.y - renderRamp.x, 1e-6), 0.0, 1.0);
    return mix(vec3(0.004, 0.008, 0.04), vec3(0.08, 0.32, 1.0), t);
  }
  float t = clamp(speed / max(renderRamp.z, 1e-6), 0.0, 1.0);
  return t < 0.5 ? mix(vec3(0.01, 0.04, 0.3), vec3(0.05, 0.6, 0.9), t * 2.0)
                 : mix(vec3(0.05, 0.6, 0.9), vec3(1.0), t * 2.0 - 1.0);
}

// Origin of the camera ray through a window position: the eye, or for an orthographic camera the point
// of the near plane under the pixel.
vec3 impostorRayOrigin(vec2 fragCoord) {
  if (!renderOrthographic()) return renderEye.xyz;
  vec2 ndc = fragCoord * renderViewport.zw * 2.0 - 1.0;
  vec4 near = renderInvViewProj * vec4(ndc, -1.0, 1.0);
  return near.xyz / near.w;
}

// First hit of the ray (origin, unit dir) on the sphere (centre, radius renderCamForward.w). False when
// the ray misses by more than `tolerance` (a fraction of r^2); a smaller miss counts as grazing (the quad
// path has already cut the silhouette and only rounding is left). `precise`: every pass that recomputes
// this hit gets the same bits (render_points.frag compares depths across passes).
bool impostorHit(vec3 origin, vec3 dir, vec3 centre, float tolerance, out vec3 hit) {
  float r = renderCamForward.w;
  precise vec3 oc = origin - centre;
  precise float b = dot(oc, dir);
  precise float h = b * b - (dot(oc, oc) - r * r);
  precise vec3 p = origin + (-b - sqrt(max(h, 0.0))) * dir;
  hit = p;
  return h >= -tolerance * r * r;
}

// Window depth of a hit, as renderWindowDepth() but with the same bits in every program.
float impostorDepth(vec3 hit) {
  precise vec4 clip = renderViewProj * vec4(hit, 1.0);
  precise float depth = clip.z / clip.w * 0.5 + 0.5;
  return clamp(depth, 0.0, 1.0);
}

// Lit colour of a sphere at `hit` seen along `dir`: the ramp colour, diffuse and a small highlight.
vec4 impostorColour(vec3 hit, vec3 dir, vec3 centre, float scalar) {
  vec3 n = (hit - centre) / renderCamForward.w;
  vec3 albedo = impostorRamp(centre.y, scalar);
  vec3 halfway = normalize(renderLight.xyz - dir);
  float spec = pow(max(dot(n, halfway), 0.0), 40.0) * 0.25 * renderLight.w;
  return vec4(renderDiffuse(albedo, n) + spec, 1.0);
}
