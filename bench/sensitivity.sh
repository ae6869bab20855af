#!/bin/sh
# Sensitivity of the dam-break front to the stabilising parameters: each one halved and doubled around
# its default, one at a time, for both solvers, on studies/scenes/dam_break.json (a = 0.2 m, s = a/20,
# 0.6 s). Prints each variant's largest relative change of the front position against the default run
# (frames from t = 0.1 s), and the wall time of each run; a variant that stops is reported as stopped.
# The parameters: Monaghan's alpha, the speed of sound (WCSPH's EOS; both solvers' viscosity), the
# walls' drag (fluid.wall_viscosity_factor, which multiplies fluid.wall_viscosity_speed; left out when
# the common options set it), the time step's factors (time.cfl_factor; WCSPH's force factor, DFSPH's
# fall factor and depth cap), DFSPH's density tolerance, DFSPH's density warm share (0.5, or the common
# options' value when above 0: halved, and doubled up to 1), the surface particles' wall contact
# (fluid.wall_contact: halved, and doubled up to its largest value, 1), and with the friction walls
# (fluid.wall_drag=friction in the common options) their skin friction, fluid.wall_friction (0.005).
#
#   sh bench/sensitivity.sh [BUILD_DIR] [OUT_DIR] ["--set KEY=VALUE ..." applied to every run] [SOLVERS]
#
# SOLVERS: "wcsph dfsph" (default), or one of them.
set -eu
build=${1:-build}
out=${2:-sensitivity}
common=${3:-}
solvers=${4:-wcsph dfsph}
scene=studies/scenes/dam_break.json
mkdir -p "$out"
run() {
  name=$1
  shift
  rm -rf "${out:?}/$name"
  start=$(date +%s.%N)
  rm -f "$out/$name.front"
  # shellcheck disable=SC2086 # $common is a list of options
  if "$build/cli/sphfx" -q simulate "$scene" -o "$out/$name" $common "$@"; then
    "$build/bench/dam_front" "$out/$name" 0.01 > "$out/$name.front"
  fi
  end=$(date +%s.%N)
  echo "$name: $(python3 -c "print(f'{$end - $start:.1f}')") s"
}
case "$common" in
  *wall_viscosity_factor*) wall_factor=no ;;
  *) wall_factor=yes ;;
esac
case "$common" in
  *wall_drag=friction*) friction=yes ;;
  *) friction=no ;;
esac
warm_share=$(printf '%s\n' "$common" | sed -n 's/.*density_warm_share=\([0-9.]*\).*/\1/p')
warm_share=${warm_share:-0.5}  # DFSPH's default
case " $solvers " in *" wcsph "*)
  run wcsph
  run wcsph_alpha_0.01 --set fluid.artificial_viscosity=0.01
  run wcsph_alpha_0.04 --set fluid.artificial_viscosity=0.04
  run wcsph_c_12.5 --set solver.speed_of_sound=12.5
  run wcsph_c_50 --set solver.speed_of_sound=50
  run wcsph_cfl_0.2 --set time.cfl_factor=0.2
  run wcsph_cfl_0.8 --set time.cfl_factor=0.8
  run wcsph_force_0.125 --set solver.wcsph.force_factor=0.125
  run wcsph_force_0.5 --set solver.wcsph.force_factor=0.5
  if [ "$wall_factor" = yes ]; then
    run wcsph_wallvisc_0.5 --set fluid.wall_viscosity_factor=0.5
    run wcsph_wallvisc_2 --set fluid.wall_viscosity_factor=2
  fi
  run wcsph_contact_0.3 --set fluid.wall_contact=0.3
  run wcsph_contact_1 --set fluid.wall_contact=1
  if [ "$friction" = yes ]; then
    run wcsph_friction_0.0025 --set fluid.wall_friction=0.0025
    run wcsph_friction_0.01 --set fluid.wall_friction=0.01
  fi
  ;;
esac
case " $solvers " in *" dfsph "*)
  run dfsph --set solver.method=dfsph
  run dfsph_alpha_0.01 --set solver.method=dfsph --set fluid.artificial_viscosity=0.01
  run dfsph_alpha_0.04 --set solver.method=dfsph --set fluid.artificial_viscosity=0.04
  run dfsph_c_12.5 --set solver.method=dfsph --set solver.speed_of_sound=12.5
  run dfsph_c_50 --set solver.method=dfsph --set solver.speed_of_sound=50
  run dfsph_cfl_0.2 --set solver.method=dfsph --set time.cfl_factor=0.2
  run dfsph_cfl_0.8 --set solver.method=dfsph --set time.cfl_factor=0.8
  run dfsph_fall_0.075 --set solver.method=dfsph --set solver.dfsph.fall_factor=0.075
  run dfsph_fall_0.3 --set solver.method=dfsph --set solver.dfsph.fall_factor=0.3
  run dfsph_error_0.0005 --set solver.method=dfsph --set solver.dfsph.max_density_error=0.0005
  run dfsph_error_0.002 --set solver.method=dfsph --set solver.dfsph.max_density_error=0.002
  run dfsph_depth_0.2 --set solver.method=dfsph --set solver.dfsph.depth_step_factor=0.2
  run dfsph_depth_0.8 --set solver.method=dfsph --set solver.dfsph.depth_step_factor=0.8
  if [ "$wall_factor" = yes ]; then
    run dfsph_wallvisc_0.5 --set solver.method=dfsph --set fluid.wall_viscosity_factor=0.5
    run dfsph_wallvisc_2 --set solver.method=dfsph --set fluid.wall_viscosity_factor=2
  fi
  run dfsph_contact_0.3 --set solver.method=dfsph --set fluid.wall_contact=0.3
  run dfsph_contact_1 --set solver.method=dfsph --set fluid.wall_contact=1
  if [ "$friction" = yes ]; then
    run dfsph_friction_0.0025 --set solver.method=dfsph --set fluid.wall_friction=0.0025
    run dfsph_friction_0.01 --set solver.method=dfsph --set fluid.wall_friction=0.01
  fi
  if [ -n "$warm_share" ] && python3 -c "import sys; sys.exit(not float('$warm_share') > 0)"; then
    for share in $(python3 -c "s = float('$warm_share'); print(f'{s / 2:g} {min(2 * s, 1):g}')"); do
      run "dfsph_warm_$share" --set solver.method=dfsph --set "solver.dfsph.density_warm_share=$share"
    done
  fi
  ;;
esac
python3 - "$out" <<'PY'
import glob, os, sys
out = sys.argv[1]
def load(name):
    rows = [line.split() for line in open(os.path.join(out, name + ".front"))]
    return {int(f): (float(t), float(x)) for f, t, x in rows}
for base in ("wcsph", "dfsph"):
    if not os.path.exists(os.path.join(out, base + ".front")):
        continue
    ref = load(base)
    for path in sorted(glob.glob(os.path.join(out, base + "_*")), key=os.path.basename):
        name = os.path.basename(path)
        if not os.path.isdir(path):
            continue
        if not os.path.exists(path + ".front"):
            print(f"{name}: stopped (its error is above)")
            continue
        run = load(name)
        worst, when = max((abs(run[f][1] - x) / x, t) for f, (t, x) in ref.items() if t >= 0.1 and f in run)
        print(f"{name}: largest front change {100 * worst:.2f} % (t = {when:.3f} s)")
PY
