// DFSPH boundary constraints (DFSPH_BOUNDARY_CONSTRAINTS), step start: each wall sample b carries a
// density constraint of its own, its fluid share S_b = sum_f psi_b W(x_b - x_f) (the pair kernel of the
// walls, sph_dfsph.glsl) at most its share on the resting lattice T_b. Its stiffness k_b pushes the
// fluid by -k_b psi_b grad W(x_f - x_b), the gradient of the constraint, so the walls' pressure does no
// work on motion that keeps the constraints (as the WCSPH walls' own pressure, sim_boundary_pressure.comp).
// Writes dfsph[N + b]: x the inverse Jacobi diagonal (0: no fluid near), y S_b - T_b, z the warm start
// (the density solve's warm share of the last total), w T_b; and the sample's list of fluid neighbours
// with its count (sph_dfsph.glsl, dfsphSampleSlot), which the solve's iterations read. A sample with
// fluid near it joins the wet list (sph_dfsph.glsl, DFSPH_WET_LIST), the only samples the iterations
// visit; the others get a stiffness increment of 0 for the substep (their particles' wall entries read
// it). A sample no particle's walk visited and without fluid near at its last pass is skipped, its values
// unchanged (DFSPH_SAMPLES_MARKED, sph_dfsph.glsl).
// Without colliders, T_b is the share of a fluid filling the domain on its lattice, and the samples keep
// their sorted order between substeps (the warm start and T_b are per sorted index).
// DFSPH_BOUNDARY_REST_SHARE: the variant that writes T_b alone, once per solver (DFSPHSolver::
// computeDensity): T_b is a lattice sum of (2 DFSPH_REST_REACH + 2)^3 kernels that never changes.
// With colliders (HAS_COLLIDERS), the samples are placed and re-sorted every substep
// (sim_boundary_update.comp), so nothing is kept per sorted index: T_b is recomputed here for every
// sample near fluid, as the share of the sites x_b + n s (the lattice the sample's own layer continues)
// that lie inside the domain and outside every collider at the substep's start, and the samples' solve
// starts cold.
#define DFSPH_LIST_READ
#define DFSPH_LIST_WRITE
#if !defined(DFSPH_BOUNDARY_REST_SHARE)
#define DFSPH_WET_LIST
#endif
#include "sph_params.glsl"
#include "sph_neighbors.glsl"
#include "sph_dfsph.glsl"
#if defined(HAS_COLLIDERS)
#include "sph_colliders.glsl"
#endif
layout(local_size_x = SIM_WG) in;
#if !defined(DFSPH_BOUNDARY_REST_SHARE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_INCREMENT) writeonly buffer DfsphIncrement { float increment[]; };
#endif

// Whether a lattice site lies between the walls: a periodic axis has none (the fluid continues across
// its seam), and an open face none on its side (the fluid flows on past it).
bool insideDomain(vec3 site) {
  vec3 lo = simDomainMin.xyz, hi = simDomainMax.xyz;
#if defined(SIM_OPEN_FACES)
  lo -= 1e30 * vec3((SIM_OPEN_FACES & 1) != 0, (SIM_OPEN_FACES & 4) != 0, (SIM_OPEN_FACES & 16) != 0);
  hi += 1e30 * vec3((SIM_OPEN_FACES & 2) != 0, (SIM_OPEN_FACES & 8) != 0, (SIM_OPEN_FACES & 32) != 0);
#endif
  bool x = site.x > lo.x && site.x < hi.x, y = site.y > lo.y && site.y < hi.y,
       z = site.z > lo.z && site.z < hi.z;
#if defined(SIM_PERIODIC_X)
  x = true;
#endif
#if defined(SIM_PERIODIC_Y)
  y = true;
#endif
#if defined(SIM_PERIODIC_Z)
  z = true;
#endif
  return x && y && z;
}

#if defined(DFSPH_REST_MIRROR_FROM)
// On a walled axis whose extent is not a whole number of spacings the lattice from the min wall puts its
// last layer elsewhere than half a spacing from the max wall (at 58.5 spacings on the wall itself, at 14.5
// a whole spacing off), and the max wall's samples would let the fluid in or hold it off. A sample past
// DFSPH_REST_MIRROR_FROM (per axis: the middle, or 1e30 on an axis that fits) takes the share of its
// mirror image across the domain, which sees the lattice from the max wall: the fluid rests half a spacing
// from each wall.
vec3 restLatticeFrame(vec3 xb) {
  vec3 lo = simDomainMin.xyz, hi = simDomainMax.xyz;
  return mix(xb, lo + hi - xb, step(DFSPH_REST_MIRROR_FROM, xb));
}
#endif

// The share of a fluid filling the domain on its lattice (sites min + (k + 1/2) s, or from the max wall,
// restLatticeFrame()): the sites between the lattice's cell around x_b and DFSPH_REST_REACH (ceil of the
// kernel support) cells out on each side, which hold every site within the support.
float restShare(vec3 xb) {
  const float s = DFSPH_SPACING;
#if defined(DFSPH_REST_MIRROR_FROM)
  xb = restLatticeFrame(xb);
#endif
  vec3 base = floor((xb - simDomainMin.xyz) / s - 0.5);
  float sum = 0.0;
  const int reach = DFSPH_REST_REACH;
  for (int x = -reach; x <= reach + 1; ++x)
    for (int y = -reach; y <= reach + 1; ++y)
      for (int z = -reach; z <= reach + 1; ++z) {
        vec3 site = simDomainMin.xyz + (base + vec3(x, y, z) + 0.5) * s;
        bool inside = insideDomain(site);
        sum += inside ? dfsphW(length(xb - site)) : 0.0;
      }
  return sum;
}

#if defined(HAS_COLLIDERS)
// The share of the fluid sites x_b + n s, |n_k| <= DFSPH_REST_REACH (ceil of the kernel support), that
// lie inside the domain and outside each of the DFSPH_COLLIDERS colliders placed at the substep's start.
float restShareAmongColliders(vec3 xb) {
  const float s = DFSPH_SPACING;
  const int reach = DFSPH_REST_REACH;
  SphColliderPose poses[DFSPH_COLLIDERS];
  for (uint c = 0u; c < uint(DFSPH_COLLIDERS); ++c) poses[c] = sphColliderPose(c, float(stateTime));
  float sum = 0.0;
  for (int x = -reach; x <= reach; ++x)
    for (int y = -reach; y <= reach; ++y)
      for (int z = -reach; z <= reach; ++z) {
        float r = s * length(vec3(x, y, z));
        if (r >= simDomainMin.w) continue;
        vec3 site = xb + s * vec3(x, y, z);
        bool fluid = insideDomain(site);
        for (uint c = 0u; fluid && c < uint(DFSPH_COLLIDERS); ++c) fluid = !sphInsideCollider(c, poses[c], site);
        sum += fluid ? dfsphW(r) : 0.0;
      }
  return sum;
}
#endif

void main() {
  uint b = sphfxGlobalIndex();
  if (b >= simCounts.y) return;
  uint at = DFSPH_CAPACITY + b;
#if defined(DFSPH_SAMPLES_MARKED) && !defined(DFSPH_BOUNDARY_REST_SHARE)
  if (dfsphSampleCount(b) == 0u) return;  // not marked, and no fluid near at the slot's last pass
#endif
  vec4 xb = sphFetchBoundaryPos(b);
  float psi = xb.w * dfsphWallScale(xb.xyz);
#if defined(DFSPH_BOUNDARY_REST_SHARE)
  dfsph[at].w = psi * restShare(xb.xyz);
#else
  float share = 0.0, squares = 0.0;
  uint listed = 0u;
  SPH_FOR_EACH_CELL_RANGE(xb.xyz, row, seam, first, last)
    SPH_FOR_EACH_FLUID(j, first, last) {
      vec3 d = sphDelta(sphFetchPos(j).xyz, xb.xyz);
      float r = length(d);
      share += psi * dfsphW(r);
      vec3 g = psi * dfsphGradAt(d, r);
      // Jacobi diagonal: the row sum e_fb . sum_b' e_fb' over the samples that share particle f (they
      // push it together: with |e_fb|^2 alone, the exact diagonal, the floor's corners diverge in the
      // first substeps), at least |e_fb|^2.
      squares += max(dot(g, dfsphBoundary(j).xyz), dot(g, g));
      // The sample's list, in the walk's order, as the particles' (sim_dfsph_factor.comp): every
      // candidate goes to the next free slot, which only a neighbour advances.
      dfNbr[dfsphSampleSlot(b, min(listed, uint(DFSPH_MAX_NEIGHBORS)))] = vec4(g, uintBitsToFloat(j));
      listed += r < simDomainMin.w ? 1u : 0u;
    }
  SPH_END_FOR_EACH_CELL_RANGE
  if (listed > uint(DFSPH_MAX_NEIGHBORS)) atomicOr(stateFailure, SIM_FAIL_NEIGHBORS);
  dfCount[DFSPH_CAPACITY + b] = min(listed, uint(DFSPH_MAX_NEIGHBORS));
  bool nearFluid = squares > 1e-20;
  if (nearFluid) {
    uint k = atomicAdd(dfWetCount, 1u);
    dfWet[k] = b;
    atomicMax(dfWetArgs[0], k / uint(SIM_WG) + 1u);
  } else {
    increment[at] = 0.0;
  }
#if defined(HAS_COLLIDERS)
  float rest = nearFluid ? psi * restShareAmongColliders(xb.xyz) : 0.0;
  dfsph[at] = vec4(nearFluid ? 1.0 / squares : 0.0, share - rest, 0.0, rest);
#else
  vec4 last = dfsph[at];
  dfsph[at] = vec4(nearFluid ? 1.0 / squares : 0.0, share - last.w,
                   nearFluid ? DFSPH_DENSITY_WARM_BEFORE_STEP * last.z : 0.0, last.w);
#endif
#endif
}
