// The GPU neighbour grid against brute force on the CPU, and the scan/reorder on edge cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <tuple>

#include "../core/gpu_layout_check.h"
#include "bindings.h"
#include "gpu_types.h"
#include "neighbor_grid.h"
#include "parallel_scan.h"
#include "sim_shaders.h"
#include "sim_test_util.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"

using namespace sphfx;
using Vec4 = std::array<float, 4>;

namespace {

// Both level passes: the work-group scan of hardware GPUs and the serial blocks of CPU rasterisers
// (SPHFX_WORKGROUP_REDUCE forces either), at sizes around the 1024-value blocks and over three levels.
TEST(Scan, ExclusivePrefixSumMatchesCpu) {
  auto ctx = test::makeContext();
  for (const char* workgroups : {"1", "0"}) {
    const test::ScopedEnv env("SPHFX_WORKGROUP_REDUCE", workgroups);
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
        ASSERT_EQ(got[i], sum) << "work groups " << workgroups << ", n=" << n << " i=" << i;
        sum += v[i];
      }
    }
  }
}

struct GridRun {
  std::vector<uint32_t> start, rowStart;
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
          grid.rowStart().downloadVector<uint32_t>(size_t(spec.cells()) * spec.splitX + 2),
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

// The sort keys carry the slab in their top two bits: a grid for 2^30 items or more refuses with a clear
// error before it allocates its 8 bytes per item.
TEST(NeighborGrid, RefusesMoreItemsThanTheSortKeysHold) {
  auto ctx = test::makeContext();
  sim::DispatchGate gate(1);
  EXPECT_THROW(sim::NeighborGrid(gate, cubeGrid(5, 0.1f), 1u << 30), InputError);
  EXPECT_THROW(sim::NeighborGrid(gate, cubeGrid(5, 0.1f), 0xffffffffu), InputError);
}

// With 4 slabs per cell in x: each cell ordered by slab, then by source index, and the row starts at
// every slab's first slot, against the same keys computed on the CPU (the GPU's float steps:
// (x - min) * (1 / h), floor of 4 times that), for items inside and up to 0.9 h outside the grid.
TEST(NeighborGrid, SlabOrderAndRowStartsMatchCpu) {
  auto ctx = test::makeContext();
  sim::GridSpec spec = cubeGrid(5, 0.1f);
  spec.splitX = 4;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.09f, 0.59f);
  std::vector<Vec4> items(3000);
  for (auto& p : items) p = {u(rng), u(rng), u(rng), 0};
  for (int i = 0; i < 100; ++i) items[i][0] = 0.025f * float(rng() % 21);  // on slab edges
  const GridRun r = runGrid(spec, items);
  const float inv = 1.0f / spec.cellSize;
  const uint32_t outside = spec.cells();
  auto cellOf = [&](const Vec4& p) {
    for (int a = 0; a < 3; ++a) {
      const float g = (p[a] - spec.min[a]) * inv;
      if (g < -1.0f || g >= float(spec.dims[a]) + 1.0f) return outside;
    }
    return cpuCell(spec, p);
  };
  auto slabOf = [&](const Vec4& p) {
    if (cellOf(p) == outside) return 0;
    const float g = (p[0] - spec.min[0]) * inv;
    const int cx = std::clamp(int(std::floor(g)), 0, spec.dims[0] - 1);
    return std::clamp(int(std::floor(g * 4.0f)) - 4 * cx, 0, 3);
  };
  std::vector<uint32_t> expect(items.size());
  for (uint32_t i = 0; i < items.size(); ++i) expect[i] = i;
  auto key = [&](uint32_t i) { return std::tuple(cellOf(items[i]), slabOf(items[i]), i); };
  std::sort(expect.begin(), expect.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
  // The out-of-reach cell is never sorted: compare the cells of the grid only.
  const uint32_t inGrid = r.start[outside];
  ASSERT_EQ(std::vector(r.sorted.begin(), r.sorted.begin() + inGrid),
            std::vector(expect.begin(), expect.begin() + inGrid));
  for (uint32_t c = 0; c < outside; ++c)
    for (int q = 0; q < 4; ++q) {
      uint32_t before = r.start[c];
      for (uint32_t k = r.start[c]; k < r.start[c + 1]; ++k) before += slabOf(items[expect[k]]) < q ? 1 : 0;
      ASSERT_EQ(r.rowStart[c * 4 + q], before) << "cell " << c << " slab " << q;
    }
  EXPECT_EQ(r.rowStart[outside * 4], r.start[outside]);
  EXPECT_EQ(r.rowStart[outside * 4 + 1], uint32_t(items.size()));
}

// Every split of the cells in x (sim::gridSplitX(): 4, 2 and 1 slabs per cell, chosen by the blocks'
// particle count against the 280 cells), with items on cell edges, on the domain border and up to 0.9 h
// outside it (boundary samples lie there).
class NeighbourSets : public ::testing::TestWithParam<std::pair<int, double>> {};

TEST_P(NeighbourSets, MatchBruteForce) {
  auto ctx = test::makeContext();
  const auto [split, block] = GetParam();
  const Scene scene = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.3,0.2,0.25]}, "fluid": {"spacing": 0.02,
          "blocks": [{"min": [0,0,0], "max": [)" +
      std::to_string(block) + ",0.1,0.1]}]}}");
  ASSERT_EQ(sim::gridSplitX(scene), split);
  const float h = float(scene.kernelRadius());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vec4> items;
  for (int i = 0; i < 2500; ++i) items.push_back({0.3f * u(rng), 0.2f * u(rng), 0.25f * u(rng), 0});
  for (int i = 0; i < 200; ++i)  // exactly on cell edges and on the domain border
    items.push_back({h * float(rng() % 8), h * float(rng() % 6), std::min(0.25f, h * float(rng() % 7)), 0});
  for (int i = 0; i < 300; ++i)  // a dense cluster
    items.push_back({0.151f + 0.002f * u(rng), 0.1f + 0.002f * u(rng), 0.12f + 0.002f * u(rng), 0});
  for (int i = 0; i < 200; ++i) {  // outside the domain by up to 0.9 h, below and on either x side
    const float out = 0.9f * h * u(rng);
    items.push_back({i % 2 ? -out : 0.3f + out, 0.2f * u(rng), 0.25f * u(rng), 0});
    items.push_back({0.3f * u(rng), -out, 0.25f * u(rng), 0});
  }
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

INSTANTIATE_TEST_SUITE_P(GridSplits, NeighbourSets,
                         ::testing::Values(std::pair{4, 0.1}, std::pair{2, 0.04}, std::pair{1, 0.02}),
                         [](const auto& info) { return "split" + std::to_string(info.param.first); });

TEST(SimLayout, BlocksMatchGlsl) {
  auto ctx = test::makeContext();
  sphfx::test::checkGpuLayouts(simShaderTable(), sim::simGpuLayouts());
}

}  // namespace
