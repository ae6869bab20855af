#pragma once
/// @file parallel_scan.h
/// @brief Exclusive prefix sum of 32-bit counts on the GPU: scans of blocks of 1024 values (on hardware
/// GPUs a work group per block with a Hillis-Steele scan in shared memory, on CPU rasterisers an
/// invocation per block: sim_scan_blocks.comp), recursing on the block totals, then adding the scanned
/// totals back. Used by the neighbour grid to turn cell counts into cell starts.

#include <cstdint>
#include <vector>

#include "dispatch_gate.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

class ExclusiveScan {
 public:
  /// Prepares the level buffers for `count` values and registers its dispatches with `gate`; the level
  /// pass follows workgroupReduce() (gpu_types.h), so it needs a current context.
  /// @throws GLError if the programs do not build
  /// @throws InputError if SPHFX_WORKGROUP_REDUCE is set to anything but 1 or 0
  ExclusiveScan(DispatchGate& gate, uint32_t count);

  /// Replaces data[0, count) with its exclusive prefix sum (data[0] = 0). Queues GPU work only.
  void run(const GpuBuffer& data) const;
  uint32_t count() const { return count_; }

  static constexpr uint32_t kBlock = 1024;

 private:
  struct Level {
    uint32_t count;     // values scanned at this level
    GpuBuffer sums;     // one total per block
    uint32_t entry;     // the level pass's dispatch (a group or an invocation per block)
    uint32_t addEntry;  // the add pass's dispatch (a group per block)
  };
  const DispatchGate* gate_;
  uint32_t count_;
  std::vector<Level> levels_;
  ShaderProgram blocks_, add_;
};

}  // namespace sphfx::sim
