#include "parallel_scan.h"

#include "bindings.h"
#include "gpu_types.h"
#include "sim_shaders.h"
#include "sphfx/gpu/gl.h"

namespace sphfx::sim {

namespace {
ShaderDefines levelDefines(bool workgroups) {
  ShaderDefines d;
  if (workgroups) d.set("SIM_WORKGROUP_REDUCE");
  return d;
}
}  // namespace

ExclusiveScan::ExclusiveScan(DispatchGate& gate, uint32_t count) : gate_(&gate), count_(count) {
  const bool workgroups = workgroupReduce();
  blocks_ = ShaderProgram::compute(simShaderTable(), "sim_scan_blocks.comp", levelDefines(workgroups));
  add_ = ShaderProgram::compute(simShaderTable(), "sim_scan_add.comp");
  uint32_t n = count;
  do {
    const uint32_t blocks = (n + kBlock - 1) / kBlock;
    const uint32_t add = gate.add(blocks * 256, 256);
    const uint32_t level = workgroups ? add : gate.add(blocks, 64);
    levels_.push_back({n, GpuBuffer(std::max<size_t>(blocks, 1) * 4), level, add});
    n = blocks;
  } while (n > 1);
}

void ExclusiveScan::run(const GpuBuffer& data) const {
  if (count_ == 0) return;
  // Up: scan each level in place, its block totals become the next level's data.
  for (size_t k = 0; k < levels_.size(); ++k) {
    const GpuBuffer& in = k == 0 ? data : levels_[k - 1].sums;
    in.bindStorage(SPHFX_SSBO_SIM_SCAN_DATA);
    levels_[k].sums.bindStorage(SPHFX_SSBO_SIM_SCAN_SUMS);
    blocks_.use();
    glUniform1ui(blocks_.uniform("uCount"), levels_[k].count);
    gate_->dispatch(levels_[k].entry, "sim_scan_blocks.comp");
    storageBarrier();
  }
  // Down: add each level's scanned totals to the level below (the top level is a single block).
  for (size_t k = levels_.size() - 1; k-- > 0;) {
    const GpuBuffer& in = k == 0 ? data : levels_[k - 1].sums;
    in.bindStorage(SPHFX_SSBO_SIM_SCAN_DATA);
    levels_[k].sums.bindStorage(SPHFX_SSBO_SIM_SCAN_SUMS);
    add_.use();
    glUniform1ui(add_.uniform("uCount"), levels_[k].count);
    gate_->dispatch(levels_[k].addEntry, "sim_scan_add.comp");
    storageBarrier();
  }
}

}  // namespace sphfx::sim
