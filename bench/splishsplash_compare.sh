#!/bin/sh
# sphfx against SPlisHSPlasH 2.16 on SPlisHSPlasH's dam break (59,319 particles, DFSPH, 1 s, caches at
# 25 fps), alternated in one run so that both see the same machine load. For each run it prints the wall
# time of the whole process and the surge front's RMS relative error against Martin & Moyce's square column
# (studies/reference/dam_break_martin_moyce_n1.csv). Both fronts are measured the same way: the
# (1 + n/1000)-th largest x plus half the run's particle spacing, Z measured from the column's back face
# at x = -1.95 m with a = 1 m, T = t sqrt(g / a), over the frames inside the experiment's range.
#
#   sh bench/splishsplash_compare.sh BUILD_DIR PEER_DIR [OUT_DIR] [ROUNDS] [-- sphfx simulate options]
#
# PEER_DIR is the portable SPlisHSPlasH package (bin/SPHSimulator, run.sh, front.py, scenes/).
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
rm -f "$out/wall" "$out/front"
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

  start=$(date +%s.%N)
  "$peer/run.sh" "$peer_scene" "$out/peer.$round" > "$out/peer.$round.log"
  end=$(date +%s.%N)
  echo "peer.$round $(seconds "$start" "$end")" >> "$out/wall"
  # front.py prints "k t front_x n" with t = (k - 1) / 25 and the peer's spacing is 2 x 0.0125 m.
  python3 "$peer/front.py" "$out/peer.$round" | awk '!/^#/ { printf "%d %s %.6f\n", $1, $2, $3 + 0.0125 }' \
    > "$out/peer.$round.front"
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
rows = {"sphfx": [], "peer": []}
for r in range(1, rounds + 1):
    for name in rows:
        rows[name].append((float(wall[f"{name}.{r}"]), front[f"{name}.{r}"]))
        print(f"{name}.{r}: wall {wall[f'{name}.{r}']} s, front RMS {front[f'{name}.{r}']:.2f} %")
ratios = [p[0] / s[0] for s, p in zip(rows["sphfx"], rows["peer"])]
print(f"speed (peer wall / sphfx wall) per round: {', '.join(f'{x:.3f}' for x in ratios)}; "
      f"median {statistics.median(ratios):.3f}")
for name, runs in rows.items():
    print(f"{name}: median wall {statistics.median(w for w, _ in runs):.2f} s, "
          f"front RMS {statistics.median(e for _, e in runs):.2f} %")
PY
