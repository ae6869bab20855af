#pragma once
/// @file renderer.h
/// @brief The offscreen renderer: draws a frame into multisampled framebuffer objects (linear RGBA16F
/// colour, 32-bit float depth), resolves them to single-sample and reads the image back right way up.
/// Needs a current GL context (sphfx::GLContext) for the object's whole lifetime.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sphfx/core/mesh_io.h"
#include "sphfx/core/scene.h"
#include "sphfx/render/camera.h"
#include "sphfx/render/image_io.h"

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

/// Meshes builders used for the stage and for colliders.
/// A UV sphere with `stacks` x `slices` quads (split into triangles), outward normals.
TriangleMesh makeUvSphere(const Vec3d& center, double radius, int stacks, int slices);
/// An axis-aligned box with outward normals (flat shaded: 24 vertices).
TriangleMesh makeBox(const Vec3d& min, const Vec3d& max);

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

  /// Particles as sphere impostors over the stage. @throws GLError (with --gl-debug checks) on GL errors.
  Image renderParticles(const std::vector<ParticleInstance>& particles, const ParticleStyle& style,
                        const Stage& stage, const CameraView& camera);
  /// A water surface mesh over the stage. An empty mesh draws the stage alone. @throws as renderParticles.
  Image renderSurface(const TriangleMesh& water, const Stage& stage, const CameraView& camera);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sphfx::render
