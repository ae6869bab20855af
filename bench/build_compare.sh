#!/bin/sh
# Two builds of sphfx on the default shots, alternated in one run so that both see the same machine load:
# the wall time of `sphfx simulate` on scenes/showcase.json (the default shot) and scenes/dam_break.json,
# and the dam break's front against Martin & Moyce's n^2 = 2 column (relative RMS over T = t sqrt(2 g / a)
# <= 3, a = 0.2 m, studies/reference/dam_break_martin_moyce_n2.csv; the front as bench/dam_front gives it).
#
#   sh bench/build_compare.sh BUILD_A BUILD_B [OUT_DIR] [ROUNDS] [-- sphfx simulate options]
#
# Each BUILD holds cli/sphfx and bench/dam_front. OPTS_A and OPTS_B (environment) add options to one
# build's runs only, so that one build with and without a setting compares the same way. SCENES
# (environment) replaces the scene list, e.g. SCENES="scenes/showcase.json scenes/nozzle.json".
# Prints one line per run, then the median ratios B / A.
set -eu
a=$1
b=$2
out=${3:-build_compare}
rounds=${4:-2}
shift $(($# < 4 ? $# : 4))
[ "${1:-}" = "--" ] && shift
mkdir -p "$out"
rm -f "$out/runs"

run() {
  build=$1 label=$2 scene=$3 round=$4
  shift 4
  shot=$out/$label.$(basename "$scene" .json).$round
  rm -rf "$shot"
  start=$(date +%s.%N)
  "$build/cli/sphfx" -q simulate "$scene" -o "$shot" "$@"
  end=$(date +%s.%N)
  front=-
  if [ "$(basename "$scene")" = dam_break.json ]; then
    "$build/bench/dam_front" "$shot" 0.01 > "$shot.front"
    front=$(python3 bench/front_rms.py "$shot.front" studies/reference/dam_break_martin_moyce_n2.csv \
      --a 0.2 --n2 2 --max-T 3 | cut -d' ' -f1)
  fi
  wall=$(python3 -c "print(f'{$end - $start:.2f}')")
  echo "$label $(basename "$scene" .json) $round $wall $front" | tee -a "$out/runs"
}

round=1
while [ "$round" -le "$rounds" ]; do
  for scene in ${SCENES:-scenes/dam_break.json scenes/showcase.json}; do
    # shellcheck disable=SC2086 # OPTS_A and OPTS_B are lists of options
    run "$a" A "$scene" "$round" "$@" ${OPTS_A:-}
    # shellcheck disable=SC2086
    run "$b" B "$scene" "$round" "$@" ${OPTS_B:-}
  done
  round=$((round + 1))
done

python3 - "$out/runs" <<'PY'
import statistics, sys
runs = [line.split() for line in open(sys.argv[1])]
for scene in sorted({r[1] for r in runs}):
    wall = {k: [float(r[3]) for r in runs if r[0] == k and r[1] == scene] for k in "AB"}
    ratios = [b / a for a, b in zip(wall["A"], wall["B"])]
    fronts = {k: [r[4] for r in runs if r[0] == k and r[1] == scene] for k in "AB"}
    print(f"{scene}: wall A {statistics.median(wall['A']):.2f} s, B {statistics.median(wall['B']):.2f} s, "
          f"B / A per round {', '.join(f'{x:.3f}' for x in ratios)}; front RMS A {fronts['A'][0]} %, "
          f"B {fronts['B'][0]} %")
PY
