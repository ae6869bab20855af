// Exclusive prefix sum, down pass: adds the scanned total of the preceding blocks to each block.
layout(local_size_x = 256) in;
layout(std430, binding = SPHFX_SSBO_SIM_SCAN_DATA) buffer ScanData { uint scanData[]; };
layout(std430, binding = SPHFX_SSBO_SIM_SCAN_SUMS) readonly buffer ScanSums { uint scanSums[]; };
uniform uint uCount;

void main() {
  uint base = gl_WorkGroupID.x * 1024u + gl_LocalInvocationID.x * 4u;
  uint add = scanSums[gl_WorkGroupID.x];
  for (uint k = 0u; k < 4u; ++k)
    if (base + k < uCount) scanData[base + k] += add;
}
