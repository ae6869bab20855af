#!/usr/bin/env python3
# Run-time estimate of a study (studies/full.json) from a cost model calibrated on a finished study's
# results.csv (the quick study's): wall = particles x steps / throughput(particles) + 0.5 s start-up,
# throughput interpolated (log of particles) between the measured runs; steps = simulated time / dt
# with dt from the CFL (WCSPH: cfl h / (c + v); DFSPH: cfl spacing / v), viscous and dt_max limits
# (flow speed v: 4 m/s dam break, 0.5 m/s hydrostatic, 3 mm/s Poiseuille, 0.1 m/s Taylor-Green) or
# the fixed dt; a DFSPH step counted as DFSPH_STEP_COST WCSPH steps (measured on the dam break,
# docs/validation.md).
# Runs that stop early on a health check (fixed dt above the stable one) make the real study shorter.
# Usage: python3 studies/estimate_runtime.py studies/full.json docs/quick-study/results.csv
import json, math, itertools, sys, csv
study = json.load(open(sys.argv[1]))
scenes = {}
def load(p): return json.load(open('studies/' + p))
def lattice(lo, hi, s): return max(0, math.floor((hi - lo) / s + 1e-6))
# throughput (particle-steps/s) against particles, from the quick study rows
pts = []
for r in csv.DictReader(open(sys.argv[2])):
    if r['status'] == 'completed': pts.append((int(r['particles']), float(r['particle_steps_per_s'])))
pts.sort()
def throughput(n):
    if n <= pts[0][0]: return pts[0][1]
    if n >= pts[-1][0]: return pts[-1][1]
    for (n0, t0), (n1, t1) in zip(pts, pts[1:]):
        if n0 <= n <= n1:
            return t0 + (t1 - t0) * (math.log(n) - math.log(n0)) / (math.log(n1) - math.log(n0) or 1)
DFSPH_STEP_COST = 5.5
total = 0; per = {}
for c in study['cases']:
    sc = load(c['scene'])
    sets = dict(kv.split('=') for kv in c.get('set', []))
    axes = [[(a['path'], v) for v in a['values']] for a in c['axes']]
    for point in itertools.product(*axes):
        p = dict(sets); p.update({k: v for k, v in point})
        s = float(p.get('fluid.spacing', sc['fluid']['spacing']))
        b = sc['fluid']['blocks'][0]
        n = 1
        for a in range(3): n *= lattice(b['min'][a], b['max'][a], s)
        fps = sc['time']['fps']; T = (sc['time']['end_frame'] - sc['time']['start_frame']) / fps
        h = 2 * s
        c0 = float(p.get('solver.speed_of_sound', sc['solver'].get('speed_of_sound', 30)))
        vmax = {'dam_break': 4.0, 'hydrostatic': 0.5, 'poiseuille': 0.003, 'taylor_green': 0.1}[c['validation']]
        dfsph = p.get('solver.method') == 'dfsph'
        fixed = p.get('time.dt_mode') == 'fixed'
        if fixed: dt = float(p['time.dt'])
        elif dfsph: dt = min(float(p.get('time.cfl_factor', 0.4)) * s / vmax, float(p.get('time.dt_max', 0.005)), 1 / fps / 2)
        else:
            dt = min(float(p.get('time.cfl_factor', 0.4)) * h / (c0 + vmax), 0.005)
            if sc['fluid'].get('viscosity_model') == 'laplacian':
                dt = min(dt, float(p.get('time.viscous_factor', 0.125)) * h * h / sc['fluid']['viscosity'])
        steps = T / dt * (DFSPH_STEP_COST if dfsph else 1)
        wall = n * steps / throughput(n) + 0.5
        total += wall; per[c['name']] = per.get(c['name'], 0) + wall
for k, v in per.items(): print(f'{k}: {v/60:.1f} min')
print(f'total: {total/3600:.1f} h')
