#!/usr/bin/env python3
"""The farm path against a real Slurm (one node on this machine, started and stopped by this test).

  slurm_test.py --sphfx EXE --scene SCENE --work DIR shot
      `sphfx farm submit` of a tiny shot, waited for; every frame file (caches, level sets, meshes,
      images, contact sheet) must equal byte for byte those of a local `sphfx run` of the same scene.
  slurm_test.py --sphfx EXE --scene SCENE --work DIR fault
      One render array task is cancelled (scancel JOB_TASK) while it runs; the jobs after it are then
      cancelled by Slurm (--kill-on-invalid-dep); `sphfx farm retry` resubmits only the missing chunk,
      and afterwards nothing is missing or torn (again byte-equal to the local run), and the frames done
      before the fault were not redone.

Exit 77 (ctest SKIP_RETURN_CODE) only when the Slurm or munge binaries are not installed.
"""

import argparse
import filecmp
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import slurm_cluster  # noqa: E402

STAGE_DIRS = ("cache", "surface", "mesh", "render")
LIVE_STATES = {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "REQUEUED", "RESIZING", "SUSPENDED"}


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def run(cmd, env=None, check=True):
    print("+ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    sys.stdout.write(r.stdout)
    sys.stdout.write(r.stderr)
    if check and r.returncode != 0:
        fail(f"{cmd[0]} {cmd[1] if len(cmd) > 1 else ''} exited with {r.returncode}")
    return r


def frame_files(shot):
    """Visible files of the stages' folders (temporary files are hidden: .NAME.tmp.*)."""
    files = []
    for d in STAGE_DIRS:
        folder = os.path.join(shot, d)
        if os.path.isdir(folder):
            files += sorted(os.path.join(d, f) for f in os.listdir(folder) if not f.startswith("."))
    return files


def job_ids(submit_output):
    """{stage: job id} from `sphfx farm submit` output lines "surface   job 13, 3 array tasks"."""
    ids = {}
    for line in submit_output.splitlines():
        words = line.replace(",", " ").split()
        if len(words) >= 3 and words[1] == "job":
            ids[words[0]] = words[2]
    return ids


def states(cluster, ids):
    r = subprocess.run(["squeue", "-r", "--states=all", "-h", "-o", "%i|%T", "-j", ",".join(ids.values())],
                       env=cluster.env, capture_output=True, text=True)
    return dict(l.split("|", 1) for l in r.stdout.split() if "|" in l)


def wait_for_jobs(cluster, ids, timeout=600):
    end = time.time() + timeout
    while time.time() < end:
        s = states(cluster, ids)
        if s and not any(v in LIVE_STATES for v in s.values()):
            return s
        time.sleep(1)
    fail(f"jobs {ids} still live after {timeout} s: {states(cluster, ids)}")


def compare_with_local(local, farm, frames):
    local_files, farm_files = frame_files(local), frame_files(farm)
    # An independent count first: each stage wrote every frame of the scene, plus the contact sheet.
    for d, ext in (("cache", ".vdb"), ("surface", ".vdb"), ("mesh", ".ply"), ("render", ".png")):
        n = sum(1 for f in farm_files if f.startswith(d + os.sep) and f.endswith(ext) and "_contact" not in f)
        if n != frames:
            fail(f"farm shot has {n} {d} frames, expected {frames}")
    if os.path.join("render", "surface_contact.png") not in farm_files:
        fail("farm shot has no contact sheet")
    if local_files != farm_files:
        fail(f"file sets differ:\n local only {sorted(set(local_files) - set(farm_files))}\n"
             f" farm only {sorted(set(farm_files) - set(local_files))}")
    different = [f for f in local_files
                 if not filecmp.cmp(os.path.join(local, f), os.path.join(farm, f), shallow=False)]
    if different:
        fail(f"files differ from the local run: {different}")
    print(f"ok: {len(farm_files)} frame files byte-equal to the local run", flush=True)


def local_run(args, shot, sets):
    shutil.rmtree(shot, ignore_errors=True)
    cmd = [args.sphfx, "-q", "run", args.scene, "-o", shot]
    for s in sets:
        cmd += ["--set", s]
    run(cmd)


def submit(args, cluster, shot, chunk, sets):
    cmd = [args.sphfx, "farm", "submit", args.scene, "-o", shot, "--scheduler", "slurm", "--chunk", str(chunk)]
    for s in sets:
        cmd += ["--set", s]
    ids = job_ids(run(cmd, env=cluster.env).stdout)
    if set(ids) != {"simulate", "surface", "render", "finish"}:
        fail(f"expected four jobs, got {ids}")
    return ids


def test_shot(args, cluster, frames):
    local, farm = os.path.join(args.work, "local"), os.path.join(args.work, "farm")
    local_run(args, local, [])
    shutil.rmtree(farm, ignore_errors=True)
    ids = submit(args, cluster, farm, 2, [])
    final = wait_for_jobs(cluster, ids)
    bad = {k: v for k, v in final.items() if v != "COMPLETED"}
    if bad:
        fail(f"jobs not COMPLETED: {bad}; logs in {farm}/farm/logs")
    logs = os.listdir(os.path.join(farm, "farm", "logs"))
    if not any(l.startswith("sphfx-render-farm.") and l.endswith("_2.log") for l in logs):
        fail(f"no render array task log named %x.%A_%a.log in farm/logs: {logs}")
    status = run([args.sphfx, "farm", "status", farm], env=cluster.env).stdout
    rows = [l.split() for l in status.splitlines()[1:]]
    if len(rows) != 2 + 2 * ((frames + 1) // 2) or any(r[-1] != "done" for r in rows):
        fail("farm status does not say every stage and chunk is done")
    compare_with_local(local, farm, frames)
    # Submitting a finished shot again submits nothing.
    again = run([args.sphfx, "farm", "submit", args.scene, "-o", farm, "--chunk", "2"], env=cluster.env).stdout
    if "nothing to submit" not in again:
        fail("a second submission of a finished shot submitted jobs")


def test_fault(args, cluster, frames):
    # Full HD frames take long enough on one llvmpipe thread (~1 s) to cancel a task in the middle.
    sets = ["render.width=1920", "render.height=1080"]
    local, farm = os.path.join(args.work, "local_fault"), os.path.join(args.work, "farm_fault")
    local_run(args, local, sets)
    shutil.rmtree(farm, ignore_errors=True)
    chunk = 3
    ids = submit(args, cluster, farm, chunk, sets)
    victim = f"{ids['render']}_0"
    first_image = os.path.join(farm, "render", "surface.0001.png")
    end = time.time() + 600
    while not os.path.exists(first_image):
        if time.time() > end:
            fail(f"render task {victim} wrote no frame in 600 s")
        time.sleep(0.02)
    run(["scancel", victim], env=cluster.env)
    print(f"cancelled render task {victim} after its first frame", flush=True)
    final = wait_for_jobs(cluster, ids)
    if final.get(victim) != "CANCELLED":
        fail(f"render task {victim} is {final.get(victim)}, expected CANCELLED")
    if final.get(ids["finish"]) != "CANCELLED":
        fail(f"the finish job is {final.get(ids['finish'])}; its dependency failed, so Slurm must cancel it")
    rendered = [f for f in range(1, chunk + 1) if os.path.exists(os.path.join(farm, "render", f"surface.{f:04d}.png"))]
    if len(rendered) == chunk:
        fail(f"task {victim} finished its chunk before the cancel reached it; the fault was not injected")
    print(f"after the cancel, chunk 0 has frames {rendered} of 1-{chunk}", flush=True)

    before = {f: os.stat(os.path.join(farm, f)).st_mtime_ns for f in frame_files(farm)}
    out = run([args.sphfx, "farm", "retry", farm], env=cluster.env).stdout
    retry_ids = job_ids(out)
    if "simulate" in retry_ids or retry_ids.get("surface") is None:
        fail(f"retry should resubmit surface, render and finish only (the simulation is complete): {retry_ids}")
    if "1 array tasks" not in out:
        fail("retry should resubmit only the one chunk with missing frames")
    final = wait_for_jobs(cluster, retry_ids)
    bad = {k: v for k, v in final.items() if v != "COMPLETED"}
    if bad:
        fail(f"retried jobs not COMPLETED: {bad}")
    redone = [f for f, t in before.items() if os.stat(os.path.join(farm, f)).st_mtime_ns != t]
    if redone:
        fail(f"the retry rewrote frames that were already done: {redone}")
    compare_with_local(local, farm, frames)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--sphfx", required=True)
    p.add_argument("--scene", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--frames", type=int, required=True, help="frames of the scene (an independent count)")
    p.add_argument("mode", choices=["shot", "fault"])
    args = p.parse_args()
    args.sphfx = os.path.abspath(args.sphfx)
    args.scene = os.path.abspath(args.scene)
    args.work = os.path.abspath(args.work)
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    try:
        cluster = slurm_cluster.LocalSlurm(os.path.join(args.work, "slurm"))
    except slurm_cluster.SlurmUnavailable as e:
        print(f"SKIP: cannot start Slurm: {e}")
        return slurm_cluster.SKIP_RETURN_CODE
    with cluster:
        (test_shot if args.mode == "shot" else test_fault)(args, cluster, args.frames)
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
