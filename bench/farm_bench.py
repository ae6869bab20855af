#!/usr/bin/env python3
"""Surface + render of a 100-frame shot: `sphfx run --from surface` (one process) against the farm path
(`sphfx farm submit`: chunks as Slurm array tasks on a one-node Slurm started here), alternated, and the
scheduler's overhead per task (an array of empty tasks). Figures in docs/farm.md ("Measured").

  python3 bench/farm_bench.py --sphfx build/cli/sphfx [--rounds 3] [--chunk 10] [--cpus-per-task 1]
                              [--scheduler-parameters P] [--skip-overhead]

The shot: tests/farm/tiny_shot.json with 100 frames, spacing 0.025 m (~1,000 particles) and 640x360
images, simulated once; each round copies that simulation and redoes surface and render both ways.
The machine's Slurm and munge are used (apt-get install slurm-wlm munge); daemons are stopped by pid.
"""

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "farm"))
import slurm_cluster  # noqa: E402

SETS = ["time.end_frame=100", "fluid.spacing=0.025", "render.width=640", "render.height=360"]
LIVE = {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "REQUEUED", "SUSPENDED"}


def sets_args():
    out = []
    for s in SETS:
        out += ["--set", s]
    return out


def timed(cmd, env=None):
    t = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def wait_all(env, ids, poll=0.1):
    while True:
        r = subprocess.run(["squeue", "-r", "--states=all", "-h", "-o", "%i|%T", "-j", ",".join(ids)],
                           env=env, capture_output=True, text=True)
        states = [l.split("|", 1)[1] for l in r.stdout.split() if "|" in l]
        if states and not any(s in LIVE for s in states):
            bad = [s for s in states if s != "COMPLETED"]
            if bad:
                sys.exit(f"farm_bench: jobs ended {bad}")
            return
        time.sleep(poll)


def copy_simulation(base, shot):
    shutil.rmtree(shot, ignore_errors=True)
    os.makedirs(shot)
    shutil.copytree(os.path.join(base, "cache"), os.path.join(shot, "cache"), copy_function=shutil.copy2)
    shutil.copy2(os.path.join(base, "manifest.json"), os.path.join(shot, "manifest.json"))


def local_round(a, base, shot):
    copy_simulation(base, shot)
    return timed([a.sphfx, "-q", "run", a.scene, "-o", shot, "--from", "surface", *sets_args()])


def farm_round(a, env, base, shot):
    copy_simulation(base, shot)
    t = time.perf_counter()
    out = subprocess.run([a.sphfx, "-q", "farm", "submit", a.scene, "-o", shot, "--chunk", str(a.chunk),
                          "--cpus-per-task", str(a.cpus_per_task), *sets_args()],
                         check=True, env=env, capture_output=True, text=True).stdout
    ids = [l.replace(",", " ").split()[2] for l in out.splitlines() if " job " in l]
    if any(l.startswith("simulate") for l in out.splitlines()):
        sys.exit("farm_bench: the farm resubmitted the simulation; the copied one should count as complete")
    wait_all(env, ids)
    return time.perf_counter() - t


def empty_array(env, folder, tasks):
    script = os.path.join(folder, "empty.sh")
    with open(script, "w") as f:
        f.write("#!/bin/sh\ntrue\n")
    t = time.perf_counter()
    out = subprocess.run(["sbatch", "--parsable", f"--array=0-{tasks - 1}", "--cpus-per-task=1",
                          f"--output={folder}/empty.%A_%a.log", script],
                         check=True, env=env, capture_output=True, text=True).stdout
    wait_all(env, [out.strip().split(";")[0]])
    return time.perf_counter() - t


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--sphfx", required=True)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--chunk", type=int, default=10)
    p.add_argument("--cpus-per-task", type=int, default=1)
    p.add_argument("--scheduler-parameters", default="",
                   help="SchedulerParameters of the bench's slurm.conf (default: Slurm's defaults)")
    p.add_argument("--skip-overhead", action="store_true", help="skip the empty-array measurement")
    p.add_argument("--work", default=None, help="scratch folder (default: a new temporary one)")
    a = p.parse_args()
    a.sphfx = os.path.abspath(a.sphfx)
    a.scene = os.path.join(HERE, "..", "tests", "farm", "tiny_shot.json")
    work = a.work or tempfile.mkdtemp(prefix="farm_bench.")
    os.makedirs(work, exist_ok=True)
    base = os.path.join(work, "simulated")
    shutil.rmtree(base, ignore_errors=True)
    sim = timed([a.sphfx, "-q", "simulate", a.scene, "-o", base, *sets_args()])
    print(f"simulate, 100 frames: {sim:.1f} s (once; not part of the comparison)", flush=True)

    with slurm_cluster.LocalSlurm(os.path.join(work, "slurm"), a.scheduler_parameters) as cluster:
        env = cluster.env
        local, farm = [], []
        for r in range(a.rounds):
            local.append(local_round(a, base, os.path.join(work, "local")))
            farm.append(farm_round(a, env, base, os.path.join(work, "farm")))
            print(f"round {r + 1}: run --from surface {local[-1]:.1f} s, farm {farm[-1]:.1f} s "
                  f"(ratio farm/local {farm[-1] / local[-1]:.2f})", flush=True)
        if not a.skip_overhead:
            empty = [empty_array(env, work, 100)]  # ~1 s per task: once
            single = [empty_array(env, work, 1) for _ in range(a.rounds)]

    ml, mf = statistics.median(local), statistics.median(farm)
    print(f"\nmachine: {os.cpu_count()} CPUs; shot: 100 frames, {a.chunk} frames per task, "
          f"--cpus-per-task {a.cpus_per_task}; SchedulerParameters={a.scheduler_parameters or '(defaults)'}")
    print(f"surface + render, median of {a.rounds}: run --from surface {ml:.1f} s, farm {mf:.1f} s, "
          f"farm/local {mf / ml:.2f}")
    if not a.skip_overhead:
        print(f"empty array of 100 tasks, submit to all done: {statistics.median(empty):.1f} s "
              f"= {statistics.median(empty) / 100 * 1000:.0f} ms per task")
        print(f"one empty job, submit to done: median {statistics.median(single):.2f} s")
    if not a.work:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
