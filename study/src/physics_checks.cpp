#include "sphfx/study/physics_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "sphfx/core/collider_motion.h"
#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"

namespace fs = std::filesystem;

namespace sphfx::study {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The rest criterion's bounds (issue-level acceptance figures, not fitted to a run): the surface may move
// less than half a spacing, the bulk density stays within 0.5 % of rest, and the settled flow's rms
// speed is below 1 % of sqrt(g H), i.e. KE/m < 0.5e-4 g H.
constexpr double kRestDriftSpacings = 0.5;
constexpr double kRestDensityTolerance = 0.005;
constexpr double kRestKineticFraction = 0.5e-4;
// A closed system may gain at most 1 % of g H per unit mass (time integration noise), never more.
constexpr double kEnergyGrowthFraction = 0.01;
// The last-resort clamp keeps centres 0.05 spacings from a wall; a gap under 0.1 spacings means the boundary
// model let the particle through and only the clamp held it.
constexpr double kMinWallGapSpacings = 0.1;

// Signed distance from collider c's surface, positive outside, at world point p for its pose.
double colliderDistance(const Collider& c, const ColliderPose& pose, const ColliderField* field,
                        const std::array<float, 3>& world) {
  const Vec3d p = pose.toRest({world[0], world[1], world[2]});
  if (c.isField()) return field ? field->sample(p) : kInfinity;
  if (c.shape == Shape::Sphere) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) d2 += std::pow(p[i] - c.center[i], 2);
    return std::sqrt(d2) - c.radius;
  }
  double outside2 = 0, inside = -kInfinity;
  for (int i = 0; i < 3; ++i) {
    const double d = std::max(c.min[i] - p[i], p[i] - c.max[i]);
    if (d > 0) outside2 += d * d;
    inside = std::max(inside, d);
  }
  return outside2 > 0 ? std::sqrt(outside2) : inside;
}

// The place of a point: the nearest wall face (periodic axes and open faces have none) or collider surface.
ParticlePlace placeOf(const Scene& scene, const std::vector<ColliderPose>& poses,
                      const std::vector<ColliderField>& fields, const std::array<float, 3>& p) {
  ParticlePlace place{p, kInfinity, -1};
  auto consider = [&](double d, int wall) {
    if (d < place.wallGap) place.wallGap = d, place.wall = wall;
  };
  for (int a = 0; a < 3; ++a) {
    if (scene.domain.isPeriodic(a)) continue;
    // An open face is no wall: fluid leaving through it is not pressed into anything.
    if (!scene.domain.isOpen(a, 0)) consider(p[a] - scene.domain.min[a], 2 * a);
    if (!scene.domain.isOpen(a, 1)) consider(scene.domain.max[a] - p[a], 2 * a + 1);
  }
  for (size_t c = 0; c < scene.colliders.size(); ++c)
    consider(colliderDistance(scene.colliders[c], poses[c], c < fields.size() ? &fields[c] : nullptr, p),
             6 + int(c));
  return place;
}

// "at (x, y, z) m, G spacings from the domain's x-max wall" ("collider c" for a collider; the position
// alone without walls).
std::string describePlace(const ParticlePlace& place, double spacing) {
  static const char* face[6] = {"x-min", "x-max", "y-min", "y-max", "z-min", "z-max"};
  const auto& p = place.centre;
  std::string text = fmt::format("at ({:.4f}, {:.4f}, {:.4f}) m", p[0], p[1], p[2]);
  if (place.wall >= 0)
    text += fmt::format(", {:.3f} spacings from {}", place.wallGap / spacing,
                        place.wall < 6 ? fmt::format("the domain's {} wall", face[place.wall])
                                       : fmt::format("collider {}", place.wall - 6));
  return text;
}

double surfaceHeightOf(const ParticleFrame& f, const Scene& scene) {
  const double s = scene.fluid.spacing;
  const double area =
      (scene.domain.max[0] - scene.domain.min[0]) * (scene.domain.max[2] - scene.domain.min[2]);
  std::vector<float> y(f.size());
  for (size_t i = 0; i < f.size(); ++i) y[i] = f.position[i][1];
  const size_t k = std::clamp<size_t>(size_t(std::lround(area / (s * s))), 1, y.size());
  std::nth_element(y.begin(), y.begin() + long(k - 1), y.end(), std::greater<float>());
  double sum = 0;
  for (size_t i = 0; i < k; ++i) sum += y[i];
  return sum / double(k) + 0.5 * s;
}

}  // namespace

ParticleBounds particleBounds(const Scene& scene) {
  return {kMinWallGapSpacings * scene.fluid.spacing, speedBound(scene)};
}

FrameState measureFrameState(const ParticleFrame& f, const Scene& scene, const ParticleBounds& bounds,
                             const std::vector<ColliderField>& fields) {
  FrameState st;
  st.frame = f.frame;
  st.time = f.time;
  st.particles = f.size();
  st.bulkDensityRatio = std::numeric_limits<double>::quiet_NaN();
  if (f.size() == 0) return st;
  const double g = -scene.gravity[1], floor = scene.domain.min[1], h = scene.kernelRadius();
  std::vector<ColliderPose> poses;
  for (const auto& c : scene.colliders) poses.push_back(colliderPose(c, f.time));
  st.surfaceHeight = surfaceHeightOf(f, scene);
  double kinetic = 0, potential = 0, bulk = 0;
  size_t bulkCount = 0;
  const bool haveDensity = f.density.size() == f.size();
  for (size_t i = 0; i < f.size(); ++i) {
    const auto& v = f.velocity[i];
    const double v2 = double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2];
    kinetic += 0.5 * v2;
    potential += g * (f.position[i][1] - floor);
    const ParticlePlace place = placeOf(scene, poses, fields, f.position[i]);
    const double gap = place.wallGap, speed = std::sqrt(v2);
    if (speed > st.maxSpeed || i == 0) {
      st.maxSpeed = speed;
      st.fastest = place;
    }
    if (gap < st.closest.wallGap) st.closest = place;
    st.closerThanBound += gap < bounds.wallGap ? 1 : 0;
    st.fasterThanBound += speed > bounds.speed ? 1 : 0;
    if (haveDensity && gap >= h && f.position[i][1] < st.surfaceHeight - h) {
      bulk += f.density[i];
      ++bulkCount;
    }
  }
  st.kineticPerMass = kinetic / double(f.size());
  st.energyPerMass = (kinetic + potential) / double(f.size());
  if (bulkCount) st.bulkDensityRatio = bulk / double(bulkCount) / scene.fluid.restDensity;
  return st;
}

std::vector<FrameState> measureShot(const std::string& shotDir, const Scene& scene) {
  std::vector<ColliderField> fields(scene.colliders.size());
  for (size_t c = 0; c < scene.colliders.size(); ++c)
    if (scene.colliders[c].isField())
      fields[c] =
          buildColliderField(scene.colliders[c], c, colliderFieldSpec(scene), colliderFieldPath(shotDir, c));
  const ParticleBounds bounds = particleBounds(scene);
  std::vector<FrameState> states;
  for (int frame : listFrames((fs::path(shotDir) / "cache").string(), "particles", "vdb"))
    states.push_back(
        measureFrameState(readParticleCache(particleCachePath(shotDir, frame)), scene, bounds, fields));
  return states;
}

Criterion parseCriterion(const std::string& name) {
  for (Criterion c : {Criterion::Rest, Criterion::Energy, Criterion::Walls, Criterion::Speed})
    if (name == toString(c)) return c;
  throw InputError("criterion: expected rest, energy, walls or speed, got \"" + name + "\"");
}

const char* toString(Criterion c) {
  switch (c) {
    case Criterion::Rest:
      return "rest";
    case Criterion::Energy:
      return "energy";
    case Criterion::Walls:
      return "walls";
    case Criterion::Speed:
      return "speed";
  }
  return "?";
}

double initialFluidHeight(const Scene& scene) {
  const SeededParticles seeds = seedParticles(scene);
  double top = scene.domain.min[1];
  for (const auto& p : seeds.position) top = std::max(top, double(p[1]) + 0.5 * scene.fluid.spacing);
  return top - scene.domain.min[1];
}

namespace {
// Largest distance from the pivot to the collider's surface: the lever arm of its rotation.
double colliderReach(const Collider& c) {
  const Vec3d pivot = colliderPivot(c);
  if (c.shape == Shape::Sphere) return c.radius;
  double r2 = 0;
  auto reach = [&](const Vec3d& p) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) d2 += (p[i] - pivot[i]) * (p[i] - pivot[i]);
    r2 = std::max(r2, d2);
  };
  if (c.shape == Shape::Box) {
    for (int k = 0; k < 8; ++k)
      reach({k & 1 ? c.max[0] : c.min[0], k & 2 ? c.max[1] : c.min[1], k & 4 ? c.max[2] : c.min[2]});
  } else {
    for (const auto& p : colliderRestMesh(c).positions) reach({p[0], p[1], p[2]});
  }
  return std::sqrt(r2);
}

// The largest material speed (|v| + |omega| r) of any collider at its keyframe intervals' midpoints: 0
// where every collider stays put.
double largestColliderSpeed(const Scene& scene) {
  double fastest = 0;
  for (const auto& c : scene.colliders)
    for (size_t k = 1; k < c.keyframes.size(); ++k) {
      const ColliderPose pose = colliderPose(c, 0.5 * (c.keyframes[k - 1].time + c.keyframes[k].time));
      const double w = std::sqrt(pose.angularVelocity[0] * pose.angularVelocity[0] +
                                 pose.angularVelocity[1] * pose.angularVelocity[1] +
                                 pose.angularVelocity[2] * pose.angularVelocity[2]);
      const double v = std::sqrt(pose.velocity[0] * pose.velocity[0] + pose.velocity[1] * pose.velocity[1] +
                                 pose.velocity[2] * pose.velocity[2]);
      fastest = std::max(fastest, v + (w > 0 ? w * colliderReach(c) : 0.0));
    }
  return fastest;
}
}  // namespace

double speedBound(const Scene& scene) {
  const double g = std::fabs(scene.gravity[1]);
  double initial = 0;
  for (const auto& v : seedParticles(scene).velocity)
    initial = std::max(initial, std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]));
  const double collider = largestColliderSpeed(scene);
  // Emitted fluid: its speed, plus the fall from the emitter's height (the same 2 sqrt(g H) allowance).
  double emitted = 0;
  for (const auto& e : scene.emitters)
    emitted =
        std::max(emitted, 2 * std::sqrt(g * std::max(e.center[1] - scene.domain.min[1], 0.0)) + e.speed);
  return std::max(2 * std::sqrt(g * initialFluidHeight(scene)) + initial, emitted) + collider;
}

namespace {

CriterionResult judgeRest(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Rest};
  const double s = scene.fluid.spacing, gH = std::fabs(scene.gravity[1]) * initialFluidHeight(scene);
  const double drift = std::fabs(st.back().surfaceHeight - st.front().surfaceHeight) / s;
  double worstDensity = 0;
  for (const auto& f : st)
    if (std::isfinite(f.bulkDensityRatio) && std::fabs(f.bulkDensityRatio - 1) >= std::fabs(worstDensity)) {
      worstDensity = f.bulkDensityRatio - 1;
      r.worstFrame = f.frame;
    }
  const bool haveDensity = std::isfinite(st.back().bulkDensityRatio);
  const size_t tail = std::max<size_t>(1, st.size() / 4);
  double kinetic = 0;
  for (size_t i = st.size() - tail; i < st.size(); ++i) kinetic += st[i].kineticPerMass;
  kinetic /= double(tail);
  const double kineticBound = kRestKineticFraction * gH;
  r.passed = drift < kRestDriftSpacings && haveDensity && std::fabs(worstDensity) <= kRestDensityTolerance &&
             kinetic < kineticBound;
  r.measured =
      fmt::format("surface drift {:.3f} spacings, bulk density {} (worst), KE/m {:.2e} J/kg (last quarter)",
                  drift, haveDensity ? fmt::format("{:+.2f} %", 100 * worstDensity) : "not cached", kinetic);
  r.bound = fmt::format("< {} spacings, within {:.1f} %, < {:.2e} J/kg", kRestDriftSpacings,
                        100 * kRestDensityTolerance, kineticBound);
  r.figure = fmt::format("drift {:.3f} spacings, bulk {}, KE/m {:.2e} J/kg (bound {:.2e})", drift,
                         haveDensity ? fmt::format("{:+.2f} %", 100 * worstDensity) : "not cached", kinetic,
                         kineticBound);
  return r;
}

CriterionResult judgeEnergy(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Energy};
  // The scale: g H, or without vertical gravity (a periodic vortex, say) the start's kinetic energy.
  const double gH = std::fabs(scene.gravity[1]) * initialFluidHeight(scene);
  const bool byHeight = gH > 0;
  const double scale = byHeight ? gH : std::fabs(st.front().energyPerMass);
  const char* unit = byHeight ? "g H" : "the starting E/m";
  double growth = -kInfinity;
  for (const auto& f : st)
    if (f.energyPerMass - st.front().energyPerMass > growth) {
      growth = f.energyPerMass - st.front().energyPerMass;
      r.worstFrame = f.frame;
    }
  r.passed = growth <= kEnergyGrowthFraction * scale;
  r.measured = fmt::format("largest gain {:+.3f} % of {} (E/m {:.4g} -> {:.4g} J/kg at the end)",
                           scale > 0 ? 100 * growth / scale : 0.0, unit, st.front().energyPerMass,
                           st.back().energyPerMass);
  r.bound = fmt::format("<= {:.0f} % of {}", 100 * kEnergyGrowthFraction, unit);
  r.figure = fmt::format("{:+.3f} % of {}", scale > 0 ? 100 * growth / scale : 0.0, unit);
  return r;
}

// How far a miss reaches: "; 3 particles faster than the bound in that frame (up to 5 in one), 2 frames
// with any" (empty where no particle breaks the bound: a pass).
std::string describeExtent(const std::vector<FrameState>& st, size_t FrameState::*count,
                           const FrameState& worst, const char* comparative) {
  size_t frames = 0, most = 0;
  for (const auto& f : st) {
    frames += f.*count > 0 ? 1 : 0;
    most = std::max(most, f.*count);
  }
  if (frames == 0) return "";
  const size_t n = worst.*count;
  return fmt::format("; {} particle{} {} than the bound in that frame (up to {} in one), {} frame{} with any",
                     n, n == 1 ? "" : "s", comparative, most, frames, frames == 1 ? "" : "s");
}

CriterionResult judgeWalls(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Walls};
  const FrameState* worst = &st.front();
  for (const auto& f : st)
    if (f.closest.wallGap < worst->closest.wallGap) worst = &f;
  r.worstFrame = worst->frame;
  const double s = scene.fluid.spacing;
  r.passed = worst->closest.wallGap >= kMinWallGapSpacings * s;
  r.measured = worst->closest.wall >= 0 ? "closest centre " + describePlace(worst->closest, s) : "no walls";
  r.measured += describeExtent(st, &FrameState::closerThanBound, *worst, "nearer");
  r.bound = fmt::format(">= {} spacings (rest: 0.5)", kMinWallGapSpacings);
  r.figure =
      worst->closest.wall >= 0 ? fmt::format("{:.3f} spacings", worst->closest.wallGap / s) : "no walls";
  return r;
}

CriterionResult judgeSpeed(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Speed};
  const FrameState* worst = &st.front();
  for (const auto& f : st)
    if (f.maxSpeed > worst->maxSpeed) worst = &f;
  r.worstFrame = worst->frame;
  const double bound = speedBound(scene);
  r.passed = worst->maxSpeed <= bound;
  r.measured = fmt::format("fastest {:.3f} m/s {}", worst->maxSpeed,
                           describePlace(worst->fastest, scene.fluid.spacing)) +
               describeExtent(st, &FrameState::fasterThanBound, *worst, "faster");
  r.bound = fmt::format("<= {:.3f} m/s", bound);
  r.figure = fmt::format("{:.3f} m/s (bound {:.3f})", worst->maxSpeed, bound);
  return r;
}

}  // namespace

CriterionResult judge(Criterion c, const std::vector<FrameState>& states, const Scene& scene) {
  if (states.empty()) return CriterionResult{c, false, "no frames", "", 0};
  // Rest and energy hold for closed systems only: fluid that enters or leaves brings or takes its energy
  // and moves the surface, and a moving collider's work enters the fluid.
  if (c == Criterion::Rest || c == Criterion::Energy) {
    const char* reason = scene.changesParticleCount() ? "emitters, kill boxes or open faces change the fluid"
                         : largestColliderSpeed(scene) > 0 ? "a moving collider does work on the fluid"
                                                           : nullptr;
    if (reason)
      return CriterionResult{c, true, fmt::format("not judged: {}", reason), "closed systems only", 0, false};
  }
  switch (c) {
    case Criterion::Rest:
      return judgeRest(states, scene);
    case Criterion::Energy:
      return judgeEnergy(states, scene);
    case Criterion::Walls:
      return judgeWalls(states, scene);
    case Criterion::Speed:
      return judgeSpeed(states, scene);
  }
  return {};
}

}  // namespace sphfx::study
