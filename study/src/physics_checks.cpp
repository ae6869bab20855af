#include "sphfx/study/physics_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

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
// The last-resort clamp keeps centres 0.05 s from a wall; a gap under 0.1 s means the boundary model
// let the particle through and only the clamp held it.
constexpr double kMinWallGapSpacings = 0.1;

Vec3d colliderOffset(const Collider& c, double t) {
  if (c.keyframes.empty()) return {0, 0, 0};
  if (t <= c.keyframes.front().time) return c.keyframes.front().offset;
  for (size_t k = 1; k < c.keyframes.size(); ++k) {
    const Keyframe &a = c.keyframes[k - 1], &b = c.keyframes[k];
    if (t < b.time) {
      const double s = (t - a.time) / (b.time - a.time);
      Vec3d o{};
      for (int i = 0; i < 3; ++i) o[i] = a.offset[i] + s * (b.offset[i] - a.offset[i]);
      return o;
    }
  }
  return c.keyframes.back().offset;
}

// Signed distance from the collider's surface, positive outside.
double colliderDistance(const Collider& c, const Vec3d& offset, const std::array<float, 3>& p) {
  if (c.shape == Shape::Sphere) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) d2 += std::pow(p[i] - c.center[i] - offset[i], 2);
    return std::sqrt(d2) - c.radius;
  }
  double outside2 = 0, inside = -kInfinity;
  for (int i = 0; i < 3; ++i) {
    const double lo = c.min[i] + offset[i] - p[i], hi = p[i] - c.max[i] - offset[i];
    const double d = std::max(lo, hi);
    if (d > 0) outside2 += d * d;
    inside = std::max(inside, d);
  }
  return outside2 > 0 ? std::sqrt(outside2) : inside;
}

// Distance from p to the nearest wall face (periodic axes have none) and collider surface.
double wallGap(const Scene& scene, const std::vector<Vec3d>& offsets, const std::array<float, 3>& p) {
  double gap = kInfinity;
  for (int a = 0; a < 3; ++a) {
    if (scene.domain.isPeriodic(a)) continue;
    gap = std::min({gap, p[a] - scene.domain.min[a], scene.domain.max[a] - p[a]});
  }
  for (size_t c = 0; c < scene.colliders.size(); ++c)
    gap = std::min(gap, colliderDistance(scene.colliders[c], offsets[c], p));
  return gap;
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

FrameState measureFrameState(const ParticleFrame& f, const Scene& scene) {
  FrameState st;
  st.frame = f.frame;
  st.time = f.time;
  st.particles = f.size();
  st.minWallGap = kInfinity;
  st.bulkDensityRatio = std::numeric_limits<double>::quiet_NaN();
  if (f.size() == 0) return st;
  const double g = -scene.gravity[1], floor = scene.domain.min[1], h = scene.kernelRadius();
  std::vector<Vec3d> offsets;
  for (const auto& c : scene.colliders) offsets.push_back(colliderOffset(c, f.time));
  st.surfaceHeight = surfaceHeightOf(f, scene);
  double kinetic = 0, potential = 0, bulk = 0;
  size_t bulkCount = 0;
  const bool haveDensity = f.density.size() == f.size();
  for (size_t i = 0; i < f.size(); ++i) {
    const auto& v = f.velocity[i];
    const double v2 = double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2];
    kinetic += 0.5 * v2;
    potential += g * (f.position[i][1] - floor);
    st.maxSpeed = std::max(st.maxSpeed, std::sqrt(v2));
    const double gap = wallGap(scene, offsets, f.position[i]);
    st.minWallGap = std::min(st.minWallGap, gap);
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
  std::vector<FrameState> states;
  for (int frame : listFrames((fs::path(shotDir) / "cache").string(), "particles", "vdb"))
    states.push_back(measureFrameState(readParticleCache(particleCachePath(shotDir, frame)), scene));
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

double speedBound(const Scene& scene) {
  const double g = std::fabs(scene.gravity[1]);
  double initial = 0, collider = 0;
  for (const auto& v : seedParticles(scene).velocity)
    initial = std::max(initial, std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]));
  for (const auto& c : scene.colliders)
    for (size_t k = 1; k < c.keyframes.size(); ++k) {
      double d2 = 0;
      for (int i = 0; i < 3; ++i) d2 += std::pow(c.keyframes[k].offset[i] - c.keyframes[k - 1].offset[i], 2);
      collider = std::max(collider, std::sqrt(d2) / (c.keyframes[k].time - c.keyframes[k - 1].time));
    }
  return 2 * std::sqrt(g * initialFluidHeight(scene)) + initial + collider;
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
      fmt::format("surface drift {:.3f} s, bulk density {} (worst), KE/m {:.2e} J/kg (last quarter)", drift,
                  haveDensity ? fmt::format("{:+.2f} %", 100 * worstDensity) : "not cached", kinetic);
  r.bound = fmt::format("< {} s, within {:.1f} %, < {:.2e} J/kg", kRestDriftSpacings,
                        100 * kRestDensityTolerance, kineticBound);
  return r;
}

CriterionResult judgeEnergy(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Energy};
  const double gH = std::fabs(scene.gravity[1]) * initialFluidHeight(scene);
  double growth = -kInfinity;
  for (const auto& f : st)
    if (f.energyPerMass - st.front().energyPerMass > growth) {
      growth = f.energyPerMass - st.front().energyPerMass;
      r.worstFrame = f.frame;
    }
  r.passed = growth <= kEnergyGrowthFraction * gH;
  r.measured = fmt::format("largest gain {:+.3f} % of g H (E/m {:.4g} -> {:.4g} J/kg at the end)",
                           100 * growth / gH, st.front().energyPerMass, st.back().energyPerMass);
  r.bound = fmt::format("<= {:.0f} % of g H", 100 * kEnergyGrowthFraction);
  return r;
}

CriterionResult judgeWalls(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Walls};
  double gap = kInfinity;
  for (const auto& f : st)
    if (f.minWallGap < gap) {
      gap = f.minWallGap;
      r.worstFrame = f.frame;
    }
  const double s = scene.fluid.spacing;
  r.passed = gap >= kMinWallGapSpacings * s;
  r.measured = std::isfinite(gap) ? fmt::format("closest centre {:.3f} s from a wall", gap / s) : "no walls";
  r.bound = fmt::format(">= {} s (rest: 0.5 s)", kMinWallGapSpacings);
  return r;
}

CriterionResult judgeSpeed(const std::vector<FrameState>& st, const Scene& scene) {
  CriterionResult r{Criterion::Speed};
  double fastest = 0;
  for (const auto& f : st)
    if (f.maxSpeed > fastest) {
      fastest = f.maxSpeed;
      r.worstFrame = f.frame;
    }
  const double bound = speedBound(scene);
  r.passed = fastest <= bound;
  r.measured = fmt::format("fastest {:.3f} m/s", fastest);
  r.bound = fmt::format("<= {:.3f} m/s", bound);
  return r;
}

}  // namespace

CriterionResult judge(Criterion c, const std::vector<FrameState>& states, const Scene& scene) {
  if (states.empty()) return CriterionResult{c, false, "no frames", "", 0};
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
