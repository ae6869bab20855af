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
#
# RESOLUTIONS (environment; default 39): particles along the column's edge, one run pair per value in each
# round. SPlisHSPlasH fills the 1 m column with n^3 particles at radius 1 / (2 (n + 1)) (its scene: 0.0125,
# n = 39), sphfx at spacing 1 / n (its scene's own at 39), so both runs of a pair have the same particles.
# The summary gives each code's error against run time: per resolution the median wall time and front, and
# for each SPlisHSPlasH resolution the fastest sphfx resolution whose front is no further from the
# experiment, with the ratio of their wall times.
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
resolutions=${RESOLUTIONS:-39}
scene_spacing=$(python3 -c "import json; print(json.load(open('$scene'))['fluid']['spacing'])")
mkdir -p "$out"
rm -f "$out/wall" "$out/front" "$out/flow"

# The peer's scene at n particles along the column's edge: its own file at 39, else a copy in OUT_DIR
# (write_peer_scene) whose tank mesh is the package's (SPlisHSPlasH caches the tank's volume map, per
# radius, in Cache/ next to the scene file).
peer_scene_for() { if [ "$1" = 39 ]; then echo "$peer_scene"; else echo "$out/peer_scene.$1.json"; fi; }
write_peer_scene() {
  python3 - "$peer_scene" "$1" "$(peer_scene_for "$1")" <<'PY'
import json, os, sys
source, n, target = sys.argv[1], int(sys.argv[2]), sys.argv[3]
scene = json.load(open(source))
scene["Configuration"]["particleRadius"] = 0.5 / (n + 1)
for body in scene.get("RigidBodies", []):
    body["geometryFile"] = os.path.join(os.path.dirname(os.path.abspath(source)), body["geometryFile"])
json.dump(scene, open(target, "w"), indent=1)
PY
}
# sphfx's spacing at n (its scene's own at 39) and the options that set it.
sphfx_spacing() { if [ "$1" = 39 ]; then echo "$scene_spacing"; else python3 -c "print(1 / $1)"; fi; }
sphfx_spacing_options() { [ "$1" = 39 ] || echo "--set fluid.spacing=$(sphfx_spacing "$1")"; }
peer_radius() { python3 -c "print(0.5 / ($1 + 1))"; }

# Writes the copies, and computes each scene's volume map once, outside the timed runs (a marker in
# OUT_DIR for the copies).
for n in $resolutions; do
  [ "$n" = 39 ] || write_peer_scene "$n"
  if [ "$n" = 39 ]; then warmed=$peer/scenes/Cache; else warmed=$out/peer_cache.$n; fi
  [ -e "$warmed" ] && continue
  "$peer/run.sh" "$(peer_scene_for "$n")" "$out/peer_warmup.$n" > /dev/null
  rm -rf "$out/peer_warmup.$n"
  [ "$n" = 39 ] || touch "$warmed"
done

seconds() { python3 -c "print(f'{$2 - $1:.2f}')"; }
run_sphfx() {  # n round [sphfx options]
  name=sphfx.$1.$2
  n=$1
  shift 2
  rm -rf "${out:?}/$name"
  start=$(date +%s.%N)
  # shellcheck disable=SC2046 # the spacing option is two words or none
  "$build/cli/sphfx" -q simulate "$scene" -o "$out/$name" $(sphfx_spacing_options "$n") "$@"
  end=$(date +%s.%N)
  echo "$name $(seconds "$start" "$end")" >> "$out/wall"
  "$build/bench/dam_front" "$out/$name" "$(sphfx_spacing "$n")" > "$out/$name.front"
  steps=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['simulate']['substeps'])" \
    "$out/$name/manifest.json")
  criteria=$("$build/cli/sphfx" inspect "$out/$name" --criteria speed walls)
  fastest=$(echo "$criteria" | sed -n 's/.*fastest \([0-9.]*\) m\/s.*/\1/p')
  closest=$(echo "$criteria" | sed -n 's/.*closest centre at ([^)]*) m, \([0-9.]*\) spacings from.*/\1/p')
  echo "$name $steps $fastest $closest" >> "$out/flow"
}
run_peer() {  # n round
  name=peer.$1.$2
  radius=$(peer_radius "$1")
  rm -rf "${out:?}/$name"
  start=$(date +%s.%N)
  "$peer/run.sh" "$(peer_scene_for "$1")" "$out/$name" > "$out/$name.log"
  end=$(date +%s.%N)
  echo "$name $(seconds "$start" "$end")" >> "$out/wall"
  # front.py prints "k t front_x n" with t = (k - 1) / 25; half the peer's spacing is its radius.
  python3 "$peer/front.py" "$out/$name" | awk -v r="$radius" '!/^#/ { printf "%d %s %.6f\n", $1, $2, $3 + r }' \
    > "$out/$name.front"
  python3 - "$peer" "$out/$name" "$name" "$scene" "$radius" >> "$out/flow" <<'PY'
import glob, json, math, re, sys
sys.path.insert(0, sys.argv[1])
from read_sph import read_bgeo
# Steps: the log's total of the step sizes over their mean. Over the exported frames: the fastest particle,
# and the closest centre to the tank's walls (the same box as the sphfx scene's domain) in the peer's
# spacing, twice its radius.
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
print(f"{sys.argv[3]} {round(total / mean)} {fastest:.3f} {closest / (2 * float(sys.argv[5])):.3f}")
PY
}

round=1
while [ "$round" -le "$rounds" ]; do
  for n in $resolutions; do
    run_sphfx "$n" "$round" "$@"
    run_peer "$n" "$round"
  done
  round=$((round + 1))
done

for name in $(cut -d' ' -f1 "$out/wall"); do
  rms=$(python3 bench/front_rms.py "$out/$name.front" "$reference" --a 1 --n2 1 --back -1.95)
  echo "$name ${rms%% *}" >> "$out/front"
done
python3 - "$out" "$rounds" "$resolutions" <<'PY'
import os, statistics, sys
out, rounds, resolutions = sys.argv[1], int(sys.argv[2]), [int(n) for n in sys.argv[3].split()]
read = lambda name: dict(line.split(maxsplit=1) for line in open(os.path.join(out, name)))
wall = {k: float(v) for k, v in read("wall").items()}
front = {k: float(v) for k, v in read("front").items()}
flow = {k: v.split() for k, v in read("flow").items()}
for r in range(1, rounds + 1):
    for n in resolutions:
        for code in ("sphfx", "peer"):
            name = f"{code}.{n}.{r}"
            steps, fastest, closest = flow[name]
            print(f"{name}: {n ** 3} particles, wall {wall[name]:.2f} s, front RMS {front[name]:.2f} %, "
                  f"{steps} steps, fastest {float(fastest):.2f} m/s, closest to a wall {closest} spacings")
median = {}
for n in resolutions:
    ratios = [wall[f"peer.{n}.{r}"] / wall[f"sphfx.{n}.{r}"] for r in range(1, rounds + 1)]
    print(f"{n ** 3} particles: speed (peer wall / sphfx wall) per round "
          f"{', '.join(f'{x:.3f}' for x in ratios)}; median {statistics.median(ratios):.3f}")
    for code in ("sphfx", "peer"):
        runs = [f"{code}.{n}.{r}" for r in range(1, rounds + 1)]
        median[code, n] = (statistics.median(wall[k] for k in runs), statistics.median(front[k] for k in runs))
        print(f"  {code}: median wall {median[code, n][0]:.2f} s, front RMS {median[code, n][1]:.2f} %")
# Each code against its own finest resolution of this run (round 1): the RMS relative difference of the
# surge position Z = front_x + 1.95 m over the frames after the start, so what refining still changes.
def surge(name):
    rows = (line.split() for line in open(os.path.join(out, name + ".front")))
    return {round(float(t), 4): float(x) + 1.95 for _, t, x in rows if float(t) > 0}
finest = max(resolutions)
for code in ("sphfx", "peer"):
    reference = surge(f"{code}.{finest}.1")
    for n in resolutions:
        if n == finest:
            continue
        run = surge(f"{code}.{n}.1")
        d = [(run[t] - z) / z for t, z in reference.items() if t in run]
        print(f"{code} at {n ** 3} against its {finest ** 3}: front {100 * statistics.fmean(x * x for x in d) ** 0.5:.2f} % RMS")
# Error against run time: for each peer resolution, the cheapest sphfx one at no more error (medians).
for n in resolutions:
    peer_wall, peer_front = median["peer", n]
    fits = [m for m in resolutions if median["sphfx", m][1] <= peer_front]
    if not fits:
        print(f"peer at {n ** 3}: no sphfx resolution reaches its front RMS {peer_front:.2f} %")
        continue
    m = min(fits, key=lambda m: median["sphfx", m][0])
    sphfx_wall, sphfx_front = median["sphfx", m]
    print(f"peer at {n ** 3} ({peer_wall:.2f} s, {peer_front:.2f} %): sphfx at {m ** 3} ({sphfx_wall:.2f} s, "
          f"{sphfx_front:.2f} %), speed {peer_wall / sphfx_wall:.3f}")
PY
