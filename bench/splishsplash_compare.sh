#!/bin/sh
# sphfx against SPlisHSPlasH 2.16 on SPlisHSPlasH's dam break (59,319 particles, DFSPH, 1 s, caches at
# 25 fps), alternated in one run so that both see the same machine load. For each run it prints the wall
# time of the whole process and the surge front's RMS relative error against Martin & Moyce's square column
# (studies/reference/dam_break_martin_moyce_n1.csv). Both fronts are measured the same way: the
# (1 + n/1000)-th largest x plus half the run's particle spacing, Z measured from the column's back face
# at x = -1.95 m with a = 1 m, T = t sqrt(g / a), over the frames inside the experiment's range. It also
# prints each run's steps, its fastest particle and its closest centre to the tank's walls (in its own
# particle spacings) over the cached frames: both step rules bound a step's travel by the fastest particle,
# so the faster one's run takes more steps.
#
#   sh bench/splishsplash_compare.sh BUILD_DIR PEER_DIR [OUT_DIR] [ROUNDS] [-- sphfx simulate options]
#
# PEER_DIR is the portable SPlisHSPlasH package (bin/SPHSimulator, run.sh, front.py, read_sph.py,
# scenes/).
set -eu
build=$1
peer=$2
out=${3:-splishsplash_compare}
rounds=${4:-2}
shift $(($# < 4 ? $# : 4))
[ "${1:-}" = "--" ] && shift
scene=scenes/dam_break_splishsplash.json
peer_scene=$peer/scenes/DamBreakModel_r0125_1s.json
reference=studies/reference/dam_break_martin_moyce_n1.csv
spacing=$(python3 -c "import json; print(json.load(open('$scene'))['fluid']['spacing'])")
mkdir -p "$out"
rm -f "$out/wall" "$out/front" "$out/flow"
# Computes the volume map the peer caches next to its scene once, outside the timed runs.
[ -d "$peer/scenes/Cache" ] || "$peer/run.sh" "$peer_scene" "$out/peer_warmup" > /dev/null

seconds() { python3 -c "print(f'{$2 - $1:.2f}')"; }
round=1
while [ "$round" -le "$rounds" ]; do
  rm -rf "$out/sphfx.$round" "$out/peer.$round"
  start=$(date +%s.%N)
  "$build/cli/sphfx" -q simulate "$scene" -o "$out/sphfx.$round" "$@"
  end=$(date +%s.%N)
  echo "sphfx.$round $(seconds "$start" "$end")" >> "$out/wall"
  "$build/bench/dam_front" "$out/sphfx.$round" "$spacing" > "$out/sphfx.$round.front"
  steps=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['simulate']['substeps'])" \
    "$out/sphfx.$round/manifest.json")
  criteria=$("$build/cli/sphfx" inspect "$out/sphfx.$round" --criteria speed walls)
  fastest=$(echo "$criteria" | sed -n 's/.*fastest \([0-9.]*\) m\/s.*/\1/p')
  closest=$(echo "$criteria" | sed -n 's/.*closest centre \([0-9.]*\) s from.*/\1/p')
  echo "sphfx.$round $steps $fastest $closest" >> "$out/flow"

  start=$(date +%s.%N)
  "$peer/run.sh" "$peer_scene" "$out/peer.$round" > "$out/peer.$round.log"
  end=$(date +%s.%N)
  echo "peer.$round $(seconds "$start" "$end")" >> "$out/wall"
  # front.py prints "k t front_x n" with t = (k - 1) / 25 and the peer's spacing is 2 x 0.0125 m.
  python3 "$peer/front.py" "$out/peer.$round" | awk '!/^#/ { printf "%d %s %.6f\n", $1, $2, $3 + 0.0125 }' \
    > "$out/peer.$round.front"
  python3 - "$peer" "$out/peer.$round" "peer.$round" "$scene" >> "$out/flow" <<'PY'
import glob, json, math, re, sys
sys.path.insert(0, sys.argv[1])
from read_sph import read_bgeo
# Steps: the log's total of the step sizes over their mean. Over the exported frames: the fastest particle,
# and the closest centre to the tank's walls (the same box as the sphfx scene's domain) in the peer's
# spacing, 2 x 0.0125 m.
log = open(sys.argv[2] + "/log/SPH_log.txt").read()
total = float(re.findall(r"Total number: Time step size: ([0-9.eE+-]+)", log)[-1])
mean = float(re.findall(r"Average number: Time step size: ([0-9.eE+-]+)", log)[-1])
domain = json.load(open(sys.argv[4]))["domain"]
fastest, closest = 0.0, math.inf
for path in glob.glob(sys.argv[2] + "/partio/ParticleData_Fluid_*.bgeo"):
    frame = read_bgeo(path)
    for v in frame["velocity"]:
        fastest = max(fastest, math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2))
    for p in frame["position"]:
        for a in range(3):
            closest = min(closest, p[a] - domain["min"][a], domain["max"][a] - p[a])
print(f"{sys.argv[3]} {round(total / mean)} {fastest:.3f} {closest / 0.025:.3f}")
PY
  round=$((round + 1))
done

for round in $(seq "$rounds"); do
  for name in sphfx peer; do
    rms=$(python3 bench/front_rms.py "$out/$name.$round.front" "$reference" --a 1 --n2 1 --back -1.95)
    echo "$name.$round ${rms%% *}" >> "$out/front"
  done
done
python3 - "$out" "$rounds" <<'PY'
import os, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
wall = dict(line.split() for line in open(os.path.join(out, "wall")))
front = {k: float(v) for k, v in (line.split() for line in open(os.path.join(out, "front")))}
flow = {}
for line in open(os.path.join(out, "flow")):
    k, n, v, c = line.split()
    flow[k] = (int(n), float(v), float(c))
rows = {"sphfx": [], "peer": []}
for r in range(1, rounds + 1):
    for name in rows:
        rows[name].append((float(wall[f"{name}.{r}"]), front[f"{name}.{r}"]))
        steps, fastest, closest = flow[f"{name}.{r}"]
        print(f"{name}.{r}: wall {wall[f'{name}.{r}']} s, front RMS {front[f'{name}.{r}']:.2f} %, "
              f"{steps} steps, fastest {fastest:.2f} m/s, closest to a wall {closest:.3f} spacings")
ratios = [p[0] / s[0] for s, p in zip(rows["sphfx"], rows["peer"])]
print(f"speed (peer wall / sphfx wall) per round: {', '.join(f'{x:.3f}' for x in ratios)}; "
      f"median {statistics.median(ratios):.3f}")
for name, runs in rows.items():
    print(f"{name}: median wall {statistics.median(w for w, _ in runs):.2f} s, "
          f"front RMS {statistics.median(e for _, e in runs):.2f} %")
PY
