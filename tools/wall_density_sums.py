#!/usr/bin/env python3
"""Density of one particle moved from its lattice site towards a wall of Akinci samples that continue the
fluid's cubic lattice (psi = m), all other particles and samples fixed: how soft the wall is for each
density kernel (docs/design.md, "Boundaries"). Units of the spacing d, h = 2 d.

    python3 tools/wall_density_sums.py
"""
import math

H = 2.0  # kernel support in spacings (solver.kernel_support default)


def poly6(r2):
    return 315 / (64 * math.pi * H**9) * max(H * H - r2, 0.0) ** 3


def cubic(r2):
    q = math.sqrt(r2) / H
    k = 8 / (math.pi * H**3)
    return k * (6 * q**3 - 6 * q**2 + 1) if q <= 0.5 else k * 2 * max(1 - q, 0.0) ** 3


def spiky(r2):
    return 15 / (math.pi * H**6) * max(H - math.sqrt(r2), 0.0) ** 3


def lattice_sum(kernel, px, py, pz, wall):
    """Sum over the lattice sites (i + 1/2, l + 1/2, k + 1/2) on one side of the wall plane y = 0,
    without the particle's own site (0.5, 0.5, 0.5)."""
    total = 0.0
    for i in range(-5, 6):
        for k in range(-5, 6):
            for l in range(-4, 5):
                y = l + 0.5
                if (y < 0) != wall or (i, k, l) == (0, 0, 0):
                    continue
                total += kernel((px - i - 0.5) ** 2 + (py - y) ** 2 + (pz - k - 0.5) ** 2)
    return total


def density(fluid_kernel, wall_kernel, wall_scale, y):
    return (fluid_kernel(0.0) + lattice_sum(fluid_kernel, 0.5, y, 0.5, False)
            + wall_scale * lattice_sum(wall_kernel, 0.5, y, 0.5, True))


def main():
    heights = [0.5, 0.4, 0.3, 0.2, 0.1, 0.05]
    # Spiky wall term scaled so that the resting site (0.5 d) keeps the poly6 lattice's rest density.
    spiky_scale = lattice_sum(poly6, 0.5, 0.5, 0.5, True) / lattice_sum(spiky, 0.5, 0.5, 0.5, True)
    cases = [("poly6", poly6, poly6, 1.0), ("cubic spline", cubic, cubic, 1.0),
             (f"poly6, spiky walls x {spiky_scale:.4f}", poly6, spiky, spiky_scale)]
    print("distance from the wall plane (d): " + " ".join(f"{y:6.2f}" for y in heights))
    for name, fluid_kernel, wall_kernel, scale in cases:
        rest = density(fluid_kernel, wall_kernel, scale, 0.5)
        rise = [100 * (density(fluid_kernel, wall_kernel, scale, y) / rest - 1) for y in heights]
        print(f"{name:34s} " + " ".join(f"{r:5.1f}%" for r in rise))
    # Bumpiness: the wall term over the hollow between four samples minus the one above a sample.
    rest = density(poly6, poly6, 1.0, 0.5)
    bumps = [100 * (lattice_sum(poly6, 0.0, y, 0.0, True) - lattice_sum(poly6, 0.5, y, 0.5, True)) / rest
             for y in heights]
    print(f"{'poly6 walls, hollow - above sample':34s} " + " ".join(f"{b:+5.1f}%" for b in bumps))


if __name__ == "__main__":
    main()
