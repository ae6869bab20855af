#!/bin/sh
# Self-convergence of the dam-break front: studies/scenes/dam_break.json (a = 0.2 m, 0.6 s) at spacings
# a/10, a/20, a/40 and a/80 against a run of ours at a/160 (2.46 million particles: a GPU node's job),
# for each solver. Error of a run: the RMS over the frames from t = 0.05 s until the reference front
# reaches 0.9 m (before the far wall at 1 m) of (x - x_ref) / (x_ref - 0.2), the surge distance; x is
# bench/dam_front's front. Prints each run's error and wall time and the observed order between
# successive spacings and as the least-squares slope. A run that stops (exit 3) is reported and left out;
# the finest completed run is then the reference.
#
#   sh bench/dam_self_convergence.sh BUILD_DIR [OUT_DIR] [-- sphfx simulate options]
#
# DIVISIONS="40 20 10" runs a smaller ladder, SOLVERS="dfsph" one solver.
set -eu
build=$1
out=${2:-dam_self_convergence}
shift $(($# < 2 ? $# : 2))
[ "${1:-}" = "--" ] && shift
scene=studies/scenes/dam_break.json
mkdir -p "$out"
rm -f "$out/runs"
for solver in ${SOLVERS:-wcsph dfsph}; do
  for divisions in ${DIVISIONS:-160 80 40 20 10}; do
    spacing=$(python3 -c "print(0.2 / $divisions)")
    shot=$out/$solver.$divisions
    rm -rf "$shot"
    start=$(date +%s.%N)
    status=completed
    "$build/cli/sphfx" -q simulate "$scene" -o "$shot" --set solver.method="$solver" \
      --set fluid.spacing="$spacing" "$@" || status=stopped
    end=$(date +%s.%N)
    [ "$status" = completed ] && "$build/bench/dam_front" "$shot" "$spacing" > "$shot.front"
    rm -rf "$shot"
    echo "$solver $divisions $(python3 -c "print(f'{$end - $start:.2f}')") $status" >> "$out/runs"
  done
done

python3 - "$out" <<'PY'
import math, os, sys
out = sys.argv[1]
runs = [line.split() for line in open(os.path.join(out, "runs"))]
def front(solver, n):
    return {int(f): (float(t), float(x)) for f, t, x in
            (line.split() for line in open(os.path.join(out, f"{solver}.{n}.front")))}
for solver in ("wcsph", "dfsph"):
    for s, n, wall, status in runs:
        if s == solver and status != "completed":
            print(f"{solver}: a/{n} stopped after {float(wall):.1f} s (see above)")
    done = sorted(((int(n), float(w)) for s, n, w, status in runs if s == solver and status == "completed"),
                  reverse=True)
    if len(done) < 2:
        continue
    (reference, ref_wall), others = done[0], sorted(done[1:])
    ref = front(solver, reference)
    frames = [f for f, (t, x) in sorted(ref.items()) if t >= 0.05]
    frames = frames[:next((k for k, f in enumerate(frames) if ref[f][1] > 0.9), len(frames))]
    rows = []
    for n, wall in others:
        run = front(solver, n)
        e = [(run[f][1] - ref[f][1]) / (ref[f][1] - 0.2) for f in frames]
        rows.append((n, math.sqrt(sum(v * v for v in e) / len(e)), wall))
    print(f"{solver}: reference a/{reference} ({ref_wall:.1f} s); {len(frames)} frames, t "
          f"{ref[frames[0]][0]:.3f}-{ref[frames[-1]][0]:.3f} s")
    for k, (n, err, wall) in enumerate(rows):
        order = "" if k == 0 else f", order {math.log(rows[k - 1][1] / err) / math.log(n / rows[k - 1][0]):.2f}"
        print(f"  a/{n}: error {100 * err:.2f} %, wall {wall:.2f} s{order}")
    if len(rows) > 1:
        xs = [math.log(0.2 / n) for n, _, _ in rows]
        ys = [math.log(err) for _, err, _ in rows]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        print(f"  observed order (least squares over the spacing): {slope:.2f}")
PY
