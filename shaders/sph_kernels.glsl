// SPH kernels with support radius h (simDomainMin.w). Factors are precomputed on the CPU
// (sphfx::sim::kernelFactors, wendlandFactors) into simKernel.xy.
#if defined(KERNEL_WENDLAND_C2)
// WCSPH with Wendland C2 (Wendland 1995; Dehnen & Aly 2012), one kernel for the density sum and the
// pressure gradient: W = simKernel.x (1 - q)^4 (1 + 4 q), grad W = simKernel.y (1 - q)^3 r, q = |r| / h.
float sphW(float r2) {
  float q = sqrt(r2) / simDomainMin.w, t = max(1.0 - q, 0.0);
  return simKernel.x * t * t * t * t * (1.0 + 4.0 * q);
}

vec3 sphGradW(vec3 r, float len) {
  float t = max(1.0 - len / simDomainMin.w, 0.0);
  return (simKernel.y * t * t * t) * r;
}
#else
// Mueller et al. 2003: poly6 for density, spiky gradient for pressure (DFSPH's wall calibration in
// sphfx::sim::DFSPHSolver is derived for this pair).
float sphPoly6(float r2) {
  float d = max(simKernel.w - r2, 0.0);
  return simKernel.x * d * d * d;
}

// Gradient of the spiky kernel at offset r (|r| = len) from the neighbour; zero at r = 0.
vec3 sphSpikyGrad(vec3 r, float len) {
  float d = simDomainMin.w - len;
  return (len > 1e-12 && d > 0.0) ? (simKernel.y * d * d / len) * r : vec3(0.0);
}

float sphW(float r2) { return sphPoly6(r2); }
vec3 sphGradW(vec3 r, float len) { return sphSpikyGrad(r, len); }
#endif

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
// from starts[first] to starts[last]. False for rows outside the grid. With SIM_PERIODIC_Y and
// SIM_PERIODIC_Z the rows wrap around in y and z (the grid has >= 3 cells there, so no row is visited
// twice); with SIM_PERIODIC_X this is the part of the row inside the grid and sphRowWrap() gives the
// cell across the seam.
//
// With SIM_GRID_SPLIT_X (sphfx::sim::gridSplitX(): each cell ordered in slabs of h / split in x, and
// the starts indexed per slab, NeighborGrid::rowStart()) the range is trimmed to the x-interval that the
// kernel sphere of xi reaches at the row's nearest y and z, and rows it does not reach are skipped: 27
// h^3 of candidates become about 15 h^3 with split 4. The reach is
// widened by 1e-3 h so that rounding never drops a neighbour; beyond h every kernel is 0.
bool sphRow(vec3 xi, ivec3 cell, int dy, int dz, out uint first, out uint last) {
  ivec3 r = cell + ivec3(0, dy, dz);
#if defined(SIM_PERIODIC_Y)
  r.y = (r.y + simGridDims.y) % simGridDims.y;
#endif
#if defined(SIM_PERIODIC_Z)
  r.z = (r.z + simGridDims.z) % simGridDims.z;
#endif
  if (r.y < 0 || r.z < 0 || r.y >= simGridDims.y || r.z >= simGridDims.z) return false;
#if defined(SIM_GRID_SPLIT_X)
  int slabs = simGridDims.x * SIM_GRID_SPLIT_X;
  uint base = uint(slabs * (r.y + simGridDims.y * r.z));
  // Gap between xi and the row's cells in y and z (0 in the particle's own row). The border rows also
  // hold the items up to h outside the grid (sim_grid_cells.comp), so they reach out to infinity. A
  // periodic y or z row may lie across the seam, so that axis is not trimmed there.
  float h = simDomainMin.w;
  vec2 low = simDomainMin.yz + vec2(r.yz) * h, high = low + h;
  low = mix(low, vec2(-1e30), equal(r.yz, ivec2(0)));
  high = mix(high, vec2(1e30), equal(r.yz, simGridDims.yz - 1));
  vec2 gap = max(max(low - xi.yz, xi.yz - high), 0.0);
#if defined(SIM_PERIODIC_Y)
  gap.x = 0.0;
#endif
#if defined(SIM_PERIODIC_Z)
  gap.y = 0.0;
#endif
  float reach2 = simKernel.w - dot(gap, gap);
  if (reach2 <= 0.0) return false;
  float reach = sqrt(reach2) + 1e-3 * h, perSlab = float(SIM_GRID_SPLIT_X) / h;
  int x0 = int(floor((xi.x - reach - simDomainMin.x) * perSlab));
  int x1 = int(floor((xi.x + reach - simDomainMin.x) * perSlab));
  first = base + uint(clamp(x0, 0, slabs - 1));
  last = base + uint(clamp(x1, 0, slabs - 1)) + 1u;
#else
  uint base = uint(simGridDims.x * (r.y + simGridDims.y * r.z));
  first = base + uint(max(r.x - 1, 0));
  last = base + uint(min(r.x + 1, simGridDims.x - 1)) + 1u;
#endif
  return true;
}

// Periodic boundaries (SIM_PERIODIC_X, SIM_PERIODIC_Y, SIM_PERIODIC_Z; scene domain.periodic). A periodic axis has
// floor(extent / h) >= 3 cells, the last one taking the remainder, so the cells tile the period.
// Every pair distance goes through sphDelta() (minimum image), and a neighbour row of a particle in the
// first or last x column also has the cell on the other side of the seam (sphRowWrap()). Without
// periodic axes sphDelta() is the plain difference.

// Offset x_i - x_j, reduced to the nearest periodic image along the periodic axes.
vec3 sphDelta(vec3 xi, vec3 xj) {
  vec3 d = xi - xj;
#if defined(SIM_PERIODIC_X)
  float lx = simDomainMax.x - simDomainMin.x;
  d.x -= lx * round(d.x / lx);
#endif
#if defined(SIM_PERIODIC_Y)
  float ly = simDomainMax.y - simDomainMin.y;
  d.y -= ly * round(d.y / ly);
#endif
#if defined(SIM_PERIODIC_Z)
  float lz = simDomainMax.z - simDomainMin.z;
  d.z -= lz * round(d.z / lz);
#endif
  return d;
}

#if defined(SIM_PERIODIC_X)
#if defined(SIM_GRID_SPLIT_X)
#error "a periodic x axis walks whole cells (sphfx::sim::gridSplitX() is 1 there)"
#endif
// The cell of row (dy, dz) of `cell` that lies across the x seam: cell nx-1 for a particle in column 0,
// cell 0 for one in column nx-1 (one cell, i.e. the range starts[first] to starts[last]). False for
// particles in the other columns and for rows outside the grid. sphRow() gives the rest of the row.
bool sphRowWrap(ivec3 cell, int dy, int dz, out uint first, out uint last) {
  int nx = simGridDims.x;
  if (cell.x != 0 && cell.x != nx - 1) return false;
  if (!sphRow(vec3(0.0), cell, dy, dz, first, last)) return false;
  uint base = first - uint(max(cell.x - 1, 0));  // start of the row's x = 0 cell
  first = base + uint(cell.x == 0 ? nx - 1 : 0);
  last = first + 1u;
  return true;
}
#endif

#if defined(SIM_PERIODIC_X) || defined(SIM_PERIODIC_Y) || defined(SIM_PERIODIC_Z)
float sphWrapAxis(float x, float lo, float hi) {
  float x2 = x - (hi - lo) * floor((x - lo) / (hi - lo));
  // Rounding may land exactly on hi; NaN stays NaN for the health check.
  return (x2 >= hi || x2 < lo) ? lo : x2;
}

// A position brought back into [min, max) along the periodic axes (integration, after the move).
vec3 sphWrapPosition(vec3 x) {
#if defined(SIM_PERIODIC_X)
  x.x = sphWrapAxis(x.x, simDomainMin.x, simDomainMax.x);
#endif
#if defined(SIM_PERIODIC_Y)
  x.y = sphWrapAxis(x.y, simDomainMin.y, simDomainMax.y);
#endif
#if defined(SIM_PERIODIC_Z)
  x.z = sphWrapAxis(x.z, simDomainMin.z, simDomainMax.z);
#endif
  return x;
}
#endif

#if defined(SIM_WALL_CONTACT) || defined(SIM_COLLIDER_CONTACT)
// fluid.wall_contact, for a particle with fewer than SIM_WALL_CONTACT neighbours (fluid and samples
// within h), where the density no longer holds it off the walls: `excess` is the walls' kernel sum over
// it less SIM_WALL_CONTACT_REST (a resting particle's half a spacing from a flat wall), `grad` the sum's
// gradient, `sampleRate` sum_b psi_b v_b . grad W_ib (moving colliders). Returns the velocity less the
// part along `grad` that would take the sum past the rest value within dt: at most the approach, so the
// contact never adds energy against walls at rest. The colliders' contact (sphColliderContact(),
// sph_colliders.glsl) passes a distance constraint the same way: unit `grad`, `excess` in metres.
vec3 sphWallContact(vec3 v, vec3 grad, float excess, float sampleRate, float dt) {
  float g2 = dot(grad, grad), approach = dot(v, grad) - sampleRate;
  float over = excess + dt * approach;
  if (g2 <= 0.0 || approach <= 0.0 || over <= 0.0 || dt <= 0.0) return v;
  return v - (min(over, dt * approach) / (dt * g2)) * grad;
}
#endif

#if defined(SIM_WALL_FRICTION)
// fluid.wall_drag "friction" (artificial model): the walls' Monaghan term pushes only along the walls'
// normal and only against an approach, and the sliding along them meets a skin friction of coefficient
// SIM_WALL_FRICTION (c_f), a wall shear stress c_f rho |u_t| u_t / 2 whatever the spacing. Sums over the
// samples within h: grad = sum psi_b grad W (rho0 times the solid fraction's gradient; its length
// integrates to rho0 / 2 across the fluid beside a flat wall, which sets the friction's scale), monaghan =
// the walls' Monaghan acceleration as under "viscous", velocity = sum psi_b W (v_b, 1) (moving colliders).
struct WallDragSums {
  vec3 grad;
  vec3 monaghan;
  vec4 velocity;
};

WallDragSums wallDragZero() { return WallDragSums(vec3(0.0), vec3(0.0), vec4(0.0)); }

void wallDragAdd(inout WallDragSums s, float psi, vec3 grad, float r2, vec3 vb, vec3 monaghan) {
  s.grad += psi * grad;
  s.monaghan += monaghan;
#if defined(HAS_COLLIDERS)
  s.velocity += (psi * sphW(r2)) * vec4(vb, 1.0);
#endif
}

// The acceleration on a particle of velocity vi over a step dt (the last step's; 0: none yet). Both parts
// only take energy: the normal push acts while the particle approaches and stops at most the approach
// within dt, the friction opposes the sliding and stops at most the sliding within dt.
vec3 wallDragAcceleration(WallDragSums s, vec3 vi, float dt) {
  float g = length(s.grad);
  if (g <= 0.0) return vec3(0.0);
  vec3 n = -s.grad / g;  // out of the walls
  vec3 u = vi;
#if defined(HAS_COLLIDERS)
  if (s.velocity.w > 0.0) u -= s.velocity.xyz / s.velocity.w;
#endif
  float un = dot(u, n);
  vec3 ut = u - un * n;
  float rate = SIM_WALL_FRICTION * g / simFluid.x * length(ut);  // 1/s
  if (dt > 0.0) rate = min(rate, 1.0 / dt);
  vec3 a = -rate * ut;
  if (un < 0.0) {
    float push = max(dot(s.monaghan, n), 0.0);
    if (dt > 0.0) push = min(push, -un / dt);
    a += push * n;
  }
  return a;
}
#endif
