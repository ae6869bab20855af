#!/usr/bin/env python3
"""`sphfx farm submit --dry-run` (no Slurm needed) and the farm commands' bad input.

  dry_run_test.py --sphfx EXE --scene SCENE --work DIR dry-run
      23 frames in chunks of 4: the sbatch lines carry the stage dependencies (afterok on the simulation,
      aftercorr render -> surface, afterok finish -> render), the array range 0-5, the resources; each
      array task's script, run with its SLURM_ARRAY_TASK_ID, asks for the frames of its own chunk and the
      tasks together cover frames 1-23 once; nothing is written.
  dry_run_test.py --sphfx EXE --scene SCENE --work DIR bad
      unknown scheduler, bad chunk, bad CPU count, no sbatch on PATH, status/cancel of a shot never
      submitted, a shot holding another scene's simulation: each exits 2 with a message naming it.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def sphfx(args, *cmd, env=None):
    r = subprocess.run([args.sphfx, *cmd], capture_output=True, text=True, env=env)
    print(f"+ sphfx {' '.join(cmd)} -> {r.returncode}\n{r.stdout}{r.stderr}", flush=True)
    return r


def scripts_and_lines(text):
    """{stage: (script text, sbatch line)} from the dry-run listing."""
    parts = re.split(r"^# ---- .*/farm/(\w+)\.sh ----$", text, flags=re.M)
    out = {}
    for stage, body in zip(parts[1::2], parts[2::2]):
        script, _, line = body.partition("# sbatch line:\n")
        out[stage] = (script.strip() + "\n", line.strip())
    return out


def task_frames(script, task):
    """Runs an array task's script with `exec SPHFX` replaced by echo; returns its --frames value."""
    probe = re.sub(r"^exec '[^']*sphfx' ", "echo ", script, flags=re.M)
    env = dict(os.environ, SLURM_ARRAY_TASK_ID=str(task), SLURM_CPUS_PER_TASK="3")
    r = subprocess.run(["bash", "-c", probe], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        fail(f"task {task}'s script failed: {r.stderr}")
    m = re.search(r"--frames (\S+)", r.stdout)
    if not m or "--threads 3" not in r.stdout and "render" not in r.stdout:
        fail(f"task {task}: unexpected command {r.stdout!r}")
    first, last = map(int, m.group(1).split("-"))
    return first, last


def test_dry_run(args):
    shot = os.path.join(args.work, "shot")
    r = sphfx(args, "farm", "submit", args.scene, "-o", shot, "--chunk", "4", "--dry-run", "--partition", "p",
              "--sim-gres", "gpu:1", "--cpus-per-task", "3", "--set", "time.end_frame=23")
    if r.returncode != 0:
        fail("dry run failed")
    if os.path.exists(shot):
        fail("--dry-run wrote the shot folder")
    jobs = scripts_and_lines(r.stdout)
    if list(jobs) != ["simulate", "surface", "render", "finish"]:
        fail(f"expected simulate, surface, render, finish in that order, got {list(jobs)}")
    sim, surf, rend, fin = (jobs[s][1] for s in ("simulate", "surface", "render", "finish"))
    expect = {
        "simulate": (sim, ["--gres=gpu:1", "--partition=p", "--cpus-per-task=3"], ["--dependency", "--array"]),
        "surface": (surf, ["--array=0-5", "--dependency=afterok:$SIMULATE_JOB", "--kill-on-invalid-dep=yes",
                           "%x.%A_%a.log"], ["--gres"]),
        "render": (rend, ["--array=0-5", "--dependency=aftercorr:$SURFACE_JOB", "--partition=p"], ["--gres"]),
        "finish": (fin, ["--dependency=afterok:$RENDER_JOB", "--cpus-per-task=3"], ["--array", "--gres"]),
    }
    for stage, (line, present, absent) in expect.items():
        if not line.startswith(stage.upper() + "_JOB=$(sbatch --parsable"):
            fail(f"{stage}: not an sbatch line: {line}")
        for p in present:
            if p not in line:
                fail(f"{stage}: {p} missing from {line}")
        for a in absent:
            if a in line:
                fail(f"{stage}: unexpected {a} in {line}")
    if "--gl egl-device" not in jobs["simulate"][0] or "--resume" not in jobs["simulate"][0]:
        fail("the simulate job on a GPU resource must use the EGL device backend and --resume")
    if "--gl egl-surfaceless" not in jobs["render"][0] or "--no-contact-sheet" not in jobs["render"][0]:
        fail("render chunks must use llvmpipe (egl-surfaceless) and leave the contact sheet to the last job")
    expected = [(f, min(f + 3, 23)) for f in range(1, 24, 4)]
    for stage in ("surface", "render"):
        got = [task_frames(jobs[stage][0], t) for t in range(6)]
        if got != expected:
            fail(f"{stage}: tasks ask for {got}, expected {expected}")
    print("ok: dependencies, array ranges and chunks as expected")


def test_bad(args):
    shot = os.path.join(args.work, "bad_shot")
    cases = [
        (["farm", "submit", args.scene, "-o", shot, "--scheduler", "pbs", "--dry-run"], None, "unknown scheduler"),
        (["farm", "submit", args.scene, "-o", shot, "--chunk", "0", "--dry-run"], None, "--chunk 0"),
        (["farm", "submit", args.scene, "-o", shot, "--chunk", "-3", "--dry-run"], None, "--chunk -3"),
        (["farm", "submit", args.scene, "-o", shot, "--cpus-per-task", "0", "--dry-run"], None, "--cpus-per-task"),
        (["farm", "submit", args.scene, "-o", shot], dict(os.environ, PATH="/nonexistent"), "sbatch is not on PATH"),
        (["farm", "status", shot], None, "never submitted"),
        (["farm", "cancel", shot], None, "no jobs recorded"),
        (["farm", "submit", "no_such_scene.json", "-o", shot, "--dry-run"], None, "no_such_scene.json"),
    ]
    other = os.path.join(args.work, "other_scene_shot")
    os.makedirs(other)
    with open(os.path.join(other, "manifest.json"), "w") as f:
        f.write('{"manifest_version": 1, "simulate": {"status": "complete", "scene": {"name": "another"}}}\n')
    cases.append((["farm", "submit", args.scene, "-o", other, "--dry-run"], None,
                  "holds a simulation of another scene"))
    for cmd, env, message in cases:
        r = sphfx(args, *cmd, env=env)
        if r.returncode != 2:
            fail(f"{' '.join(cmd)}: exit {r.returncode}, expected 2")
        if message not in r.stderr:
            fail(f"{' '.join(cmd)}: error does not say {message!r}: {r.stderr!r}")
    if os.path.exists(shot):
        fail("bad input wrote the shot folder")
    print(f"ok: {len(cases)} bad inputs exit 2 with a clear message")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--sphfx", required=True)
    p.add_argument("--scene", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("mode", choices=["dry-run", "bad"])
    args = p.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    (test_dry_run if args.mode == "dry-run" else test_bad)(args)
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
