#!/bin/sh
# SPlisHSPlasH 2.16's DFSPH on our resting tank (scenes/hydrostatic.json: 0.2 x 0.4 x 0.2 m box, water
# 0.3 m deep, particle spacing 0.01 m), 10 s, with the settings of its own dam break (volume-map walls,
# standard viscosity 0.01, tolerances 0.05 % / 0.1 %, CFL steps up to 5 ms). It fills the block from one
# spacing inside the walls (10,469 particles). Prints, as `sphfx inspect` does for ours, the kinetic
# energy per unit mass over the last quarter of the run, the fastest particle and the closest approach
# to a wall, with the wall time (docs/validation.md, Known limits).
#
#   sh bench/splishsplash_rest.sh PEER_DIR [OUT_DIR]
#
# PEER_DIR is the portable SPlisHSPlasH package (bin/SPHSimulator, run.sh, read_sph.py, scenes/).
set -eu
peer=$1
out=${2:-splishsplash_rest}
mkdir -p "$out"
cp "$peer/scenes/UnitBox.obj" "$out/"
python3 - "$peer/scenes/DamBreakModel_r0125_1s.json" "$out/rest.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
config = scene["Configuration"]
config.update(particleRadius=0.005, stopAt=10.0, dataExportFPS=24)
walls = scene["RigidBodies"][0]
walls.update(translation=[0.1, 0.2, 0.1], scale=[0.2, 0.4, 0.2], mapResolution=[20, 40, 20])
scene["FluidBlocks"][0].update(start=[0, 0, 0], end=[0.2, 0.3, 0.2], translation=[0, 0, 0])
json.dump(scene, open(sys.argv[2], "w"), indent=1)
PY
rm -rf "$out/run"
"$peer/run.sh" "$out/rest.json" "$out/run" > "$out/run.log"
tail -n 1 "$out/run.log"
python3 - "$peer" "$out/run" <<'PY'
import glob, math, re, sys
sys.path.insert(0, sys.argv[1])
from read_sph import read_bgeo
spacing, box = 0.01, (0.2, 0.4, 0.2)
frames = []
for path in glob.glob(sys.argv[2] + "/partio/ParticleData_Fluid_*.bgeo"):
    k = int(re.search(r"_(\d+)\.bgeo$", path).group(1))
    d = read_bgeo(path)
    speeds = [math.sqrt(a * a + b * b + c * c) for a, b, c in d["velocity"]]
    closest = min(min(p[0], box[0] - p[0], p[1], p[2], box[2] - p[2]) for p in d["position"]) / spacing
    frames.append(((k - 1) / 24, sum(0.5 * s * s for s in speeds) / len(speeds), max(speeds), closest, len(speeds)))
frames.sort()
end = frames[-1][0]
last = [f for f in frames if f[0] >= 0.75 * end]
print(f"particles {frames[-1][4]}, {end:.2f} s: KE/m {sum(f[1] for f in last) / len(last):.3e} J/kg (last quarter), "
      f"fastest {max(f[2] for f in frames):.3f} m/s, closest centre {min(f[3] for f in frames):.3f} spacings from a wall")
PY
