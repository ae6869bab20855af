#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sphfx/core/error.h"

namespace sphfx::study {

double surgeFront(const ParticleFrame& frame, double wallX) {
  if (frame.size() == 0) return 0;
  std::vector<float> x(frame.size());
  for (size_t i = 0; i < frame.size(); ++i) x[i] = frame.position[i][0];
  const size_t k = std::min(x.size(), 1 + x.size() / 2000);
  std::nth_element(x.begin(), x.begin() + long(k - 1), x.end(), std::greater<float>());
  return double(x[k - 1]) + 0.5 * frame.particleSpacing - wallX;
}

double columnHeightAtWall(const ParticleFrame& frame, double wallX, double band) {
  std::vector<float> y;
  for (const auto& p : frame.position)
    if (p[0] - wallX <= band) y.push_back(p[1]);
  if (y.empty()) return 0;
  // The k-th highest, k = 1 + n/50: droplets falling back past the wall do not set the water height.
  const size_t k = std::min(y.size(), 1 + y.size() / 50);
  std::nth_element(y.begin(), y.begin() + long(k - 1), y.end(), std::greater<float>());
  return double(y[k - 1]) + 0.5 * frame.particleSpacing;
}

CurveError relativeError(const std::vector<CurveSample>& simulated, const Table& reference, double tMax) {
  CurveError e;
  double sum = 0;
  for (const auto& s : simulated) {
    if (s.t > tMax || !reference.covers(s.t)) continue;
    const double ref = reference.at(s.t);
    const double rel = std::fabs(s.value - ref) / std::fabs(ref);
    sum += rel * rel;
    e.max = std::max(e.max, rel);
    ++e.samples;
  }
  e.rms = e.samples ? std::sqrt(sum / double(e.samples)) : 0;
  return e;
}

PressureSlabs::PressureSlabs(double rho0, double g, double H, double h)
    : rho0_(rho0), g_(g), H_(H), h_(h), slab_(h / 2) {
  const size_t slabs = size_t(std::max(1.0, std::ceil((H - h) / slab_)));
  pressure_.assign(slabs, 0);
  reference_.assign(slabs, 0);
  count_.assign(slabs, 0);
}

void PressureSlabs::add(const ParticleFrame& f) {
  if (f.pressure.size() != f.size())
    throw InputError("hydrostatic pressure: the cache lacks pressure (set cache.attributes)");
  for (size_t i = 0; i < f.size(); ++i) {
    const double y = f.position[i][1];
    if (y > H_ - h_) continue;
    const size_t b = std::min(count_.size() - 1, size_t(std::max(0.0, y / slab_)));
    pressure_[b] += f.pressure[i];
    reference_[b] += hydrostaticPressure(rho0_, g_, H_, y);
    ++count_[b];
  }
}

double PressureSlabs::profileError() const {
  double num = 0, den = 0;
  for (size_t b = 0; b < count_.size(); ++b) {
    if (count_[b] == 0) continue;
    const double sim = pressure_[b] / double(count_[b]), ref = reference_[b] / double(count_[b]);
    num += (sim - ref) * (sim - ref);
    den += ref * ref;
  }
  return den > 0 ? std::sqrt(num / den) : 0;
}

std::vector<double> PressureSlabs::ratios() const {
  std::vector<double> r(count_.size(), 0);
  for (size_t b = 0; b < count_.size(); ++b)
    if (count_[b] > 0 && reference_[b] != 0) r[b] = pressure_[b] / reference_[b];
  return r;
}

HydrostaticError hydrostaticError(const ParticleFrame& f, double rho0, double g, double H, double h) {
  if (f.density.size() != f.size() || f.pressure.size() != f.size())
    throw InputError("hydrostatic error: the cache lacks density or pressure (set cache.attributes)");
  HydrostaticError e;
  double num = 0, den = 0, densitySum = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    densitySum += f.density[i];
    e.maxDensityError = std::max(e.maxDensityError, std::fabs(f.density[i] / rho0 - 1));
    const double y = f.position[i][1];
    if (y > H - h) continue;
    const double ref = hydrostaticPressure(rho0, g, H, y);
    num += (f.pressure[i] - ref) * (f.pressure[i] - ref);
    den += ref * ref;
  }
  e.pressureL2 = den > 0 ? std::sqrt(num / den) : 0;
  PressureSlabs slabs(rho0, g, H, h);
  slabs.add(f);
  e.profileL2 = slabs.profileError();
  e.meanDensityError = f.size() ? densitySum / double(f.size()) / rho0 - 1 : 0;
  return e;
}

double poiseuilleProfileError(const ParticleFrame& f, double L, double F, double nu, int bins) {
  // Each slab compares the mean simulated velocity with the mean reference at the same particles, so
  // the profile's curvature inside a slab does not bias the error.
  std::vector<double> sum(size_t(bins), 0), refSum(size_t(bins), 0);
  std::vector<int> count(size_t(bins), 0);
  for (size_t i = 0; i < f.size(); ++i) {
    const double y = f.position[i][1];
    const int b = std::clamp(int(y / L * bins), 0, bins - 1);
    sum[size_t(b)] += f.velocity[i][0];
    refSum[size_t(b)] += poiseuilleVelocity(std::clamp(y, 0.0, L), f.time, L, F, nu);
    ++count[size_t(b)];
  }
  double num = 0, den = 0;
  for (size_t b = 0; b < size_t(bins); ++b) {
    if (count[b] == 0) continue;
    const double ref = refSum[b] / count[b];
    const double sim = sum[b] / count[b];
    num += (sim - ref) * (sim - ref);
    den += ref * ref;
  }
  return den > 0 ? std::sqrt(num / den) : 0;
}

double taylorGreenModeAmplitude(const ParticleFrame& f, double x0, double z0, double lx, double lz) {
  double num = 0, den = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    const double ax = 2 * M_PI * (f.position[i][0] - x0) / lx, az = 2 * M_PI * (f.position[i][2] - z0) / lz;
    const double bu = std::sin(ax) * std::cos(az), bw = -(lz / lx) * std::cos(ax) * std::sin(az);
    num += f.velocity[i][0] * bu + f.velocity[i][2] * bw;
    den += bu * bu + bw * bw;
  }
  return den > 0 ? num / den : 0;
}

double kineticEnergy(const ParticleFrame& f, double m) {
  double e = 0;
  for (const auto& v : f.velocity)
    e += 0.5 * m * (double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
  return e;
}

double potentialEnergy(const ParticleFrame& f, double m, double g) {
  double e = 0;
  for (const auto& p : f.position) e += m * g * p[1];
  return e;
}

double observedOrder(const std::vector<std::pair<double, double>>& he) {
  if (he.size() < 2) throw InputError("observed order: needs errors at two or more spacings");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& [h, e] : he) {
    if (!(h > 0) || !(e > 0)) throw InputError("observed order: spacings and errors must be positive");
    const double x = std::log(h), y = std::log(e);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = double(he.size());
  const double denom = n * sxx - sx * sx;
  if (denom == 0) throw InputError("observed order: all spacings are equal");
  return (n * sxy - sx * sy) / denom;
}

std::vector<size_t> paretoFront(const std::vector<std::pair<double, double>>& ce) {
  std::vector<size_t> front;
  for (size_t i = 0; i < ce.size(); ++i) {
    bool dominated = false;
    for (size_t j = 0; j < ce.size() && !dominated; ++j)
      dominated = j != i && ce[j].first <= ce[i].first && ce[j].second <= ce[i].second &&
                  (ce[j].first < ce[i].first || ce[j].second < ce[i].second);
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](size_t a, size_t b) { return ce[a].first < ce[b].first; });
  return front;
}

}  // namespace sphfx::study
