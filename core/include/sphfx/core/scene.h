#pragma once
/// @file scene.h
/// @brief The scene: everything a shot needs, in SI units, loaded from JSON. Axis convention: +Y is up.
///
/// Every parameter is declared once, in scene.cpp, with its default, unit, valid range and description;
/// `sphfx scene --schema` and docs/scene-format.md are generated from those declarations.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "sphfx/core/methods.h"
#include "sphfx/core/schema.h"

namespace sphfx {

using Vec3d = std::array<double, 3>;

enum class EquationOfState { Linear, Tait };
/// WCSPH's smoothing kernel for density and pressure gradient.
enum class SphKernel { WendlandC2, Muller2003 };
/// How DFSPH's walls enter the constant-density solve (solver.dfsph.walls).
enum class DfsphWalls { Push, Constraints };
/// The fluid's density kernel under DFSPH (solver.dfsph.density_kernel).
enum class DfsphDensityKernel { Poly6, Spiky, WendlandC2 };
/// The substeps whose constant-density solve starts warm (solver.dfsph.density_warm_steps).
enum class DfsphWarmSteps { All, FlowLimited };
enum class ViscosityModel { None, Laplacian, Artificial };
/// The artificial model's walls: Monaghan's term on the whole relative velocity (no slip), or on the
/// approach alone with a skin friction on the sliding.
enum class WallDrag { Viscous, Friction };
enum class TimeStepMode { Fixed, Cfl };
/// Box and sphere: fluid blocks and colliders; mesh and vdb: colliders only.
enum class Shape { Box, Sphere, Mesh, Vdb };
/// Optional per-particle attributes of the cache. Position `P` and velocity `v` are always stored.
enum class CacheAttribute { Density, Pressure, Id };
enum class RenderSource { Surface, Particles };
enum class ColorBy { Height, Speed };
enum class ImageFormat { Png, Exr };
/// Axes along which the domain may wrap around (periodic boundaries).
enum class PeriodicAxis { X, Y, Z };
/// Faces of the domain box; an open face has no wall and removes the particles that leave through it.
enum class DomainFace { XMin, XMax, YMin, YMax, ZMin, ZMax };
/// Shapes of an emitter (a nozzle that adds particles while it is active).
enum class EmitterShape { Disc, Box, Sphere };

/// The simulation domain: a box with solid walls on its six sides, except the faces of periodic axes.
struct Domain {
  Vec3d min{};
  Vec3d max{};
  std::vector<PeriodicAxis> periodic;  ///< wrapped axes: no walls there, [min, max) repeats
  std::vector<DomainFace> open;        ///< faces without walls: particles leaving through them are removed
  /// True if axis 0 (x), 1 (y) or 2 (z) wraps around.
  bool isPeriodic(int axis) const;
  bool anyPeriodic() const { return !periodic.empty(); }
  /// True if the face of `axis` on `side` (0: min, 1: max) is open.
  bool isOpen(int axis, int side) const;
};

/// A Taylor-Green vortex in a fluid block's initial velocity (fluid.blocks[].taylor_green; the field is
/// taylorGreenVelocity()).
struct TaylorGreenVortex {
  double amplitude = 0;  ///< U0 (m/s)
};

/// A block of fluid present at the first frame.
struct FluidBlock {
  Shape shape = Shape::Box;
  Vec3d min{};     ///< box only
  Vec3d max{};     ///< box only
  Vec3d center{};  ///< sphere only
  double radius = 0;
  Vec3d velocity{};                              ///< initial velocity of every particle in the block
  std::optional<TaylorGreenVortex> taylorGreen;  ///< added to `velocity` where set
};

/// The Taylor-Green vortex of amplitude U in the x-z plane of a domain periodic in x and z, one
/// wavelength per period (kx = 2 pi / Lx, kz = 2 pi / Lz, phases from domain.min):
///   u = U sin(kx x) cos(kz z), v = 0, w = -U (kx / kz) cos(kx x) sin(kz z),
/// divergence-free; under viscosity nu it decays as exp(-nu (kx^2 + kz^2) t) (Taylor & Green 1937).
Vec3d taylorGreenVelocity(const Domain& domain, double amplitude, const Vec3d& position);

struct Fluid {
  double spacing = 0;  ///< rest particle spacing (m); sets the resolution and the particle mass
  double packing = 1;  ///< initial lattice spacing as a fraction of `spacing` (< 1: compressed start)
  double restDensity = 0;
  ViscosityModel viscosityModel = ViscosityModel::Artificial;
  double viscosity = 0;            ///< kinematic viscosity (m^2/s), laplacian model
  double artificialViscosity = 0;  ///< Monaghan alpha, artificial model
  double wallViscosityFactor = 1;  ///< viscosity between fluid and walls/colliders: 1 no slip, 0 free slip
  double wallViscositySpeed = 0;   ///< artificial model: the walls' alpha c (m/s), apart from the fluid's
  WallDrag wallDrag = WallDrag::Viscous;  ///< artificial model: what the walls' term acts on
  double wallFriction = 0;                ///< WallDrag::Friction: skin-friction coefficient c_f
  double wallContact = 0;  ///< below this share of a full neighbourhood: no approach past the resting layer
  std::vector<FluidBlock> blocks;
};

/// WCSPH's own parameters (solver.wcsph).
struct WcsphSettings {
  EquationOfState eos = EquationOfState::Tait;
  SphKernel kernel = SphKernel::WendlandC2;
  double stiffness = 0;    ///< linear EOS: p = k (rho - rho0), k in Pa / (kg/m^3) = m^2/s^2
  double gamma = 7;        ///< Tait exponent
  double forceFactor = 0;  ///< CFL mode: factor on Monaghan's force limit sqrt(h / |a|max)
};

/// DFSPH's own parameters (solver.dfsph).
struct DfsphSettings {
  double maxDensityError = 0;     ///< average density error tolerance (fraction of rho0)
  double maxDivergenceError = 0;  ///< mean |D rho/Dt| / rho0 * dt (relative change per step)
  int minIterations = 0;
  int minDivergenceIterations = 0;
  int maxIterations = 0;
  double jacobiOmega = 0;          ///< relaxation of the projected Jacobi updates
  double jacobiMomentum = 0;       ///< heavy-ball share of the previous Jacobi increment
  double densityWarmShare = 0;     ///< share of the last substep's stiffness the density solve starts from
  double divergenceWarmShare = 0;  ///< the same for the divergence solve
  DfsphWalls walls = DfsphWalls::Push;  ///< the walls' part in the constant-density solve
  DfsphDensityKernel densityKernel = DfsphDensityKernel::Poly6;  ///< the fluid's density sum
  double densityWallPush = 0;      ///< wall samples' weight in the constant-density solve (push walls)
  double freeSurfaceFraction = 0;  ///< below this share of a full neighbourhood: no divergence estimate
  double fallFactor = 0;           ///< CFL mode: |a|max dt^2 <= fallFactor * spacing
  /// CFL mode: dt <= depthStepFactor * spacing / sqrt(|g| H), H the domain's extent along gravity (0: off)
  double depthStepFactor = 0;
  /// The substeps densityWarmShare applies in (with densityWarmShare > 0)
  DfsphWarmSteps densityWarmSteps = DfsphWarmSteps::All;
};

struct SolverSettings {
  Solver method = Solver::WCSPH;
  double kernelSupport = 0;  ///< kernel support radius h as a multiple of the particle spacing
  /// Numerical speed of sound (m/s): WCSPH's Tait EOS and acoustic limit, and the c of Monaghan's
  /// artificial viscosity under either solver.
  double speedOfSound = 0;
  WcsphSettings wcsph;
  DfsphSettings dfsph;
};

struct TimeSettings {
  double fps = 0;
  int startFrame = 1;
  int endFrame = 1;
  TimeStepMode mode = TimeStepMode::Cfl;
  double dt = 0;  ///< fixed mode
  double cflFactor = 0;
  double viscousFactor = 0;
  double dtMin = 0;
  double dtMax = 0;
};

/// Placement of a collider at a time: a translation, linear between keys, and a rotation about the
/// collider's pivot (colliderPivot()), interpolated as quaternions (slerp); held before the first and
/// after the last key (collider_motion.h).
struct Keyframe {
  double time = 0;
  Vec3d offset{};
  Vec3d rotation{};  ///< degrees about x, then y, then z (fixed axes)
};

/// A solid object the fluid flows around, moved by keyframes. Mesh and vdb colliders are placed at rest
/// by scale, then rotation, then translation.
struct Collider {
  std::string name;
  Shape shape = Shape::Box;
  Vec3d min{};
  Vec3d max{};
  Vec3d center{};
  double radius = 0;
  std::string file;      ///< mesh (OBJ, PLY, STL) or vdb file; absolute once loaded (loadScene)
  std::string grid;      ///< vdb: name of the level-set grid; empty: the first float grid
  double scale = 1;      ///< mesh/vdb: uniform scale (keeps distances distances)
  Vec3d rotation{};      ///< mesh/vdb: degrees about x, then y, then z
  Vec3d translation{};   ///< mesh/vdb
  double thickness = 0;  ///< mesh: shell thickness for a mesh that is not closed; 0: must be closed
  std::vector<Keyframe> keyframes;
  /// True for shapes described by a signed distance field (mesh, vdb).
  bool isField() const { return shape == Shape::Mesh || shape == Shape::Vdb; }
};

/// A nozzle adding fluid on the lattice of fluid.spacing while it is active: a disc emits a new layer of
/// its lattice points each time the emitted fluid has advanced one spacing along `direction`.
struct Emitter {
  std::string name;
  EmitterShape shape = EmitterShape::Disc;
  Vec3d center{};             ///< disc, sphere
  double radius = 0;          ///< disc, sphere
  Vec3d min{};                ///< box
  Vec3d max{};                ///< box
  Vec3d direction{0, -1, 0};  ///< unit vector (normalised on load)
  double speed = 0;           ///< m/s along direction; also the emitted particles' velocity
  double start = 0;           ///< s
  double end = 0;             ///< s; emission covers [start, end)
};

/// A box that removes the particles entering it.
struct KillBox {
  Vec3d min{};
  Vec3d max{};
};

struct Limits {
  int maxParticles = 0;  ///< most particles a scene may hold at once (initial + all its emitters emit)
};

struct Health {
  double maxDensityRatio = 0;  ///< stop if any density exceeds this multiple of rest density
  double maxSpeed = 0;         ///< stop if any particle is faster than this (m/s)
};

struct CacheSettings {
  std::vector<CacheAttribute> attributes;
};

/// The anisotropic method's own parameters (surface.anisotropic; Yu & Turk 2013).
struct AnisotropicSurfaceSettings {
  double lambda = 0;         ///< Laplacian smoothing of the kernel centres
  double maxStretch = 0;     ///< k_r: largest ratio between a kernel's axes
  int isolatedBelow = 0;     ///< N_eps: fewer neighbours give a small isotropic kernel
  double isolatedScale = 0;  ///< k_n: that kernel's support relative to the full one
};

struct SurfaceSettings {
  SurfaceMethod method = SurfaceMethod::ZhuBridson;
  double voxelFactor = 0;   ///< voxel size as a multiple of the particle spacing
  double radiusFactor = 0;  ///< particle radius as a multiple of the particle spacing
  int smoothIterations = 0;
  double adaptivity = 0;
  AnisotropicSurfaceSettings anisotropic;
};

struct CameraKey {
  double time = 0;
  Vec3d position{};
  Vec3d lookAt{};
};

struct Camera {
  Vec3d position{};
  Vec3d lookAt{};
  double fovDegrees = 0;  ///< vertical field of view
  std::vector<CameraKey> keyframes;
};

struct RenderSettings {
  int width = 0;
  int height = 0;
  int samples = 0;
  RenderSource source = RenderSource::Surface;
  ColorBy colorBy = ColorBy::Height;
  ImageFormat format = ImageFormat::Png;
  std::optional<Camera> camera;  ///< absent: automatic framing of the domain
};

struct Scene {
  int version = 1;
  std::string name;
  Domain domain;
  Vec3d gravity{};
  Fluid fluid;
  SolverSettings solver;
  TimeSettings time;
  std::vector<Collider> colliders;
  std::vector<Emitter> emitters;
  std::vector<KillBox> kill;
  Limits limits;
  Health health;
  CacheSettings cache;
  SurfaceSettings surface;
  RenderSettings render;

  /// Support radius of the SPH kernels (m).
  double kernelRadius() const { return solver.kernelSupport * fluid.spacing; }
  /// Mass of one particle (kg): rest density times the spacing cubed.
  double particleMass() const { return fluid.restDensity * fluid.spacing * fluid.spacing * fluid.spacing; }
  /// Simulated time of a frame number (the start frame is t = 0).
  double frameTime(int frame) const { return double(frame - time.startFrame) / time.fps; }
  bool hasCacheAttribute(CacheAttribute a) const;
  /// Speed of sound of the equation of state (m/s), which the acoustic CFL condition and the artificial
  /// viscosity read: solver.speed_of_sound under Tait, sqrt(stiffness) under the linear EOS.
  double soundSpeed() const;
  /// The walls' and colliders' viscosity term as a multiple of the fluid's (0: free slip, no wall term):
  /// fluid.wall_viscosity_factor under the laplacian model; under the artificial model that factor times
  /// fluid.wall_viscosity_speed over the fluid's artificial_viscosity times soundSpeed() (the scene check
  /// rejects a fluid alpha of 0 with walls that have a viscosity of their own).
  double wallViscosityMultiple() const;
  /// DFSPH's depth cap on the step in CFL mode (s): solver.dfsph.depth_step_factor times the spacing over
  /// sqrt(g H), g H = sum_k |g_k| (max_k - min_k) over the walled axes (the column's hydrostatic head);
  /// infinity without the cap (factor 0, no gravity against a wall, fixed steps or WCSPH).
  double dfsphDepthStep() const;
  /// True if the particle count can change during the run (emitters, kill boxes or open faces).
  bool changesParticleCount() const { return !emitters.empty() || !kill.empty() || !domain.open.empty(); }
};

/// The scene schema (all declarations). Used for validation, resolved output and docs.
const schema::Object<Scene>& sceneSchema();

/// Applies one "--set path=value" override to raw scene JSON. The path is dotted
/// ("fluid.viscosity", "fluid.blocks.0.min"); the value is parsed as JSON, or taken as a string if it is
/// not valid JSON ("solver.method=dfsph"). Missing objects on the way are created. Keys that moved
/// (migrateSceneJson) are moved first, in `raw` and in the path. Setting a method (solver.method,
/// surface.method) to another one drops the parameter groups of the other methods from `raw`, since
/// nothing would read them (and an unread parameter is an error): `--set solver.method=dfsph` on a WCSPH
/// scene runs it with DFSPH's defaults.
/// @throws InputError if the text has no '=' or the path runs through a non-object value.
void applyOverride(schema::Json& raw, const std::string& assignment);

/// applyOverride, unless the scene's other choices leave the key it sets unread (fluid.wall_drag under
/// viscosity_model "none"): then `raw` is left as it was and the result is false. Any other error of the
/// resulting scene is left for its own parse to report. Suites and studies apply their overrides so, to
/// leave one out of the runs whose settings do not read it.
/// @throws InputError as applyOverride.
bool applyOverrideIfRead(schema::Json& raw, const std::string& assignment);

/// Moves keys of older scene files to where they are declared now (solver.eos -> solver.wcsph.eos,
/// solver.max_iterations -> solver.dfsph.max_iterations, time.fall_factor -> solver.dfsph.fall_factor,
/// ...), logging a warning for each. `source` names the input in the warnings.
/// @throws InputError "SOURCE: /json/path: ..." if a key is given both at its old and its new place.
void migrateSceneJson(schema::Json& raw, const std::string& source);

/// Validates raw scene JSON (after migrateSceneJson) and returns the scene. `source` names the input in
/// error messages. A parameter that the scene's choices leave unread (a DFSPH parameter under WCSPH,
/// time.dt in CFL mode, fluid.viscosity with the artificial model) is an error.
/// @throws InputError "SOURCE: /json/path: what was expected, got what".
Scene parseScene(const schema::Json& raw, const std::string& source);

/// Reads, overrides and validates a scene file.
/// @throws InputError on unreadable files, JSON syntax errors and every validation failure.
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// The resolved scene as JSON, every default filled in. parseScene(sceneToJson(s)) == s.
schema::Json sceneToJson(const Scene& scene);

/// sceneToJson less the keys of features the scene does not use (no emitters, kill boxes or open faces,
/// keyframes without rotation, the default particle limit): what identifies a scene's results. Adding
/// a feature to sphfx leaves the identity of scenes that do not use it unchanged, so restart files and
/// committed study digests stay valid.
schema::Json sceneIdentityJson(const Scene& scene);

/// The parameter reference as Markdown (docs/scene-format.md is this text).
std::string sceneReferenceMarkdown();

/// Cells of size >= h along a periodic axis of `extent`: floor(extent / h) (the last cell takes the
/// remainder, so that the cells tile the period and a cell's neighbours across the seam are adjacent).
int periodicCells(double extent, double kernelRadius);

/// Number of particles the fluid blocks produce (same lattice as the simulator seeds).
size_t countInitialParticles(const Scene& scene);

/// Initial particles: a cubic lattice of `spacing`, cell-centred in each block, with the block's velocity.
struct SeededParticles {
  std::vector<std::array<float, 3>> position;
  std::vector<std::array<float, 3>> velocity;
};
SeededParticles seedParticles(const Scene& scene);

/// The lattice points of one layer of an emitter: a disc's points center + spacing (a u + b w) for
/// integers a, b within its radius, (u, w) an orthonormal basis of the disc's plane (emitterBasis()).
std::vector<Vec3d> emitterLayerPoints(const Scene& scene, const Emitter& emitter);
/// Unit vectors u, w spanning the plane normal to `direction` (unit): deterministic, right-handed.
std::array<Vec3d, 2> emitterBasis(const Vec3d& direction);
/// Layers an emitter emits over its active time: layer k leaves at start + k spacing / speed, for every
/// k with that time before end.
size_t emitterLayers(const Scene& scene, const Emitter& emitter);
/// Particles an emitter adds over its active time (layers x points per layer).
size_t countEmittedParticles(const Scene& scene, const Emitter& emitter);
/// The most particles the scene can hold at once: the initial ones plus all that its emitters add. The
/// GPU buffers are sized for it once.
size_t maxParticleCount(const Scene& scene);

}  // namespace sphfx
