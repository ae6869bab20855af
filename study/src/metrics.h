#pragma once
/// @file metrics.h
/// @brief Error metrics computed from particle caches (the simulation stage's output on disk), plus the
/// numerical analysis a study reports: observed order of convergence and the Pareto front of error
/// against run time.

#include <cstddef>
#include <utility>
#include <vector>

#include "references.h"
#include "sphfx/core/particle_cache.h"

namespace sphfx::study {

/// Leading edge of a dam-break surge: the x of the k-th farthest particle from the wall behind the
/// column, k = 1 + N/2000, so that one stray droplet does not set the front; minus wallX.
double surgeFront(const ParticleFrame& frame, double wallX);

/// Height of the water at the wall: the top (y + spacing/2) of the k-th highest particle within `band`
/// of the wall, k = 1 + n/50, so that splash droplets falling past the wall do not count.
double columnHeightAtWall(const ParticleFrame& frame, double wallX, double band);

/// A simulated curve sample (dimensionless time, value).
struct CurveSample {
  double t;
  double value;
};

struct CurveError {
  double rms = 0;  ///< RMS of |sim - ref| / ref over the samples the table covers
  double max = 0;  ///< largest such relative error
  size_t samples = 0;
};

/// Compares a simulated curve with a reference table at the simulated samples whose time lies in the
/// table's range and at most tMax. Reference values are interpolated linearly.
CurveError relativeError(const std::vector<CurveSample>& simulated, const Table& reference, double tMax);

struct HydrostaticError {
  double pressureL2 = 0;  ///< ||p - rho0 g (H - y)|| / ||rho0 g (H - y)|| over particles below H - h
  /// The same norm of the pressure profile: the mean pressure of the particles in each slab h / 2 high
  /// against the mean reference at the same particles (the field, without the particle-scale noise).
  double profileL2 = 0;
  double meanDensityError = 0;  ///< mean(rho) / rho0 - 1
  double maxDensityError = 0;   ///< max |rho / rho0 - 1|
};

/// A resting column's pressure in horizontal slabs h / 2 high from the floor (y = 0) up to H - h: per slab
/// the sums of the particles' pressure and of the reference rho0 g (H - y) at the same particles, over
/// every frame add() was given (a time average when several are).
class PressureSlabs {
 public:
  PressureSlabs(double restDensity, double gravity, double surfaceHeight, double kernelRadius);
  /// Adds the frame's particles below H - h. @throws InputError if the frame lacks pressure.
  void add(const ParticleFrame& frame);
  /// ||slab mean - reference mean|| / ||reference mean|| over the slabs holding particles (0 if none).
  double profileError() const;
  /// Mean pressure over mean reference per slab (0 where a slab is empty).
  std::vector<double> ratios() const;
  double slabHeight() const { return slab_; }

 private:
  double rho0_, g_, H_, h_, slab_;
  std::vector<double> pressure_, reference_;
  std::vector<long> count_;
};

/// Hydrostatic errors; needs the cache's density and pressure attributes. Particles within one kernel
/// radius of the free surface are left out of the pressure norm (SPH kernels are truncated there).
/// @throws InputError if the frame lacks density or pressure.
HydrostaticError hydrostaticError(const ParticleFrame& frame, double restDensity, double gravity,
                                  double surfaceHeight, double kernelRadius);

/// Relative L2 error of the x velocity profile across the channel against poiseuilleVelocity(), with
/// particles averaged in `bins` slabs across y in [0, L].
double poiseuilleProfileError(const ParticleFrame& frame, double plateDistance, double bodyForce,
                              double viscosity, int bins);

/// Amplitude U of the Taylor-Green mode (references.h, taylorGreenAmplitude()) in a frame: the least-
/// squares fit of the particles' (u, w) onto (sin(kx x) cos(kz z), -(kx / kz) cos(kx x) sin(kz z)),
/// x and z measured from (x0, z0), over all particles. Velocity in other modes (the start's acoustic
/// waves, which are at 2 k) is orthogonal to it and does not count.
double taylorGreenModeAmplitude(const ParticleFrame& frame, double x0, double z0, double periodX,
                                double periodZ);

/// Kinetic energy sum m |v|^2 / 2 and potential energy sum m g y (J), for energy-drift reports.
double kineticEnergy(const ParticleFrame& frame, double particleMass);
double potentialEnergy(const ParticleFrame& frame, double particleMass, double gravity);

/// Observed order of convergence p from errors e(h) ~ C h^p: the least-squares slope of log e against
/// log h over all points (at least two, h and e positive). @throws InputError otherwise.
double observedOrder(const std::vector<std::pair<double, double>>& spacingAndError);

/// Indices of the points (cost, error) that no other point beats in both (lower cost and lower error),
/// sorted by cost. Ties: a point is dominated only by one at least as good in both and better in one.
std::vector<size_t> paretoFront(const std::vector<std::pair<double, double>>& costAndError);

}  // namespace sphfx::study
