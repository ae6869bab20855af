// Exclusive prefix sum, level pass: scans blocks of 1024 values in place and writes each block's total to
// `sums`. Levels recurse on the totals; sim_scan_add.comp adds the scanned totals back.
// SIM_WORKGROUP_REDUCE (hardware GPUs): a work group per block, 4 values per invocation, then a
// Hillis-Steele scan of the 256 partial sums in shared memory. Otherwise (CPU rasterisers, where every
// barrier runs the whole group up to it, so its 17 barriers cost more than the sums): an invocation per
// block adds its values in order, with no barrier. Both give the same integers.
layout(std430, binding = SPHFX_SSBO_SIM_SCAN_DATA) buffer ScanData { uint scanData[]; };
layout(std430, binding = SPHFX_SSBO_SIM_SCAN_SUMS) writeonly buffer ScanSums { uint scanSums[]; };
uniform uint uCount;

#if defined(SIM_WORKGROUP_REDUCE)
layout(local_size_x = 256) in;
shared uint partial[256];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * 1024u + t * 4u;
  uint v[4];
  uint sum = 0u;
  for (uint k = 0u; k < 4u; ++k) {
    uint value = base + k < uCount ? scanData[base + k] : 0u;
    v[k] = sum;
    sum += value;
  }
  partial[t] = sum;
  barrier();
  for (uint off = 1u; off < 256u; off <<= 1) {
    uint add = t >= off ? partial[t - off] : 0u;
    barrier();
    partial[t] += add;
    barrier();
  }
  uint prefix = t > 0u ? partial[t - 1u] : 0u;
  for (uint k = 0u; k < 4u; ++k)
    if (base + k < uCount) scanData[base + k] = v[k] + prefix;
  if (t == 255u) scanSums[gl_WorkGroupID.x] = partial[255];
}
#else
layout(local_size_x = 64) in;

void main() {
  uint block = gl_GlobalInvocationID.x, base = block * 1024u;
  if (base >= uCount) return;
  uint end = min(base + 1024u, uCount), sum = 0u;
  for (uint k = base; k < end; ++k) {
    uint value = scanData[k];
    scanData[k] = sum;
    sum += value;
  }
  scanSums[block] = sum;
}
#endif
