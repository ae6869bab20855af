#!/usr/bin/env python3
"""Independent PLY reader (Python standard library only) for the surfacing tests.

Parses a binary little-endian PLY with float x y z nx ny nz vertices and "list uchar int" faces, checks
that every face is a triangle indexing existing vertices and that normals are unit length, and prints
"vertices V faces F volume VOL area A" (volume by the divergence theorem). Exit 1 with a message if the
file is malformed.
"""
import math
import struct
import sys


def fail(msg):
    print(f"check_ply: {msg}", file=sys.stderr)
    sys.exit(1)


def main(path):
    data = open(path, "rb").read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        fail("not a PLY file")
    header = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in header:
        fail("not binary little endian")
    nv = nf = None
    props = []
    for line in header:
        w = line.split()
        if w[:2] == ["element", "vertex"]:
            nv = int(w[2])
        elif w[:2] == ["element", "face"]:
            nf = int(w[2])
        elif w[0] == "property" and nf is None:
            props.append((w[1], w[2]))
    if props != [("float", n) for n in ("x", "y", "z", "nx", "ny", "nz")]:
        fail(f"unexpected vertex properties {props}")
    off = end + len(b"end_header\n")
    verts = [struct.unpack_from("<6f", data, off + 24 * i) for i in range(nv)]
    off += 24 * nv
    faces = []
    for _ in range(nf):
        (n,) = struct.unpack_from("<B", data, off)
        if n != 3:
            fail(f"face with {n} vertices")
        faces.append(struct.unpack_from("<3i", data, off + 1))
        off += 13
    if off != len(data):
        fail(f"{len(data) - off} trailing bytes")
    for v in verts:
        if abs(math.sqrt(v[3] ** 2 + v[4] ** 2 + v[5] ** 2) - 1) > 1e-3:
            fail(f"normal not unit length: {v[3:]}")
    vol = area = 0.0
    for f in faces:
        if min(f) < 0 or max(f) >= nv:
            fail(f"face {f} indexes past {nv} vertices")
        a, b, c = (verts[i][:3] for i in f)
        u = [b[k] - a[k] for k in range(3)]
        w = [c[k] - a[k] for k in range(3)]
        n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        vol += sum(a[k] * n[k] for k in range(3)) / 6
        area += math.sqrt(sum(x * x for x in n)) / 2
    print(f"vertices {nv} faces {nf} volume {vol:.9g} area {area:.9g}")


if __name__ == "__main__":
    main(sys.argv[1])
