// Fastest particles of a shot's cache frames: how many exceed 3 and 5 m/s, and the fastest few with
// their positions and velocities. The CFL step (0.4 d / |v|max) follows the single fastest particle,
// so this shows what sets a run's step count (docs/performance.md, "Simulation"). With --densest N also the
// N densest particles (the cache must store `density`, scene cache.attributes): where a run that stops
// on health.max_density_ratio compresses (docs/validation.md, "Known limits"). With --near-walls the number
// of particles within 0.1 and 0.25 spacings of the domain's walls (the shot's manifest.json gives the domain;
// a resting first layer sits at 0.5 spacings): how deep the fluid is pressed into the walls
// (docs/design.md, "Boundaries"), and the five closest particles with their wall (and with a cached
// `density` their density: a thin sheet pressed into a wall sums well below rest). With --layers, for a
// fluid at rest that fills the domain's floor: the particles sorted by height in layers of A / s^2 (A the
// floor's area), each layer's mean height, and the gaps between them in spacings: how much of a resting
// column's surface drift is the bottom layer's, the bulk's compression and the top layer's, and with a
// cached `density` how much of the compression the solver's density sum sees, how much of the cubic
// lattice each part keeps, and how each part moves: its mean vertical velocity (the part rising or sinking
// as a whole) against its RMS speed (any motion, a jitter in place included) (docs/validation.md, "Known
// limits").
//   cache_speeds SHOT FRAME... [--top N] [--densest N] [--near-walls] [--layers]
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sphfx/core/manifest.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"

namespace {

float speed(const std::array<float, 3>& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// Indices of the `count` particles with the largest key, largest first.
template <class Key>
std::vector<size_t> largest(size_t n, size_t count, Key key) {
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  const size_t shown = std::min(count, n);
  std::partial_sort(order.begin(), order.begin() + long(shown), order.end(),
                    [&](size_t a, size_t b) { return key(a) > key(b); });
  order.resize(shown);
  return order;
}

// With `density`, also the particle's cached density where the cache stores it.
void printParticle(const char* label, float value, const sphfx::ParticleFrame& f, size_t i,
                   bool density = false) {
  const auto& p = f.position[i];
  const auto& v = f.velocity[i];
  std::printf("  %s %7.2f  x (%7.4f %7.4f %7.4f)  v (%6.2f %6.2f %6.2f)", label, value, p[0], p[1], p[2],
              v[0], v[1], v[2]);
  if (density && f.density.size() == f.size()) std::printf("  rho %.1f", double(f.density[i]));
  std::printf("\n");
}

// The shot's domain, from the scene its manifest records (sphfx simulate writes it).
sphfx::Domain readDomain(const std::string& shot) {
  const sphfx::ManifestJson m = sphfx::readManifest(shot);
  if (!m.contains("simulate") || !m["simulate"].contains("scene"))
    throw std::runtime_error(sphfx::manifestPath(shot) +
                             ": no simulate.scene (--near-walls and --layers read the domain there)");
  return sphfx::parseScene(m["simulate"]["scene"], sphfx::manifestPath(shot) + " (simulate.scene)").domain;
}

// The nearest wall (0 x-min, 1 x-max, 2 y-min, ...) and the distance to it in particle spacings.
// Periodic axes have no walls.
std::pair<size_t, double> nearestWall(const sphfx::Domain& w, const std::array<float, 3>& p, double spacing) {
  std::pair<size_t, double> nearest{0, INFINITY};
  for (int a = 0; a < 3; ++a) {
    if (w.isPeriodic(a)) continue;
    const double low = double(p[size_t(a)]) - w.min[size_t(a)],
                 high = w.max[size_t(a)] - double(p[size_t(a)]);
    if (low < nearest.second) nearest = {size_t(2 * a), low};
    if (high < nearest.second) nearest = {size_t(2 * a + 1), high};
  }
  return {nearest.first, nearest.second / spacing};
}

void reportNearWalls(const sphfx::Domain& w, const sphfx::ParticleFrame& f) {
  static const char* names[6] = {"x-min", "x-max", "y-min", "y-max", "z-min", "z-max"};
  std::array<size_t, 6> within01{}, within025{};
  for (const auto& p : f.position) {
    const auto [wall, d] = nearestWall(w, p, f.particleSpacing);
    within01[wall] += d < 0.1;
    within025[wall] += d < 0.25;
  }
  auto line = [&](const char* label, const std::array<size_t, 6>& count) {
    std::printf("  within %s spacings of a wall: %zu (", label,
                std::accumulate(count.begin(), count.end(), size_t(0)));
    for (size_t k = 0; k < 6; ++k) std::printf("%s%s %zu", k ? ", " : "", names[k], count[k]);
    std::printf(")\n");
  };
  line("0.1", within01);
  line("0.25", within025);
  // The closest few, with where they are: which wall, and whether at a face, an edge or a corner.
  const std::vector<size_t> closest = largest(
      f.size(), 5, [&](size_t i) { return -nearestWall(w, f.position[i], f.particleSpacing).second; });
  for (size_t i : closest) {
    const auto [wall, d] = nearestWall(w, f.position[i], f.particleSpacing);
    std::printf("  %s", names[wall]);
    printParticle("spacings", float(d), f, i, true);
  }
}

double mean(const std::vector<double>& v, size_t first, size_t last) {
  return std::accumulate(v.begin() + long(first), v.begin() + long(last), 0.0) / double(last - first);
}

// Layer bounds of the lower, middle and upper third of the column and the top layer: part p holds
// layers parts[p] .. parts[p + 1] - 1.
using LayerParts = std::array<size_t, 5>;

// How much of the starting cubic lattice a layer keeps along a horizontal axis: |mean exp(2 pi i x / s)|
// over its particles, 1 on the lattice, 0 where half its rows have shifted half a spacing (or where it
// has no order left). A layer's order is the smaller of its x and z figures.
double layerLatticeOrder(const sphfx::Domain& w, const sphfx::ParticleFrame& f,
                         const std::vector<size_t>& order, size_t first, size_t last) {
  const double s = f.particleSpacing, twoPi = 2 * std::numbers::pi;
  double result = 1;
  for (int a : {0, 2}) {
    double c = 0, sn = 0;
    for (size_t k = first; k < last; ++k) {
      const double phase = twoPi * (double(f.position[order[k]][size_t(a)]) - w.min[size_t(a)]) / s;
      c += std::cos(phase);
      sn += std::sin(phase);
    }
    result = std::min(result, std::hypot(c, sn) / double(last - first));
  }
  return result;
}

// The layers' mean lattice order in each of `parts` (layer bounds, LayerParts): whether a column's
// compression came with the lattice giving way.
void reportLatticeOrder(const sphfx::Domain& w, const sphfx::ParticleFrame& f,
                        const std::vector<size_t>& order, size_t floorCount, const LayerParts& parts) {
  double value[4];
  for (size_t p = 0; p < 4; ++p) {
    double sum = 0;
    for (size_t k = parts[p]; k < parts[p + 1]; ++k)
      sum += layerLatticeOrder(w, f, order, k * floorCount, (k + 1) * floorCount);
    value[p] = sum / double(parts[p + 1] - parts[p]);
  }
  std::printf(
      "  lattice order (1: cubic, 0: rows shifted half a spacing): lower third %.3f, middle %.3f, "
      "upper third %.3f, top layer %.3f\n",
      value[0], value[1], value[2], value[3]);
}

// Each part's mean vertical velocity and RMS speed (m/s): a part that moves as a whole has the two alike, a
// jitter in place an RMS speed well above its mean.
void reportLayerMotion(const sphfx::ParticleFrame& f, const std::vector<size_t>& order, size_t floorCount,
                       const LayerParts& parts) {
  double up[4], rms[4];
  for (size_t p = 0; p < 4; ++p) {
    const size_t first = parts[p] * floorCount, last = parts[p + 1] * floorCount;
    double vy = 0, v2 = 0;
    for (size_t k = first; k < last; ++k) {
      const auto& v = f.velocity[order[k]];
      vy += v[1];
      v2 += double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2];
    }
    up[p] = vy / double(last - first);
    rms[p] = std::sqrt(v2 / double(last - first));
  }
  std::printf(
      "  motion (m/s): mean v_y lower third %.4f, middle %.4f, upper third %.4f, top layer %.4f; RMS speed "
      "%.4f, %.4f, %.4f, %.4f\n",
      up[0], up[1], up[2], up[3], rms[0], rms[1], rms[2], rms[3]);
}

// Layers of floorCount particles by height: the bottom layer above the floor, the mean gap between
// neighbouring layers in the lower, middle and upper third of the column, and the top layer's gap;
// each part's lattice order and motion; and with a cached `density`, each part's mean density, which says
// how much of the gaps' compression the solver's density sum sees.
void reportLayers(const sphfx::Domain& w, const sphfx::ParticleFrame& f) {
  const double s = f.particleSpacing;
  const auto floorCount = size_t(std::lround((w.max[0] - w.min[0]) * (w.max[2] - w.min[2]) / (s * s)));
  const size_t layers = floorCount ? f.size() / floorCount : 0;
  if (layers < 6) throw std::runtime_error("--layers needs at least 6 layers of A / s^2 particles");
  std::vector<size_t> order(f.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return f.position[a][1] < f.position[b][1]; });
  std::vector<double> y(f.size()), rho(f.density.empty() ? 0 : f.size());
  for (size_t k = 0; k < order.size(); ++k) {
    y[k] = (double(f.position[order[k]][1]) - w.min[1]) / s;
    if (!rho.empty()) rho[k] = f.density[order[k]];
  }
  std::vector<double> height(layers), gap(layers - 1);
  for (size_t k = 0; k < layers; ++k) height[k] = mean(y, k * floorCount, (k + 1) * floorCount);
  for (size_t k = 0; k + 1 < layers; ++k) gap[k] = height[k + 1] - height[k];
  const size_t inner = layers - 2, third = inner / 3;  // gaps 0 .. layers - 3: below the top layer
  std::printf(
      "  layers %zu of %zu particles: bottom %.4f s above the floor, top %.4f s; gaps (s): lower "
      "third %.4f, middle %.4f, upper third %.4f, top layer %.4f\n",
      layers, floorCount, height[0], height[layers - 1], mean(gap, 0, third), mean(gap, third, inner - third),
      mean(gap, inner - third, inner), gap[layers - 2]);
  // Layer k's particles are k * floorCount .. (k + 1) * floorCount; gap k lies between layers k and k + 1.
  const LayerParts parts = {0, third + 1, inner - third + 1, layers - 1, layers};
  reportLatticeOrder(w, f, order, floorCount, parts);
  reportLayerMotion(f, order, floorCount, parts);
  if (rho.empty()) return;
  auto partDensity = [&](size_t p) { return mean(rho, parts[p] * floorCount, parts[p + 1] * floorCount); };
  std::printf("  cached density (kg/m^3): lower third %.2f, middle %.2f, upper third %.2f, top layer %.2f\n",
              partDensity(0), partDensity(1), partDensity(2), partDensity(3));
}

void report(const std::string& shot, int frameNumber, size_t top, size_t densest, const sphfx::Domain& domain,
            bool nearWalls, bool layers) {
  const std::string path = sphfx::particleCachePath(shot, frameNumber);
  const sphfx::ParticleFrame f = sphfx::readParticleCache(path);
  const std::vector<size_t> fastest = largest(f.size(), top, [&](size_t i) { return speed(f.velocity[i]); });
  size_t over3 = 0, over5 = 0;
  for (const auto& v : f.velocity) {
    over3 += speed(v) > 3.0f;
    over5 += speed(v) > 5.0f;
  }
  std::printf("frame %d  t %.3f s  particles %zu  |v| > 3 m/s: %zu  |v| > 5 m/s: %zu\n", frameNumber, f.time,
              f.size(), over3, over5);
  for (size_t i : fastest) printParticle("|v|", speed(f.velocity[i]), f, i);
  if (nearWalls) reportNearWalls(domain, f);
  if (layers) reportLayers(domain, f);
  if (densest == 0) return;
  if (f.density.size() != f.size())
    throw std::runtime_error(path + " stores no density: add \"density\" to the scene's cache.attributes");
  std::printf("  densest (kg/m^3):\n");
  for (size_t i : largest(f.size(), densest, [&](size_t k) { return f.density[k]; }))
    printParticle("rho", f.density[i], f, i);
}

// A whole non-negative number, or a clear error naming the argument.
long parseCount(const std::string& text, const char* what) {
  long value = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 0)
    throw std::invalid_argument(std::string("expected ") + what + ", got '" + text + "'");
  return value;
}

// A frame number; film shots may start below 0 (the scene allows start_frame down to -1e6).
int parseFrame(const std::string& text) {
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size())
    throw std::invalid_argument("expected a frame number, got '" + text + "'");
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 3) {
      std::fprintf(stderr,
                   "usage: cache_speeds SHOT FRAME... [--top N] [--densest N] [--near-walls] [--layers]\n");
      return 2;
    }
    size_t top = 6, densest = 0;
    bool nearWalls = false, layers = false;
    std::vector<int> frames;
    for (int i = 2; i < argc; ++i) {
      if (std::string(argv[i]) == "--top" && i + 1 < argc)
        top = size_t(parseCount(argv[++i], "a count after --top"));
      else if (std::string(argv[i]) == "--densest" && i + 1 < argc)
        densest = size_t(parseCount(argv[++i], "a count after --densest"));
      else if (std::string(argv[i]) == "--near-walls")
        nearWalls = true;
      else if (std::string(argv[i]) == "--layers")
        layers = true;
      else
        frames.push_back(parseFrame(argv[i]));
    }
    const sphfx::Domain domain = nearWalls || layers ? readDomain(argv[1]) : sphfx::Domain{};
    for (int frame : frames) report(argv[1], frame, top, densest, domain, nearWalls, layers);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cache_speeds: %s\n", e.what());
    return 1;
  }
}
