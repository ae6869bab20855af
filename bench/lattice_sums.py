#!/usr/bin/env python3
"""Kernel sums of a particle over the simple cubic, body-centred and face-centred cubic lattices at the
same number density (one particle per spacing^3), for the kernels sphfx uses.

  python3 bench/lattice_sums.py [--support S ...]

Prints, per support (kernel radius h in spacings, default 2) and kernel, the sum of W over the lattice
around a site (self included), in units of 1 / spacing^3, and each lattice's difference from the simple
cubic one. The fluid starts on the simple cubic lattice and its mass is calibrated on that lattice's sum:
under a kernel whose sum is lower on a closer packing, the same rest density holds more particles per
volume once the lattice gives way (docs/validation.md, "Known limits", 96,000 particles).
"""
import argparse
import itertools
import math


def spiky(r, h):
    return 15 / (math.pi * h**6) * (h - r) ** 3 if r < h else 0.0


def poly6(r, h):
    return 315 / (64 * math.pi * h**9) * (h * h - r * r) ** 3 if r < h else 0.0


def wendland_c2(r, h):
    q = r / h
    return 21 / (2 * math.pi * h**3) * (1 - q) ** 4 * (1 + 4 * q) if q < 1 else 0.0


def cubic_spline(r, h):
    """The cubic spline with support h (SPlisHSPlasH's form)."""
    q, k = r / h, 8 / (math.pi * h**3)
    if q <= 0.5:
        return k * (6 * q**3 - 6 * q**2 + 1)
    return 2 * k * (1 - q) ** 3 if q < 1 else 0.0


KERNELS = {"spiky": spiky, "poly6": poly6, "wendland_c2": wendland_c2, "cubic_spline": cubic_spline}

# Conventional cell sites (in cell units) and sites per cell: the cell edge is cbrt(sites) spacings.
LATTICES = {
    "sc": [(0, 0, 0)],
    "bcc": [(0, 0, 0), (0.5, 0.5, 0.5)],
    "fcc": [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)],
}


def distances(lattice, reach):
    """Distances (in spacings) from the site at the origin to every site within `reach` spacings."""
    basis = LATTICES[lattice]
    edge = len(basis) ** (1 / 3)
    n = int(math.ceil(reach / edge)) + 1
    out = []
    for i, j, k in itertools.product(range(-n, n + 1), repeat=3):
        for bx, by, bz in basis:
            r = edge * math.sqrt((i + bx) ** 2 + (j + by) ** 2 + (k + bz) ** 2)
            if r <= reach:
                out.append(r)
    return out


def lattice_sum(kernel, lattice, support):
    return sum(kernel(r, support) for r in distances(lattice, support))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--support", type=float, nargs="+", default=[2.0])
    args = parser.parse_args()
    for h in args.support:
        print(f"support {h:g} spacings (sum of W over the lattice, 1 / spacing^3; difference from sc)")
        for name, kernel in KERNELS.items():
            sc = lattice_sum(kernel, "sc", h)
            cells = []
            for lattice in LATTICES:
                s = lattice_sum(kernel, lattice, h)
                cells.append(f"{lattice} {s:.4f}" + ("" if lattice == "sc" else f" ({100 * (s / sc - 1):+.2f} %)"))
            print(f"  {name:13s} " + ", ".join(cells))


if __name__ == "__main__":
    main()
