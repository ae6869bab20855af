#pragma once
/// @file renderer.h
/// @brief The offscreen renderer: draws a frame into multisampled framebuffer objects (linear RGBA16F
/// colour, 32-bit float depth), resolves them to single-sample and reads the image back right way up.
/// Needs a current GL context (sphfx::GLContext) for the object's whole lifetime.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"
#include "image_io.h"
#include "sphfx/core/mesh_io.h"
#include "sphfx/core/scene.h"

namespace sphfx::render {

/// A solid object (a collider) drawn opaque.
struct Solid {
  TriangleMesh mesh;
  Vec3d offset{};  ///< translation for this frame
  std::array<float, 3> albedo{0.75f, 0.32f, 0.1f};
};

/// What surrounds the fluid: the sky, the ground plane at the domain floor (a faint checker), the tank
/// walls (the four sides of the domain; only the inner faces turned towards the camera are drawn, so
/// the camera always sees in), and the colliders.
struct Stage {
  Domain domain;
  bool sky = true;
  bool ground = true;
  bool walls = true;
  std::vector<Solid> solids;
  Vec3d lightDirection{0.35, 0.85, 0.4};  ///< toward the key light (normalised when used)
};

/// How particles look.
struct ParticleStyle {
  float radius = 0.01f;  ///< sphere radius (m)
  ColorBy colorBy = ColorBy::Height;
  float heightMin = 0, heightMax = 1;  ///< height ramp: dark at heightMin, bright blue at heightMax
  float speedScale = 1;                ///< speed ramp: white at this speed (m/s)
};

/// One particle to draw: position and the speed used by the speed ramp.
struct ParticleInstance {
  float position[3];
  float speed;
};

/// How particles reach the GL. Point sprites (one vertex per particle) are the fast path; camera-facing
/// quads (4 vertices) take the spheres a point cannot draw: those reaching in front of the near plane
/// (or holding the camera), those whose silhouette box is centred off screen (GL clips a point by its
/// centre, so a sphere straddling the image edge would vanish), and those larger than the GL's biggest
/// point. Spheres wholly outside the view volume are dropped.
/// Points come ordered for the occlusion passes (render_points.frag): first `occluders` of them, nearest
/// first (per 4-pixel screen cell, those within 8 radii of the cell's nearest point: the likely front
/// layers), then the rest.
struct ImpostorSplit {
  std::vector<ParticleInstance> points, quads;
  size_t occluders = 0;
  size_t culled = 0;
};

/// Splits `particles` (spheres of `radius`) for `camera` in a width x height image whose GL draws
/// points up to `maxPointSize` pixels. @throws InputError for an invalid camera (as projectionMatrix()).
ImpostorSplit splitImpostors(const std::vector<ParticleInstance>& particles, float radius,
                             const CameraView& camera, int width, int height, double maxPointSize);

/// Meshes builders used for the stage and for colliders.
/// A UV sphere with `stacks` x `slices` quads (split into triangles), outward normals.
TriangleMesh makeUvSphere(const Vec3d& center, double radius, int stacks, int slices);
/// An axis-aligned box with outward normals (flat shaded: 24 vertices).
TriangleMesh makeBox(const Vec3d& min, const Vec3d& max);
/// The same surface with hard edges kept: one vertex per triangle corner, its normal averaged over the
/// triangles around the (position-welded) vertex that turn less than `creaseDegrees` from the corner's
/// own triangle. Stairs stay sharp, a tessellated sphere stays smooth.
TriangleMesh withCreaseNormals(const TriangleMesh& mesh, double creaseDegrees);

class Renderer {
 public:
  /// Allocates the framebuffers and compiles the programs. `samples` is clamped to what the GL allows
  /// (GL_MAX_SAMPLES; 1 means no MSAA). @throws GLError if a program does not build or a framebuffer is
  /// incomplete; InputError for a size outside 1..GL_MAX_TEXTURE_SIZE or a zero sample count.
  Renderer(int width, int height, int samples);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int width() const;
  int height() const;
  /// The MSAA sample count in use after clamping.
  int samples() const;
  /// The largest point size the GL rasterises (upper end of GL_POINT_SIZE_RANGE), in pixels.
  double maxPointSize() const;
  /// How the last renderParticles() call drew its particles: as points (of which `occluders` in the
  /// occluder pass and `visible` after the occlusion cull), as quads, or not at all (outside the view).
  struct ParticleCounts {
    size_t points = 0, quads = 0, culled = 0, occluders = 0, visible = 0;
  };
  ParticleCounts lastParticleCounts() const;

  /// Particles as sphere impostors over the stage (point sprites where possible, see ImpostorSplit).
  /// @throws GLError (with --gl-debug checks) on GL errors.
  Image renderParticles(const std::vector<ParticleInstance>& particles, const ParticleStyle& style,
                        const Stage& stage, const CameraView& camera);
  /// A water surface mesh over the stage. An empty mesh draws the stage alone. @throws as renderParticles.
  Image renderSurface(const TriangleMesh& water, const Stage& stage, const CameraView& camera);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sphfx::render
