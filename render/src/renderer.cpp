#include "renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "gpu_layouts.h"
#include "render_shaders.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/gpu_layout.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::render {

TriangleMesh makeUvSphere(const Vec3d& center, double radius, int stacks, int slices) {
  TriangleMesh m;
  for (int i = 0; i <= stacks; ++i) {
    const double theta = M_PI * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const double phi = 2 * M_PI * j / slices;
      const Vec3d n{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
      const Vec3d p = add(center, scale(n, radius));
      m.positions.push_back({float(p[0]), float(p[1]), float(p[2])});
      m.normals.push_back({float(n[0]), float(n[1]), float(n[2])});
    }
  }
  const auto at = [slices](int i, int j) { return uint32_t(i * (slices + 1) + j); };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      // Counter-clockwise seen from outside.
      if (i > 0) m.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
      if (i + 1 < stacks) m.triangles.push_back({at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  return m;
}

TriangleMesh withCreaseNormals(const TriangleMesh& m, double creaseDegrees) {
  std::map<std::array<float, 3>, uint32_t> weld;
  std::vector<uint32_t> id(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i)
    id[i] = weld.emplace(m.positions[i], uint32_t(weld.size())).first->second;
  std::vector<std::array<double, 3>> faceNormal(m.triangles.size());  // area-weighted
  std::vector<std::vector<uint32_t>> around(weld.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto &a = m.positions[m.triangles[t][0]], &b = m.positions[m.triangles[t][1]],
               &c = m.positions[m.triangles[t][2]];
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                 e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    faceNormal[t] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
    for (uint32_t v : m.triangles[t]) around[id[v]].push_back(uint32_t(t));
  }
  auto unit = [](std::array<double, 3> n) {
    const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0)
      for (double& c : n) c /= l;
    return n;
  };
  const double cosCrease = std::cos(creaseDegrees * std::numbers::pi / 180.0);
  TriangleMesh out;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto own = unit(faceNormal[t]);
    std::array<uint32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[t][k];
      std::array<double, 3> sum{};
      for (uint32_t f : around[id[v]]) {
        const auto n = unit(faceNormal[f]);
        if (n[0] * own[0] + n[1] * own[1] + n[2] * own[2] < cosCrease) continue;
        for (int a = 0; a < 3; ++a) sum[a] += faceNormal[f][a];
      }
      const auto n = unit(sum);
      tri[k] = uint32_t(out.positions.size());
      out.positions.push_back(m.positions[v]);
      out.normals.push_back({float(n[0]), float(n[1]), float(n[2])});
    }
    out.triangles.push_back(tri);
  }
  return out;
}

TriangleMesh makeBox(const Vec3d& lo, const Vec3d& hi) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const float sign = side ? 1.f : -1.f;
      const uint32_t base = uint32_t(m.positions.size());
      for (int k = 0; k < 4; ++k) {
        std::array<float, 3> p{};
        p[axis] = float(side ? hi[axis] : lo[axis]);
        p[u] = float((k & 1) ? hi[u] : lo[u]);
        p[v] = float((k & 2) ? hi[v] : lo[v]);
        std::array<float, 3> n{};
        n[axis] = sign;
        m.positions.push_back(p);
        m.normals.push_back(n);
      }
      // (u, v) is right-handed with the +axis normal; flip the winding on the minus side.
      if (side) {
        m.triangles.push_back({base, base + 1, base + 3});
        m.triangles.push_back({base, base + 3, base + 2});
      } else {
        m.triangles.push_back({base, base + 3, base + 1});
        m.triangles.push_back({base, base + 2, base + 3});
      }
    }
  return m;
}

namespace {

/// tan() of the rays from the eye tangent to a circle of radius r centred at (c, depth) in one view plane,
/// or false when a tangent ray is not in front of the eye (the circle reaches beside or behind it). The
/// same maths as tangentSlopes() in render_points.vert.
bool tangentSlopes(double c, double depth, double r, double& lo, double& hi) {
  const double t = std::sqrt(std::max(c * c + depth * depth - r * r, 0.0));
  const double dlo = depth * t + r * c, dhi = depth * t - r * c;
  if (!(dlo > 0 && dhi > 0)) return false;
  lo = (c * t - r * depth) / dlo;
  hi = (c * t + r * depth) / dhi;
  return true;
}

/// Occluder selection in splitImpostors: screen cells of 4 pixels; the points within 8 radii (four
/// layers of a packed fluid) of a cell's nearest. One layer would leave the gaps between its spheres
/// open (the farthest depth of every cull tile would be the background); four close them. Measured on
/// the bench's 1M block: 2 radii cull 1 %, 4 radii 49 %, 8 radii 93 %, 16 radii 93 % with twice the
/// occluders.
constexpr int kOccluderCell = 4;
constexpr double kOccluderDepth = 8;

/// Orders `ps` by `depth` (nearest first) with a counting sort over depth buckets: O(n), and order within
/// a bucket (a small fraction of the depth range) does not matter to early depth rejection.
void sortNearToFar(std::vector<ParticleInstance>& ps, const std::vector<float>& depth) {
  if (ps.size() < 2) return;
  const auto [lo, hi] = std::minmax_element(depth.begin(), depth.end());
  const size_t buckets = std::min<size_t>(4096, ps.size());
  const double scale = *hi > *lo ? double(buckets - 1) / (double(*hi) - *lo) : 0;
  std::vector<uint32_t> start(buckets + 1, 0), bucketOf(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) {
    bucketOf[i] = uint32_t((depth[i] - *lo) * scale);
    ++start[bucketOf[i] + 1];
  }
  for (size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<ParticleInstance> sorted(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) sorted[start[bucketOf[i]]++] = ps[i];
  ps.swap(sorted);
}

}  // namespace

ImpostorSplit splitImpostors(const std::vector<ParticleInstance>& particles, float radius,
                             const CameraView& camera, int width, int height, double maxPointSize) {
  const Mat4 view = viewMatrix(camera), proj = projectionMatrix(camera, double(width) / height);
  const double r = radius, n = camera.nearPlane, f = camera.farPlane, sx = proj[0], sy = proj[5];
  const bool ortho = camera.orthographic;
  // Distances to the side planes |sx x| = depth (perspective) are scaled by 1/sqrt(s^2 + 1).
  const double nx = 1 / std::sqrt(sx * sx + 1), ny = 1 / std::sqrt(sy * sy + 1);
  // Margins keep the GPU's float maths on the same side as this double-precision decision: a point's
  // centre stays a tenth of a pixel inside the image, its front a thousandth of the range behind near.
  const double edgeX = 1 - 0.2 / width, edgeY = 1 - 0.2 / height, nearMargin = 1e-3 * (f - n);
  const double maxSize = maxPointSize - 2;  // the shader adds half a pixel; the rest is for rounding
  // Occluder candidates: per screen cell, the points near the cell's nearest centre.
  const int cellsX = (width + kOccluderCell - 1) / kOccluderCell;
  const int cellsY = (height + kOccluderCell - 1) / kOccluderCell;
  std::vector<float> cellNearest(size_t(cellsX) * cellsY, std::numeric_limits<float>::infinity());
  ImpostorSplit split;
  split.points.reserve(particles.size());
  std::vector<float> pointDepth;
  std::vector<uint32_t> pointCell;
  pointDepth.reserve(particles.size());
  pointCell.reserve(particles.size());
  for (const ParticleInstance& p : particles) {
    const Vec3d v = transformPoint(view, {p.position[0], p.position[1], p.position[2]});
    const double depth = -v[2];
    bool outside = depth + r <= n || depth - r >= f;
    if (ortho)
      outside = outside || std::abs(v[0]) - 1 / sx >= r || std::abs(v[1]) - 1 / sy >= r;
    else
      outside = outside || (sx * std::abs(v[0]) - depth) * nx >= r || (sy * std::abs(v[1]) - depth) * ny >= r;
    if (outside) {
      ++split.culled;
      continue;
    }
    double x0 = v[0] - r, x1 = v[0] + r, y0 = v[1] - r, y1 = v[1] + r;
    bool point = depth - r > n + nearMargin;
    if (point && !ortho)
      point = tangentSlopes(v[0], depth, r, x0, x1) && tangentSlopes(v[1], depth, r, y0, y1);
    double cx = 0, cy = 0;
    if (point) {
      x0 *= sx, x1 *= sx, y0 *= sy, y1 *= sy;  // NDC
      cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
      const double size = std::max((x1 - x0) * width, (y1 - y0) * height) / 2;
      point = std::abs(cx) < edgeX && std::abs(cy) < edgeY && size <= maxSize;
    }
    if (!point) {
      split.quads.push_back(p);
      continue;
    }
    const int px = std::clamp(int((cx * 0.5 + 0.5) * width), 0, width - 1);
    const int py = std::clamp(int((cy * 0.5 + 0.5) * height), 0, height - 1);
    const uint32_t cell = uint32_t((py / kOccluderCell) * cellsX + px / kOccluderCell);
    cellNearest[cell] = std::min(cellNearest[cell], float(depth));
    split.points.push_back(p);
    pointDepth.push_back(float(depth));
    pointCell.push_back(cell);
  }
  // Occluders first, nearest first; the rest after them in any order.
  std::vector<ParticleInstance> occluders, rest;
  std::vector<float> occluderDepth;
  for (size_t i = 0; i < split.points.size(); ++i) {
    if (pointDepth[i] <= cellNearest[pointCell[i]] + float(kOccluderDepth * r)) {
      occluders.push_back(split.points[i]);
      occluderDepth.push_back(pointDepth[i]);
    } else {
      rest.push_back(split.points[i]);
    }
  }
  sortNearToFar(occluders, occluderDepth);
  split.occluders = occluders.size();
  split.points = std::move(occluders);
  split.points.insert(split.points.end(), rest.begin(), rest.end());
  return split;
}

namespace {

/// A mesh in GL buffers: positions (attribute 0), normals (attribute 1), triangle indices.
class GpuMesh {
 public:
  GpuMesh() { glCreateVertexArrays(1, &vao_); }
  ~GpuMesh() { glDeleteVertexArrays(1, &vao_); }
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  void upload(const TriangleMesh& mesh) {
    count_ = GLsizei(mesh.triangles.size() * 3);
    if (count_ == 0) return;
    positions_.uploadVector(mesh.positions);
    normals_.uploadVector(mesh.normals);
    indices_.uploadVector(mesh.triangles);
    glVertexArrayVertexBuffer(vao_, 0, positions_.id(), 0, sizeof(float) * 3);
    glVertexArrayVertexBuffer(vao_, 1, normals_.id(), 0, sizeof(float) * 3);
    for (GLuint a = 0; a < 2; ++a) {
      glEnableVertexArrayAttrib(vao_, a);
      glVertexArrayAttribFormat(vao_, a, 3, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(vao_, a, a);
    }
    glVertexArrayElementBuffer(vao_, indices_.id());
  }
  void draw() const {
    if (count_ == 0) return;
    glBindVertexArray(vao_);
    glDrawElements(GL_TRIANGLES, count_, GL_UNSIGNED_INT, nullptr);
  }

 private:
  GLuint vao_ = 0;
  GpuBuffer positions_, normals_, indices_;
  GLsizei count_ = 0;
};

GLuint makeRenderbuffer(GLenum format, int samples, int w, int h) {
  GLuint rb = 0;
  glCreateRenderbuffers(1, &rb);
  glNamedRenderbufferStorageMultisample(rb, samples > 1 ? samples : 0, format, w, h);
  return rb;
}

GLuint makeTexture(GLenum format, int w, int h) {
  GLuint tex = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &tex);
  glTextureStorage2D(tex, 1, format, w, h);
  glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return tex;
}

void checkComplete(GLuint fbo, const char* what) {
  const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw GLError(fmt::format("render: {} framebuffer incomplete (status 0x{:x})", what, status));
}

void copyMatrix(const Mat4& m, float* out) {
  for (int i = 0; i < 16; ++i) out[i] = float(m[i]);
}
void copyVec(const Vec3d& v, float w, float* out) {
  out[0] = float(v[0]), out[1] = float(v[1]), out[2] = float(v[2]), out[3] = w;
}

/// The tank's four side walls as inward-facing quads, so that back-face culling drops the walls between
/// the camera and the inside (their inner face is turned away from a camera outside them).
TriangleMesh makeWalls(const Domain& d) {
  TriangleMesh box = makeBox(d.min, d.max);
  TriangleMesh walls;
  for (size_t face = 0; face < 6; ++face) {
    if (face == 2 || face == 3) continue;  // makeBox orders faces -x,+x,-y,+y,-z,+z: skip floor and top
    if (d.isOpen(int(face / 2), int(face % 2))) continue;  // an outflow face has no wall to draw
    const uint32_t base = uint32_t(walls.positions.size());
    for (int k = 0; k < 4; ++k) {
      walls.positions.push_back(box.positions[face * 4 + k]);
      auto n = box.normals[face * 4 + k];
      walls.normals.push_back({-n[0], -n[1], -n[2]});
    }
    for (int t = 0; t < 2; ++t) {
      auto tri = box.triangles[face * 2 + t];
      const uint32_t off = uint32_t(face * 4);
      walls.triangles.push_back({base + tri[0] - off, base + tri[2] - off, base + tri[1] - off});
    }
  }
  return walls;
}

/// A square on the domain floor, wide enough to reach the horizon of any sensible view.
TriangleMesh makeGround(const Domain& d) {
  const double size = std::max({d.max[0] - d.min[0], d.max[1] - d.min[1], d.max[2] - d.min[2]});
  const double cx = (d.min[0] + d.max[0]) / 2, cz = (d.min[2] + d.max[2]) / 2, r = size * 10;
  TriangleMesh m;
  const float y = float(d.min[1]);
  for (int k = 0; k < 4; ++k) {
    m.positions.push_back({float(cx + ((k & 1) ? r : -r)), y, float(cz + ((k & 2) ? r : -r))});
    m.normals.push_back({0, 1, 0});
  }
  m.triangles = {{0, 2, 1}, {1, 2, 3}};
  return m;
}

}  // namespace

struct Renderer::Impl {
  int width = 0, height = 0, samples = 1;
  GLuint msaaFbo = 0, msaaColor = 0, msaaDepth = 0;
  GLuint resolveFbo = 0, resolveColor = 0, resolveDepth = 0;
  GLuint backFbo = 0, backDepth = 0;
  GLuint nearestDepth = 0;      // r32ui: per-pixel nearest window depth of the point-sprite passes
  GLuint depthMaxTiles = 0;     // r32f: farthest depth per SPHFX_RENDER_CULL_TILE square, for the cull
  bool depthInNearest = false;  // the last frame's depth is in nearestDepth, not the depth buffer
  GLuint emptyVao = 0;
  double maxPointSize = 1;
  ShaderProgram sky, solid, depthOnly, water, particles, pointsOcclude, pointsNearest, pointsShade;
  ShaderProgram nearestInit, depthMax, pointsCull;
  GpuBuffer params{sizeof(RenderParams)};
  GpuBuffer pointBuffer, quadBuffer, quadIndices, visibleBuffer, drawCommand{4 * sizeof(GLuint)};
  size_t quadCapacity = 0;
  ParticleCounts lastCounts;
  void initNearestDepth();
  GLuint cullPoints(size_t count);
  GpuMesh waterMesh, ground, walls;
  std::vector<std::unique_ptr<GpuMesh>> solids;

  Impl(int w, int h, int requestedSamples);
  ~Impl();
  void createFramebuffers();
  void setParams(const CameraView& camera, const Stage& stage, const ParticleStyle* style);
  void beginFrame();
  void drawStage(const Stage& stage);
  void resolve();
  void drawWater(const TriangleMesh& mesh);
  void drawParticles(const std::vector<ParticleInstance>& particles, const CameraView& camera, float radius);
  void drawQuads(const std::vector<ParticleInstance>& quads);
  void drawPoints(const std::vector<ParticleInstance>& points, size_t occluders);
  Image readBack(const CameraView& camera);
};

Renderer::Impl::Impl(int w, int h, int requestedSamples) : width(w), height(h) {
  GLint maxSize = 0, maxSamples = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  if (w < 1 || h < 1 || w > maxSize || h > maxSize)
    throw InputError(
        fmt::format("render: image size {}x{} is outside 1..{} (GL_MAX_TEXTURE_SIZE)", w, h, maxSize));
  if (requestedSamples < 1) throw InputError("render: samples must be at least 1");
  samples = std::clamp(requestedSamples, 1, std::max(1, int(maxSamples)));
  createFramebuffers();
  glCreateVertexArrays(1, &emptyVao);
  sky = ShaderProgram::graphics(renderShaderTable(), "render_fullscreen.vert", "render_sky.frag");
  solid = ShaderProgram::graphics(renderShaderTable(), "render_mesh.vert", "render_solid.frag");
  depthOnly = ShaderProgram::graphics(renderShaderTable(), "render_mesh.vert", "render_depth.frag");
  water = ShaderProgram::graphics(renderShaderTable(), "render_mesh.vert", "render_water.frag");
  particles = ShaderProgram::graphics(renderShaderTable(), "render_particles.vert", "render_particles.frag");
  const auto pointsPass = [](int pass) {
    return ShaderProgram::graphics(renderShaderTable(), "render_points.vert", "render_points.frag",
                                   ShaderDefines().set("SPHFX_IMPOSTOR_PASS", pass));
  };
  pointsOcclude = pointsPass(SPHFX_IMPOSTOR_OCCLUDE);
  pointsNearest = pointsPass(SPHFX_IMPOSTOR_NEAREST);
  pointsShade = pointsPass(SPHFX_IMPOSTOR_SHADE);
  nearestInit = ShaderProgram::compute(renderShaderTable(), "render_nearest_init.comp");
  depthMax = ShaderProgram::compute(renderShaderTable(), "render_depth_max.comp");
  pointsCull = ShaderProgram::compute(renderShaderTable(), "render_points_cull.comp");
  GLfloat pointRange[2] = {1, 1};
  glGetFloatv(GL_POINT_SIZE_RANGE, pointRange);
  maxPointSize = pointRange[1];
}

void Renderer::Impl::createFramebuffers() {
  msaaColor = makeRenderbuffer(GL_RGBA16F, samples, width, height);
  msaaDepth = makeRenderbuffer(GL_DEPTH_COMPONENT32F, samples, width, height);
  glCreateFramebuffers(1, &msaaFbo);
  glNamedFramebufferRenderbuffer(msaaFbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaaColor);
  glNamedFramebufferRenderbuffer(msaaFbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaaDepth);
  checkComplete(msaaFbo, "multisampled");

  resolveColor = makeTexture(GL_RGBA16F, width, height);
  resolveDepth = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &resolveFbo);
  glNamedFramebufferTexture(resolveFbo, GL_COLOR_ATTACHMENT0, resolveColor, 0);
  glNamedFramebufferTexture(resolveFbo, GL_DEPTH_ATTACHMENT, resolveDepth, 0);
  checkComplete(resolveFbo, "resolve");

  backDepth = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &backFbo);
  glNamedFramebufferTexture(backFbo, GL_DEPTH_ATTACHMENT, backDepth, 0);
  glNamedFramebufferDrawBuffer(backFbo, GL_NONE);
  checkComplete(backFbo, "water back-face depth");

  glCreateTextures(GL_TEXTURE_2D, 1, &nearestDepth);
  glTextureStorage2D(nearestDepth, 1, GL_R32UI, width, height);
  glCreateTextures(GL_TEXTURE_2D, 1, &depthMaxTiles);
  glTextureStorage2D(depthMaxTiles, 1, GL_R32F, (width + SPHFX_RENDER_CULL_TILE - 1) / SPHFX_RENDER_CULL_TILE,
                     (height + SPHFX_RENDER_CULL_TILE - 1) / SPHFX_RENDER_CULL_TILE);
}

Renderer::Impl::~Impl() {
  glDeleteFramebuffers(1, &msaaFbo);
  glDeleteFramebuffers(1, &resolveFbo);
  glDeleteFramebuffers(1, &backFbo);
  glDeleteRenderbuffers(1, &msaaColor);
  glDeleteRenderbuffers(1, &msaaDepth);
  const GLuint textures[] = {resolveColor, resolveDepth, backDepth, nearestDepth, depthMaxTiles};
  glDeleteTextures(5, textures);
  glDeleteVertexArrays(1, &emptyVao);
}

void Renderer::Impl::setParams(const CameraView& camera, const Stage& stage, const ParticleStyle* style) {
  const double aspect = double(width) / height;
  const Mat4 view = viewMatrix(camera);
  const Mat4 viewProj = multiply(projectionMatrix(camera, aspect), view);
  const CameraBasis basis = cameraBasis(camera);
  RenderParams p{};
  copyMatrix(viewProj, p.viewProj);
  copyMatrix(view, p.view);
  copyMatrix(inverse(viewProj), p.invViewProj);
  copyVec(camera.position, camera.orthographic ? 1.f : 0.f, p.eye);
  copyVec(basis.right, float(camera.nearPlane), p.camRight);
  copyVec(basis.up, float(camera.farPlane), p.camUp);
  copyVec(basis.forward, style ? style->radius : 0.f, p.camForward);
  copyVec(normalize(stage.lightDirection), 1.f, p.light);
  p.viewport[0] = float(width), p.viewport[1] = float(height);
  p.viewport[2] = 1.f / float(width), p.viewport[3] = 1.f / float(height);
  if (style) {
    p.ramp[0] = style->heightMin, p.ramp[1] = style->heightMax, p.ramp[2] = style->speedScale;
    p.ramp[3] = style->colorBy == ColorBy::Speed ? 1.f : 0.f;
  }
  copyVec(stage.domain.min, 0, p.domainMin);
  copyVec(stage.domain.max, 0, p.domainMax);
  const Mat4 proj = projectionMatrix(camera, aspect);
  p.projection[0] = float(proj[0]), p.projection[1] = float(proj[5]);
  p.projection[2] = float(proj[10]), p.projection[3] = float(proj[14]);
  params.upload(&p, sizeof(p));
  params.bindUniform(SPHFX_UBO_RENDER_PARAMS);
}

void Renderer::Impl::beginFrame() {
  depthInNearest = false;
  glBindFramebuffer(GL_FRAMEBUFFER, msaaFbo);
  glViewport(0, 0, width, height);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float clearColor[4] = {0, 0, 0, 0};
  const float clearDepth = 1;
  glClearNamedFramebufferfv(msaaFbo, GL_COLOR, 0, clearColor);
  glClearNamedFramebufferfv(msaaFbo, GL_DEPTH, 0, &clearDepth);
  glDisable(GL_BLEND);
  glEnable(GL_MULTISAMPLE);
}

void Renderer::Impl::drawStage(const Stage& stage) {
  if (stage.sky) {
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    sky.use();
    glBindVertexArray(emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  solid.use();
  const Mat4 id = identity();
  float model[16];
  copyMatrix(id, model);
  glUniformMatrix4fv(solid.uniform("uModel"), 1, GL_FALSE, model);
  const double size =
      std::max(stage.domain.max[0] - stage.domain.min[0], stage.domain.max[2] - stage.domain.min[2]);
  glUniform1f(solid.uniform("uCheckerSize"), float(size > 0 ? size / 8 : 1));
  if (stage.ground) {
    glUniform1i(solid.uniform("uPattern"), 1);
    glUniform3f(solid.uniform("uAlbedo"), 0.55f, 0.53f, 0.5f);
    ground.upload(makeGround(stage.domain));
    glDisable(GL_CULL_FACE);
    ground.draw();
  }
  glUniform1i(solid.uniform("uPattern"), 0);
  if (stage.walls) {
    glUniform3f(solid.uniform("uAlbedo"), 0.72f, 0.74f, 0.76f);
    walls.upload(makeWalls(stage.domain));
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    walls.draw();
    glDisable(GL_CULL_FACE);
  }
  while (solids.size() < stage.solids.size()) solids.push_back(std::make_unique<GpuMesh>());
  for (size_t i = 0; i < stage.solids.size(); ++i) {
    const Solid& s = stage.solids[i];
    copyMatrix(translation(s.offset), model);
    glUniformMatrix4fv(solid.uniform("uModel"), 1, GL_FALSE, model);
    glUniform3f(solid.uniform("uAlbedo"), s.albedo[0], s.albedo[1], s.albedo[2]);
    solids[i]->upload(s.mesh);
    solids[i]->draw();
  }
  glCheck("render: stage");
}

void Renderer::Impl::resolve() {
  glBlitNamedFramebuffer(msaaFbo, resolveFbo, 0, 0, width, height, 0, 0, width, height,
                         GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
  glCheck("render: resolve");
}

void Renderer::Impl::drawWater(const TriangleMesh& mesh) {
  waterMesh.upload(mesh);
  float model[16];
  copyMatrix(identity(), model);
  // Farthest water surface per pixel (depth GREATER from a cleared 0): the far side of the thickness.
  glBindFramebuffer(GL_FRAMEBUFFER, backFbo);
  const float zero = 0;
  glClearNamedFramebufferfv(backFbo, GL_DEPTH, 0, &zero);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  depthOnly.use();
  glUniformMatrix4fv(depthOnly.uniform("uModel"), 1, GL_FALSE, model);
  waterMesh.draw();
  // Nearest water surface into the multisampled image, over the opaque stage already there. No face
  // culling: the nearest surface wins the depth test whatever the mesh's winding.
  glBindFramebuffer(GL_FRAMEBUFFER, msaaFbo);
  glDepthFunc(GL_LESS);
  water.use();
  glUniformMatrix4fv(water.uniform("uModel"), 1, GL_FALSE, model);
  glBindTextureUnit(SPHFX_TEX_RENDER_BACKGROUND, resolveColor);
  glBindTextureUnit(SPHFX_TEX_RENDER_OPAQUE_DEPTH, resolveDepth);
  glBindTextureUnit(SPHFX_TEX_RENDER_BACK_DEPTH, backDepth);
  waterMesh.draw();
  glCheck("render: water");
  for (GLuint unit : {0u, 1u, 2u}) glBindTextureUnit(unit, 0);
}

void Renderer::Impl::drawParticles(const std::vector<ParticleInstance>& ps, const CameraView& camera,
                                   float radius) {
  static_assert(sizeof(ParticleInstance) == sizeof(RenderParticle));
  const ImpostorSplit split = splitImpostors(ps, radius, camera, width, height, maxPointSize);
  lastCounts = {split.points.size(), split.quads.size(), split.culled, split.occluders, 0};
  // Impostors are drawn at one sample over the resolved (antialiased) stage: their silhouettes come from a
  // per-pixel ray test, which MSAA would not smooth anyway, and per-sample depth and colour writes would
  // cost more than the shading.
  glBindFramebuffer(GL_FRAMEBUFFER, resolveFbo);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  drawQuads(split.quads);
  drawPoints(split.points, split.occluders);
  glCheck("render: particles");
}

void Renderer::Impl::drawPoints(const std::vector<ParticleInstance>& ps, size_t occluders) {
  if (ps.empty()) return;
  pointBuffer.uploadVector(ps);
  pointBuffer.bindStorage(SPHFX_SSBO_RENDER_PARTICLES);
  initNearestDepth();
  glEnable(GL_PROGRAM_POINT_SIZE);
  glBindVertexArray(emptyVao);
  // Occluders write an upper bound of the nearest surface (render_points.frag).
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  pointsOcclude.use();
  glDrawArrays(GL_POINTS, 0, GLsizei(occluders));
  // Every point not provably behind that bound goes on, through the indirect command, to the nearest
  // depth and shading passes.
  lastCounts.visible = cullPoints(ps.size());
  visibleBuffer.bindStorage(SPHFX_SSBO_RENDER_PARTICLES);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, drawCommand.id());
  glDepthMask(GL_FALSE);
  pointsNearest.use();
  glDrawArraysIndirect(GL_POINTS, nullptr);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  pointsShade.use();
  glDrawArraysIndirect(GL_POINTS, nullptr);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glDepthMask(GL_TRUE);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
  depthInNearest = true;
}

void Renderer::Impl::initNearestDepth() {
  // The nearest-depth image starts as the depth buffer so far: the stage and the quad impostors.
  nearestInit.use();
  glBindTextureUnit(SPHFX_TEX_RENDER_SCENE_DEPTH, resolveDepth);
  glBindImageTexture(SPHFX_IMAGE_RENDER_NEAREST, nearestDepth, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  dispatchCompute1D(nearestInit, uint32_t(width) * uint32_t(height), "render: nearest depth init");
  glBindTextureUnit(SPHFX_TEX_RENDER_SCENE_DEPTH, 0);  // it is also the depth attachment drawn into
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

GLuint Renderer::Impl::cullPoints(size_t count) {
  const int tile = SPHFX_RENDER_CULL_TILE;
  const uint32_t tiles = uint32_t((width + tile - 1) / tile) * uint32_t((height + tile - 1) / tile);
  glBindImageTexture(SPHFX_IMAGE_RENDER_DEPTH_MAX, depthMaxTiles, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  depthMax.use();
  glBindTextureUnit(SPHFX_TEX_RENDER_SCENE_DEPTH, resolveDepth);
  dispatchCompute1D(depthMax, tiles, "render: depth max tiles");
  glBindTextureUnit(SPHFX_TEX_RENDER_SCENE_DEPTH, 0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);

  if (visibleBuffer.size() < count * sizeof(RenderParticle))
    visibleBuffer.resize(count * sizeof(RenderParticle));
  const GLuint command[4] = {0, 1, 0, 0};  // count, instances, first, base instance
  drawCommand.upload(command, sizeof(command));
  visibleBuffer.bindStorage(SPHFX_SSBO_RENDER_VISIBLE);
  drawCommand.bindStorage(SPHFX_SSBO_RENDER_DRAW);
  pointsCull.use();
  glUniform1ui(pointsCull.uniform("uCount"), GLuint(count));
  dispatchCompute1D(pointsCull, uint32_t(count), "render: impostor cull");
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  GLuint visible = 0;
  drawCommand.download(&visible, sizeof(visible));
  return visible;
}

void Renderer::Impl::drawQuads(const std::vector<ParticleInstance>& ps) {
  if (ps.empty()) return;
  quadBuffer.uploadVector(ps);
  quadBuffer.bindStorage(SPHFX_SSBO_RENDER_PARTICLES);
  if (quadCapacity < ps.size()) {
    // Two triangles per particle over its 4 pulled vertices; grown geometrically, kept across frames.
    quadCapacity = std::max(ps.size(), quadCapacity * 2);
    std::vector<uint32_t> idx(quadCapacity * 6);
    for (size_t i = 0; i < quadCapacity; ++i) {
      const uint32_t b = uint32_t(i * 4);
      const uint32_t q[6] = {b, b + 1, b + 2, b + 2, b + 1, b + 3};
      std::copy(q, q + 6, &idx[i * 6]);
    }
    quadIndices.uploadVector(idx);
  }
  particles.use();
  glBindVertexArray(emptyVao);
  glVertexArrayElementBuffer(emptyVao, quadIndices.id());
  glDrawElements(GL_TRIANGLES, GLsizei(ps.size() * 6), GL_UNSIGNED_INT, nullptr);
  glVertexArrayElementBuffer(emptyVao, 0);
}

Image Renderer::Impl::readBack(const CameraView& camera) {
  Image img{width, height, std::vector<float>(size_t(width) * height * 4),
            std::vector<float>(size_t(width) * height)};
  std::vector<float> rows(img.rgba.size()), depth(img.depth.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, resolveFbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rows.data());
  if (depthInNearest) {
    // Float bits in an r32ui image (render_points.frag).
    static_assert(sizeof(float) == sizeof(uint32_t));
    glGetTextureImage(nearestDepth, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(depth.size() * sizeof(float)),
                      depth.data());
  } else {
    glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  }
  glCheck("render: read back");
  // GL rows run bottom to top; images top to bottom.
  const size_t rowFloats = size_t(width) * 4;
  const double n = camera.nearPlane, f = camera.farPlane;
  for (int y = 0; y < height; ++y) {
    const int src = height - 1 - y;
    std::copy_n(&rows[src * rowFloats], rowFloats, &img.rgba[y * rowFloats]);
    for (int x = 0; x < width; ++x) {
      const double d = depth[size_t(src) * width + x];
      double z = std::numeric_limits<double>::infinity();
      if (d < 1) z = camera.orthographic ? n + d * (f - n) : 2 * f * n / ((f + n) - (2 * d - 1) * (f - n));
      img.depth[size_t(y) * width + x] = float(z);
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return img;
}

Renderer::Renderer(int width, int height, int samples)
    : impl_(std::make_unique<Impl>(width, height, samples)) {}
Renderer::~Renderer() = default;
int Renderer::width() const {
  return impl_->width;
}
int Renderer::height() const {
  return impl_->height;
}
int Renderer::samples() const {
  return impl_->samples;
}
double Renderer::maxPointSize() const {
  return impl_->maxPointSize;
}
Renderer::ParticleCounts Renderer::lastParticleCounts() const {
  return impl_->lastCounts;
}

Image Renderer::renderParticles(const std::vector<ParticleInstance>& particles, const ParticleStyle& style,
                                const Stage& stage, const CameraView& camera) {
  impl_->setParams(camera, stage, &style);
  impl_->beginFrame();
  impl_->drawStage(stage);
  impl_->resolve();
  impl_->drawParticles(particles, camera, style.radius);
  return impl_->readBack(camera);
}

Image Renderer::renderSurface(const TriangleMesh& water, const Stage& stage, const CameraView& camera) {
  impl_->setParams(camera, stage, nullptr);
  impl_->beginFrame();
  impl_->drawStage(stage);
  impl_->resolve();
  if (!water.triangles.empty()) {
    impl_->drawWater(water);
    impl_->resolve();
  }
  return impl_->readBack(camera);
}

}  // namespace sphfx::render
