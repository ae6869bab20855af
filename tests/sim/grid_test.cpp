// The GPU neighbour grid against brute force on the CPU, and the scan/reorder on edge cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>
#include <set>

#include "../core/gpu_layout_check.h"
#include "bindings.h"
#include "sim_test_util.h"
#include "sphfx/core/gl.h"
#include "sphfx/sim/gpu_types.h"
#include "sphfx/sim/neighbor_grid.h"
#include "sphfx/sim/parallel_scan.h"

using namespace sphfx;
using Vec4 = std::array<float, 4>;

namespace {

TEST(Scan, ExclusivePrefixSumMatchesCpu) {
  auto ctx = test::makeContext();
  std::mt19937 rng(7);
  for (uint32_t n : {1u, 63u, 64u, 65u, 1023u, 1024u, 1025u, 4097u, 1100003u}) {
    std::vector<uint32_t> v(n);
    for (auto& x : v) x = rng() % 9;
    sim::DispatchGate gate(1);
    sim::ExclusiveScan scan(gate, n);
    gate.arm();
    GpuBuffer data(n * 4);
    data.uploadVector(v);
    scan.run(data);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    const auto got = data.downloadVector<uint32_t>(n);
    uint32_t sum = 0;
    for (uint32_t i = 0; i < n; ++i) {
      ASSERT_EQ(got[i], sum) << "n=" << n << " i=" << i;
      sum += v[i];
    }
  }
}

struct GridRun {
  std::vector<uint32_t> start;
  std::vector<uint32_t> sorted;
  std::vector<Vec4> pos;
};

GridRun runGrid(const sim::GridSpec& spec, const std::vector<Vec4>& items) {
  const uint32_t n = uint32_t(items.size());
  sim::DispatchGate gate(n);
  sim::NeighborGrid grid(gate, spec, n);
  gate.arm();
  GpuBuffer pos(n * 16), vel(n * 16), outPos(n * 16), outVel(n * 16);
  pos.uploadVector(items);
  vel.uploadVector(items);
  grid.build(pos, vel, outPos, outVel);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  return {grid.cellStart().downloadVector<uint32_t>(spec.cells() + 2),
          grid.sortedIndex().downloadVector<uint32_t>(n), outPos.downloadVector<Vec4>(n)};
}

uint32_t cpuCell(const sim::GridSpec& g, const Vec4& p) {
  int c[3];
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(int(std::floor((p[a] - g.min[a]) / g.cellSize)), 0, g.dims[a] - 1);
  return uint32_t(c[0] + g.dims[0] * (c[1] + g.dims[1] * c[2]));
}

// Checks the counting sort against the CPU: a stable sort of item indices by cell.
void expectStableCellOrder(const sim::GridSpec& spec, const std::vector<Vec4>& items) {
  const GridRun r = runGrid(spec, items);
  std::vector<uint32_t> expect(items.size());
  for (uint32_t i = 0; i < items.size(); ++i) expect[i] = i;
  std::stable_sort(expect.begin(), expect.end(),
                   [&](uint32_t a, uint32_t b) { return cpuCell(spec, items[a]) < cpuCell(spec, items[b]); });
  EXPECT_EQ(r.sorted, expect);
  for (size_t k = 0; k < items.size(); ++k) ASSERT_EQ(r.pos[k], items[expect[k]]);
  std::vector<uint32_t> counts(spec.cells() + 2, 0);
  for (const Vec4& p : items) ++counts[cpuCell(spec, p)];
  uint32_t sum = 0;
  for (uint32_t c = 0; c < spec.cells() + 2; ++c) {
    ASSERT_EQ(r.start[c], sum) << c;
    sum += counts[c];
  }
}

sim::GridSpec cubeGrid(int cells, float h) {
  return {{0, 0, 0}, h, {cells, cells, cells}};
}

TEST(NeighborGrid, ReorderEdgeCases) {
  auto ctx = test::makeContext();
  const sim::GridSpec spec = cubeGrid(5, 0.1f);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 0.5f);
  std::vector<Vec4> random(1000);  // not a multiple of 64; most of the 125 cells hit, some empty
  for (auto& p : random) p = {u(rng), u(rng) * 0.3f, u(rng), 0};
  expectStableCellOrder(spec, random);
  std::vector<Vec4> oneCell(333, Vec4{0.25f, 0.25f, 0.25f, 0});  // all in one cell, identical keys
  for (size_t i = 0; i < oneCell.size(); ++i) oneCell[i][3] = float(i);
  expectStableCellOrder(spec, oneCell);
  expectStableCellOrder(spec, {Vec4{0.49f, 0.49f, 0.49f, 1}});  // one item in the last cell
}

TEST(NeighborGrid, NeighbourSetsMatchBruteForce) {
  auto ctx = test::makeContext();
  const Scene scene = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.3,0.2,0.25]}, "fluid": {"spacing": 0.02,
          "blocks": [{"min": [0,0,0], "max": [0.1,0.1,0.1]}]}})");
  const float h = float(scene.kernelRadius());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vec4> items;
  for (int i = 0; i < 2500; ++i) items.push_back({0.3f * u(rng), 0.2f * u(rng), 0.25f * u(rng), 0});
  for (int i = 0; i < 200; ++i)  // exactly on cell edges and on the domain border
    items.push_back({h * float(rng() % 8), h * float(rng() % 6), std::min(0.25f, h * float(rng() % 7)), 0});
  for (int i = 0; i < 300; ++i)  // a dense cluster
    items.push_back({0.151f + 0.002f * u(rng), 0.1f + 0.002f * u(rng), 0.12f + 0.002f * u(rng), 0});
  for (size_t i = 0; i < items.size(); ++i) items[i][3] = std::bit_cast<float>(uint32_t(i));
  const uint32_t n = uint32_t(items.size());
  for (const auto& [id, found] : test::gpuNeighbours(scene, items)) {
    std::set<uint32_t> expect;
    for (uint32_t j = 0; j < n; ++j) {
      float d2 = 0;
      for (int a = 0; a < 3; ++a) d2 += (items[id][a] - items[j][a]) * (items[id][a] - items[j][a]);
      if (d2 < h * h) expect.insert(j);
    }
    ASSERT_EQ(found, expect) << "item " << id;
  }
}

TEST(SimLayout, BlocksMatchGlsl) {
  auto ctx = test::makeContext();
  sphfx::test::checkGpuLayouts(sim::simGpuLayouts());
}

}  // namespace
