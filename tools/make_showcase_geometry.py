#!/usr/bin/env python3
"""Writes the showcase shot's set as OBJ files (scenes/geometry/): a flight of stairs and a four-bladed
paddle wheel. Both are closed surfaces; the stairs reach through the side walls (z below 0 and above the
domain's depth) so that water cannot pass beside them. Rerun after changing a dimension here:
    python3 tools/make_showcase_geometry.py
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "scenes", "geometry")


def write_obj(path, comment, vertices, faces):
    with open(path, "w") as f:
        f.write(f"# {comment}\n# written by tools/make_showcase_geometry.py\n")
        for v in vertices:
            f.write("v %.6g %.6g %.6g\n" % v)
        for face in faces:
            f.write("f " + " ".join(str(i + 1) for i in face) + "\n")


def extrude(profile, z0, z1):
    """A closed prism: the x-y polygon `profile` (counter-clockwise, star-shaped from its first vertex)
    from z0 to z1. Caps are fans from the first vertex; sides are quads."""
    n = len(profile)
    vertices = [(x, y, z0) for x, y in profile] + [(x, y, z1) for x, y in profile]
    faces = []
    for k in range(1, n - 1):
        faces.append((0, k + 1, k))  # z0 cap, facing -z
        faces.append((n, n + k, n + k + 1))  # z1 cap, facing +z
    for k in range(n):
        j = (k + 1) % n
        faces.append((k, j, n + j, n + k))
    return vertices, faces


def box(lo, hi):
    vertices = [(hi[0] if k & 1 else lo[0], hi[1] if k & 2 else lo[1], hi[2] if k & 4 else lo[2]) for k in range(8)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return vertices, faces


def stairs():
    # Four steps down from y = 0.40 to 0.10 between x = 0.05 and x = 0.85, 0.2 m treads, 0.1 m risers.
    profile = [(0.05, 0.0), (0.85, 0.0), (0.85, 0.10), (0.65, 0.10), (0.65, 0.20), (0.45, 0.20),
               (0.45, 0.30), (0.25, 0.30), (0.25, 0.40), (0.05, 0.40)]
    return extrude(profile, -0.05, 0.35)


def paddle_wheel():
    # Two crossed blades, 0.24 m tip to tip, 0.02 m thick, across the channel's depth, centred on the
    # file's origin (the wheel's pivot).
    vertices, faces = [], []
    for lo, hi in (((-0.12, -0.01, 0.02), (0.12, 0.01, 0.28)), ((-0.01, -0.12, 0.02), (0.01, 0.12, 0.28))):
        v, f = box(lo, hi)
        faces += [tuple(i + len(vertices) for i in face) for face in f]
        vertices += v
    return vertices, faces


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    write_obj(os.path.join(OUT, "stairs.obj"), "showcase: a flight of four stairs (closed prism)", *stairs())
    write_obj(os.path.join(OUT, "paddle_wheel.obj"), "showcase: a four-bladed paddle wheel (two closed boxes)",
              *paddle_wheel())
