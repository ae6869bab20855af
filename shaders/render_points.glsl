// Point-sprite geometry of a sphere impostor, shared by render_points.vert (drawing) and
// render_points_cull.comp (occlusion culling). Needs render_params.glsl first.

layout(std430, binding = SPHFX_SSBO_RENDER_PARTICLES) readonly buffer RenderParticles {
  vec4 renderParticles[];  // xyz position, w colour scalar (speed)
};

// tan() of the two rays from the eye tangent to a circle of radius r centred at (c, depth) in one view
// plane (x-z or y-z): the silhouette's extent along that axis, per unit depth.
vec2 tangentSlopes(float c, float depth, float r) {
  float t = sqrt(max(c * c + depth * depth - r * r, 0.0));
  return vec2((c * t - r * depth) / (depth * t + r * c), (c * t + r * depth) / (depth * t - r * c));
}

struct PointSprite {
  vec2 lo, hi;      // NDC bounding box of the sphere's silhouette (exact under perspective)
  float viewDepth;  // of the centre, along the view axis
};

PointSprite pointSprite(vec3 centre) {
  float r = renderCamForward.w;
  vec3 v = (renderView * vec4(centre, 1.0)).xyz;
  PointSprite s;
  s.viewDepth = -v.z;
  vec2 xs, ys;
  if (renderOrthographic()) {
    xs = v.x + vec2(-r, r);
    ys = v.y + vec2(-r, r);
  } else {
    xs = tangentSlopes(v.x, s.viewDepth, r);
    ys = tangentSlopes(v.y, s.viewDepth, r);
  }
  s.lo = vec2(xs.x, ys.x) * renderProjection.xy;
  s.hi = vec2(xs.y, ys.y) * renderProjection.xy;
  return s;
}

// NDC depth of a point `viewDepth` in front of the camera.
float pointNdcDepth(float viewDepth) {
  float z = renderProjection.z * -viewDepth + renderProjection.w;
  return renderOrthographic() ? z : z / viewDepth;
}
