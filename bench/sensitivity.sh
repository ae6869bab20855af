#!/bin/sh
# Sensitivity of the dam-break front to the stabilising parameters: each one halved and doubled around
# its default, one at a time, for both solvers, on studies/scenes/dam_break.json (a = 0.2 m, s = a/20,
# 0.6 s). Prints each variant's largest relative change of the front position against the default run
# (frames from t = 0.1 s), and the wall time of each run.
#
#   sh bench/sensitivity.sh [BUILD_DIR] [OUT_DIR] ["--set KEY=VALUE ..." applied to every run]
set -eu
build=${1:-build}
out=${2:-sensitivity}
common=${3:-}
scene=studies/scenes/dam_break.json
mkdir -p "$out"
run() {
  name=$1
  shift
  rm -rf "${out:?}/$name"
  start=$(date +%s.%N)
  # shellcheck disable=SC2086 # $common is a list of options
  "$build/cli/sphfx" -q simulate "$scene" -o "$out/$name" $common "$@"
  end=$(date +%s.%N)
  "$build/bench/dam_front" "$out/$name" 0.01 > "$out/$name.front"
  echo "$name: $(python3 -c "print(f'{$end - $start:.1f}')") s"
}
run wcsph
run wcsph_alpha_0.01 --set fluid.artificial_viscosity=0.01
run wcsph_alpha_0.04 --set fluid.artificial_viscosity=0.04
run wcsph_c_12.5 --set solver.speed_of_sound=12.5
run wcsph_c_50 --set solver.speed_of_sound=50
run dfsph --set solver.method=dfsph
run dfsph_alpha_0.01 --set solver.method=dfsph --set fluid.artificial_viscosity=0.01
run dfsph_alpha_0.04 --set solver.method=dfsph --set fluid.artificial_viscosity=0.04
run dfsph_error_0.0005 --set solver.method=dfsph --set solver.dfsph.max_density_error=0.0005
run dfsph_error_0.002 --set solver.method=dfsph --set solver.dfsph.max_density_error=0.002
python3 - "$out" <<'PY'
import glob, os, sys
out = sys.argv[1]
def load(name):
    rows = [line.split() for line in open(os.path.join(out, name + ".front"))]
    return {int(f): (float(t), float(x)) for f, t, x in rows}
for base in ("wcsph", "dfsph"):
    ref = load(base)
    for path in sorted(glob.glob(os.path.join(out, base + "_*.front"))):
        name = os.path.basename(path)[:-6]
        run = load(name)
        worst, when = max((abs(run[f][1] - x) / x, t) for f, (t, x) in ref.items() if t >= 0.1 and f in run)
        print(f"{name}: largest front change {100 * worst:.2f} % (t = {when:.3f} s)")
PY
