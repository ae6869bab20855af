#include "neighbor_grid.h"

#include <algorithm>
#include <string>

#include "bindings.h"
#include "gpu_types.h"
#include "sim_shaders.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"

namespace sphfx::sim {

namespace {
// The sort keys carry the slab in their top two bits (sim_grid_scatter.comp).
uint32_t checkedItems(uint32_t items) {
  if (items >= (1u << 30))
    throw InputError("neighbour grid: " + std::to_string(items) +
                     " items, more than the 2^30 the sort keys hold");
  return items;
}

ShaderDefines splitDefines(const GridSpec& spec) {
  ShaderDefines d;
  if (spec.splitX > 1) d.set("SIM_GRID_SPLIT_X", spec.splitX);
  return d;
}

ShaderDefines liveDefines(ShaderDefines d, bool liveCount) {
  if (liveCount) d.set("SIM_DYNAMIC_COUNT");
  return d;
}
}  // namespace

GridSpec GridSpec::forScene(const Scene& scene) {
  GridSpec g;
  for (int a = 0; a < 3; ++a) g.min[a] = float(scene.domain.min[a]);
  g.cellSize = float(scene.kernelRadius());
  g.dims = gridDims(scene);
  g.splitX = gridSplitX(scene);
  return g;
}

NeighborGrid::NeighborGrid(DispatchGate& gate, const GridSpec& spec, uint32_t items, bool liveCount)
    : gate_(&gate),
      spec_(spec),
      items_(checkedItems(items)),
      cellStart_((size_t(spec.cells()) + 2) * 4),
      rowStart_(spec.splitX > 1 ? (size_t(spec.cells()) * spec.splitX + 2) * 4 : 4),
      cellRank_(std::max<size_t>(items, 1) * 8),
      sorted_(std::max<size_t>(items, 1) * 4),
      scan_(gate, spec.cells() + 2),
      liveCount_(liveCount),
      cells_(ShaderProgram::compute(simShaderTable(), "sim_grid_cells.comp",
                                    liveDefines(splitDefines(spec), liveCount))),
      scatter_(ShaderProgram::compute(simShaderTable(), "sim_grid_scatter.comp", liveDefines({}, liveCount))),
      sort_(ShaderProgram::compute(simShaderTable(), "sim_grid_sort.comp", splitDefines(spec))),
      itemEntry_(gate.add(items, 64)),
      cellEntry_(gate.add(spec.cells(), 64)) {
  if (liveCount) {
    live_ = ShaderProgram::compute(simShaderTable(), "sim_grid_live.comp");
    liveEntry_ = gate.add(1, 1);  // gated like the sort: a closed substep keeps the count
    glProgramUniform1ui(live_.id(), live_.uniform("uCellCount"), spec.cells());
  } else {
    // Constant per grid: set once (programs are owned by this grid).
    glProgramUniform1ui(cells_.id(), cells_.uniform("uItemCount"), items);
    glProgramUniform1ui(scatter_.id(), scatter_.uniform("uItemCount"), items);
  }
  glProgramUniform3f(cells_.id(), cells_.uniform("uGridMin"), spec.min[0], spec.min[1], spec.min[2]);
  glProgramUniform1f(cells_.id(), cells_.uniform("uInvCellSize"), 1.0f / spec.cellSize);
  glProgramUniform3i(cells_.id(), cells_.uniform("uDims"), spec.dims[0], spec.dims[1], spec.dims[2]);
  glProgramUniform1ui(sort_.id(), sort_.uniform("uCellCount"), spec.cells());
}

void NeighborGrid::build(const GpuBuffer& srcPos, const GpuBuffer& srcVel, const GpuBuffer& dstPos,
                         const GpuBuffer& dstVel) const {
  cellStart_.fill(0);
  if (items_ == 0) return;
  srcPos.bindStorage(SPHFX_SSBO_SIM_GRID_SRC_POS);
  srcVel.bindStorage(SPHFX_SSBO_SIM_GRID_SRC_VEL);
  dstPos.bindStorage(SPHFX_SSBO_SIM_GRID_DST_POS);
  dstVel.bindStorage(SPHFX_SSBO_SIM_GRID_DST_VEL);
  cellStart_.bindStorage(SPHFX_SSBO_SIM_CELL_START);
  cellRank_.bindStorage(SPHFX_SSBO_SIM_GRID_CELL_RANK);
  sorted_.bindStorage(SPHFX_SSBO_SIM_GRID_SORTED);
  rowStart_.bindStorage(SPHFX_SSBO_SIM_GRID_ROW_START);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  cells_.use();
  gate_->dispatch(itemEntry_, "sim_grid_cells.comp");
  storageBarrier();
  scan_.run(cellStart_);
  cellStart_.bindStorage(SPHFX_SSBO_SIM_CELL_START);
  scatter_.use();
  gate_->dispatch(itemEntry_, "sim_grid_scatter.comp");
  storageBarrier();
  sort_.use();
  gate_->dispatch(cellEntry_, "sim_grid_sort.comp");
  storageBarrier();
  if (liveCount_) {
    live_.use();
    gate_->dispatch(liveEntry_, "sim_grid_live.comp");
    storageBarrier();
  }
}

}  // namespace sphfx::sim
