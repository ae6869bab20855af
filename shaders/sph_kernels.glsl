// SPH kernels (Mueller et al. 2003): poly6 for density, spiky gradient for pressure, the viscosity
// kernel's Laplacian. Factors are precomputed on the CPU (sphfx::sim::KernelFactors).
float sphPoly6(float r2) {
  float d = max(simKernel.w - r2, 0.0);
  return simKernel.x * d * d * d;
}

// Gradient of the spiky kernel at offset r (|r| = len) from the neighbour; zero at r = 0.
vec3 sphSpikyGrad(vec3 r, float len) {
  float d = simDomainMin.w - len;
  return (len > 1e-12 && d > 0.0) ? (simKernel.y * d * d / len) * r : vec3(0.0);
}

float sphViscosityLaplacian(float len) { return simKernel.z * max(simDomainMin.w - len, 0.0); }

// Cell of a position in the domain grid (cell size h), clamped into the grid.
ivec3 sphCell(vec3 x) {
  return clamp(ivec3(floor((x - simDomainMin.xyz) / simDomainMin.w)), ivec3(0), simGridDims.xyz - 1);
}

// Pressure from the equation of state; negative pressure is clamped to zero so that the free surface
// does not clump (tensile instability).
float sphPressure(float rho) {
#if defined(EOS_TAIT)
  return max(simFluid.y * (pow(rho / simFluid.x, simFluid.z) - 1.0), 0.0);
#else
  return max(simFluid.y * (rho - simFluid.x), 0.0);
#endif
}

// Row (dy, dz) of the 3x3x3 cell neighbourhood of `cell`: cells (x-1..x+1, y+dy, z+dz) are contiguous
// in the sorted order because x varies fastest, so the whole row is one range of the sorted arrays,
// from starts[first] to starts[last]. False for rows outside the grid.
bool sphRow(ivec3 cell, int dy, int dz, out uint first, out uint last) {
  ivec3 r = cell + ivec3(0, dy, dz);
  if (r.y < 0 || r.z < 0 || r.y >= simGridDims.y || r.z >= simGridDims.z) return false;
  uint base = uint(simGridDims.x * (r.y + simGridDims.y * r.z));
  first = base + uint(max(r.x - 1, 0));
  last = base + uint(min(r.x + 1, simGridDims.x - 1)) + 1u;
  return true;
}
