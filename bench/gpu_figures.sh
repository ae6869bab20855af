#!/bin/sh
# The GPU path's figures (docs/performance.md, docs/validation.md) on a GPU render node through EGL device:
# the GL device, WCSPH throughput against particle count, the shipped dam break, showcase and nozzle under
# each solver (bench/build_compare.sh, one round), the production stability suite (docs/validation.md)
# one solver at a time, and the SPlisHSPlasH dam break against the peer on the node's cores (at the defaults
# at four resolutions, and with the surge settings, docs/performance.md). Each step has
# its own time limit (seconds, the step's first argument to `step`) so that one slow step leaves the others'
# figures; everything goes to OUT_DIR/gpu_figures.log and the suite reports to OUT_DIR/stability_SOLVER.md.
#
#   sh bench/gpu_figures.sh BUILD_DIR OUT_DIR [PEER_DIR]
#
# BUILD_DIR holds cli/sphfx and bench/{sim_bench,dam_front}; PEER_DIR the portable SPlisHSPlasH package
# (bench/splishsplash_compare.sh), skipped when absent.
set -u
build=$1
out=$2
peer=${3:-}
mkdir -p "$out"
log=$out/gpu_figures.log
export SPHFX_GL=egl-device

step() {
  limit=$1
  shift
  echo "## $* (limit $limit s)" >> "$log"
  start=$(date +%s.%N)
  timeout "$limit" "$@" >> "$log" 2>&1
  rc=$?
  echo "## rc $rc, wall $(python3 -c "print(f'{$(date +%s.%N) - $start:.1f}')") s" >> "$log"
  return $rc
}

{ nproc; nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader; } >> "$log" 2>&1
step 30 "$build/cli/sphfx" info --gl egl-device --selftest || exit 1
step 60 "$build/bench/sim_bench" --scene scenes/dam_break.json --particles 3e4 --particles 1e5 --particles 3e5 --particles 1e6 --seconds 0.02
step 40 "$build/bench/sim_bench" --scene scenes/dam_break_splishsplash.json --particles 0 --seconds 1 --fps 25
SCENES="scenes/dam_break.json scenes/showcase.json scenes/nozzle.json" OPTS_A="--set solver.method=wcsph" \
  OPTS_B="--set solver.method=dfsph" step 90 sh bench/build_compare.sh "$build" "$build" /tmp/build_compare 1 \
  -- --gl egl-device
for solver in dfsph wcsph; do
  limit=120
  [ "$solver" = wcsph ] && limit=150
  step $limit "$build/cli/sphfx" stability --suite studies/stability_production.json --solvers "$solver" \
    -o "$out/stability_$solver" --gl egl-device
  cp "$out/stability_$solver/stability.md" "$out/stability_$solver.md" 2> /dev/null
  rm -rf "$out/stability_$solver"
done
if [ -n "$peer" ] && [ -d "$peer" ]; then
  RESOLUTIONS="39 29 19 14" step 120 sh bench/splishsplash_compare.sh "$build" "$peer" \
    /tmp/splishsplash_compare 1 -- --gl egl-device
  step 60 sh bench/splishsplash_compare.sh "$build" "$peer" /tmp/splishsplash_compare 1 -- --gl egl-device \
    --set solver.dfsph.density_warm_share=0.8 --set solver.dfsph.density_warm_steps=all \
    --set solver.dfsph.depth_step_factor=0 --set time.cfl_factor=1.0
fi
