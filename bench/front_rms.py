#!/usr/bin/env python3
"""Relative RMS error of a dam-break front against a Martin & Moyce table.

  python3 bench/front_rms.py FRONT REFERENCE_CSV --a A --n2 N2 [--back X] [--min-T T] [--max-T T] [--frames]

FRONT holds "frame time front_x" lines (bench/dam_front). The surge position is Z = (front_x - back) / a
and the time T = n t sqrt(g / a) with n^2 = N2 (Martin & Moyce 1952); REFERENCE_CSV has columns T, Z
('#' lines are its source). Frames outside the table's range, before --min-T or past --max-T, are skipped.
Prints the RMS of (Z - Z_ref) / Z_ref in per cent and the number of frames compared; exits 2 when none is.
--frames first prints each compared frame's T, Z, Z_ref and signed error in per cent (negative: behind).
"""
import argparse
import csv
import math
import sys


def read_reference(path):
    rows = csv.DictReader(line for line in open(path) if not line.startswith("#"))
    return [(float(r["T"]), float(r["Z"])) for r in rows]


def interpolate(table, T):
    for (t0, z0), (t1, z1) in zip(table, table[1:]):
        if t0 <= T <= t1:
            return z0 + (z1 - z0) * (T - t0) / (t1 - t0)
    return None


def compared_frames(front_path, table, a, n2, back, max_T, g=9.81, min_T=0.0):
    """(T, Z, Z_ref) of each frame inside the table's range and [min_T, max_T]."""
    frames = []
    for line in open(front_path):
        _, t, x = line.split()
        T = math.sqrt(n2) * float(t) * math.sqrt(g / a)
        z = interpolate(table, T) if min_T <= T <= max_T else None
        if z is not None:
            frames.append((T, (float(x) - back) / a, z))
    return frames


def frame_errors(frames):
    """(Z - Z_ref) / Z_ref of each compared frame."""
    return [(z - ref) / ref for _, z, ref in frames]


def relative_errors(front_path, table, a, n2, back, max_T, g=9.81, min_T=0.0):
    return frame_errors(compared_frames(front_path, table, a, n2, back, max_T, g, min_T))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("front")
    parser.add_argument("reference")
    parser.add_argument("--a", type=float, required=True, help="column width a (m)")
    parser.add_argument("--n2", type=float, required=True, help="column height / width, n^2")
    parser.add_argument("--back", type=float, default=0.0, help="x of the column's back face (m)")
    parser.add_argument("--min-T", type=float, default=0.0, help="first T compared")
    parser.add_argument("--max-T", type=float, default=math.inf, help="last T compared")
    parser.add_argument("--frames", action="store_true", help="print each compared frame first")
    args = parser.parse_args()
    table = read_reference(args.reference)
    frames = compared_frames(args.front, table, args.a, args.n2, args.back, args.max_T, min_T=args.min_T)
    errors = frame_errors(frames)
    if args.frames:
        for (T, z, ref), e in zip(frames, errors):
            print(f"T {T:.2f} Z {z:.3f} Z_ref {ref:.3f} {100 * e:+.1f} %")
    if not errors:
        sys.exit(f"front_rms: {args.front}: no frame inside {args.reference}'s range of T")
    print(f"{100 * math.sqrt(sum(e * e for e in errors) / len(errors)):.2f} {len(errors)}")


if __name__ == "__main__":
    main()
