#pragma once
/// @file physics_checks.h
/// @brief Physical state of cached frames and the acceptance criteria the stability suite judges runs by:
/// water at rest stays at rest, a closed system does not gain energy, nothing enters a wall, nothing moves
/// faster than the flow can make it. Everything is computed from the particle caches alone.

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"

namespace sphfx::study {

/// Where one particle is: its centre and the nearest wall face (not a periodic or open one) or collider
/// surface to it.
struct ParticlePlace {
  std::array<float, 3> centre{};                             ///< m
  double wallGap = std::numeric_limits<double>::infinity();  ///< to that wall or surface (m); none: infinity
  int wall = -1;  ///< 2 axis + side for a face of the domain, 6 + c for collider c; -1: none
};

/// What one cached frame says about the physics.
struct FrameState {
  int frame = 0;
  double time = 0;
  size_t particles = 0;
  double kineticPerMass = 0;  ///< mean |v|^2 / 2 (J/kg)
  double energyPerMass = 0;   ///< mean |v|^2 / 2 + g (y - floor) (J/kg)
  double maxSpeed = 0;        ///< m/s
  /// The fastest particle's place: a jet up a wall reads apart from a splash in the open.
  ParticlePlace fastest;
  /// Mean top (y + s/2) of the highest A / s^2 particles, A the domain's x-z footprint: the free
  /// surface of a tank that covers its floor (m).
  double surfaceHeight = 0;
  /// Mean density / rest density of the bulk: particles at least one kernel radius from every wall and
  /// collider and below surfaceHeight - h. NaN when the cache has no density or no particle qualifies.
  double bulkDensityRatio = 0;
  /// The particle whose centre is closest to a wall face or collider surface; its wallGap is s/2 at rest
  /// on the initial lattice.
  ParticlePlace closest;
  /// How many particles break the walls and speed criteria's bounds (ParticleBounds) in this frame: a lone
  /// stray reads apart from a sheet.
  size_t closerThanBound = 0;
  size_t fasterThanBound = 0;
};

/// The per-particle bounds of the walls and speed criteria for a scene.
struct ParticleBounds {
  double wallGap = 0;                                      ///< closest a centre may come to a wall (m)
  double speed = std::numeric_limits<double>::infinity();  ///< speedBound() (m/s)
};

/// @throws as seedParticles (the speed bound reads the initial fluid).
ParticleBounds particleBounds(const Scene& scene);

/// `bounds`: particleBounds(scene), which FrameState counts particles against. `fields` holds the mesh
/// and vdb colliders' distance fields by collider index (measureShot builds them); a field collider
/// without one is left out of the wall gap.
/// @throws nothing; an empty frame gives zeros (gap: infinity).
FrameState measureFrameState(const ParticleFrame& frame, const Scene& scene, const ParticleBounds& bounds,
                             const std::vector<ColliderField>& fields = {});

/// Every cached frame of a shot, in frame order. Mesh and vdb colliders' fields are the ones the
/// simulation cached in the shot (built again if absent).
/// @throws IoError, InputError as readParticleCache and buildColliderField.
std::vector<FrameState> measureShot(const std::string& shotDir, const Scene& scene);

/// The criteria a stability case may ask for (StabilityCase::criteria names them).
enum class Criterion {
  Rest,    ///< surface height drift < s/2, bulk density within 0.5 %, kinetic energy settles
  Energy,  ///< a closed system: total energy never grows by more than 1 % of g H
  Walls,   ///< no particle centre closer than 0.1 spacings to a wall or collider surface
  Speed    ///< no particle faster than speedBound()
};

/// "rest", "energy", "walls", "speed".
/// @throws InputError for other names.
Criterion parseCriterion(const std::string& name);
const char* toString(Criterion c);

/// One criterion's verdict with its measured figure and bound, as the report prints them.
struct CriterionResult {
  Criterion criterion{};
  bool passed = false;
  std::string measured;  ///< e.g. "surface drift 0.120 spacings, bulk density -0.21 % (worst), ..."
  std::string bound;     ///< e.g. "< 0.5 spacings, within 0.5 %, < 1.50e-04 J/kg"
  int worstFrame = 0;    ///< where the measured figure is worst
  /// false where the criterion does not apply to the scene (then `passed` is true and `measured` says why):
  /// rest and energy in a scene whose emitters, kill boxes or open faces change its fluid, or whose
  /// colliders move (their work enters the fluid).
  bool judged = true;
  /// The measured figure alone, for a table of runs: e.g. "0.222 spacings" (walls), "2.877 m/s" (speed).
  std::string figure;
};

/// Judges `states` (measureShot of a completed run) by `c`. Rest compares the first and last frames
/// and, for the kinetic energy, the mean over the last quarter of the run.
CriterionResult judge(Criterion c, const std::vector<FrameState>& states, const Scene& scene);

/// Height of the fluid above the floor at the start: the highest initial particle top minus domain
/// min y (m). The scale of every bound above.
double initialFluidHeight(const Scene& scene);

/// 2 sqrt(g H) (Ritter's dam-break front speed, the fastest a gravity flow from rest of depth H runs)
/// plus the largest initial particle speed, or for emitted fluid 2 sqrt(g H_e) plus the emitter's speed
/// (H_e its height above the floor), whichever is larger; plus the largest collider material speed
/// (|v| + |omega| r) (m/s).
double speedBound(const Scene& scene);

}  // namespace sphfx::study
