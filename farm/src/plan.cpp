// The submission plan: chunks, the job scripts and their sbatch lines, from the shot's missing frames.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "shot_files.h"
#include "sphfx/core/data_files.h"
#include "sphfx/core/error.h"
#include "sphfx/farm/farm.h"
#include "sphfx/farm/process.h"

namespace fs = std::filesystem;

namespace sphfx::farm {

std::vector<Chunk> makeChunks(const FrameRange& frames, int size) {
  if (size < 1) throw InputError(fmt::format("--chunk {}: expected 1 or more frames per task", size));
  std::vector<Chunk> chunks;
  for (int first = frames.first, i = 0; first <= frames.last; first += size, ++i)
    chunks.push_back({i, {first, std::min(first + size - 1, frames.last)}});
  return chunks;
}

namespace {

void validate(const SubmitOptions& o) {
  if (o.scheduler != "slurm")
    throw InputError(fmt::format("--scheduler {}: unknown scheduler; supported: slurm", o.scheduler));
  if (o.chunk < 1) throw InputError(fmt::format("--chunk {}: expected 1 or more frames per task", o.chunk));
  if (o.cpusPerTask < 1)
    throw InputError(fmt::format("--cpus-per-task {}: expected 1 or more", o.cpusPerTask));
  if (o.shotDir.empty()) throw InputError("farm submit: -o SHOT is required");
  if (!o.dryRun && findOnPath("sbatch").empty())
    throw InputError(
        "farm submit: sbatch is not on PATH; run this on a Slurm submit host (or use --dry-run)");
}

/// The header every script starts with: what it is and how the farm submits it.
std::string scriptHeader(const std::string& what) {
  return fmt::format(
      "#!/bin/bash\n"
      "# Written by `sphfx farm submit`: {}\n"
      "# Submitted with the sbatch options `sphfx farm submit --dry-run` prints. Safe to rerun: finished\n"
      "# frames are skipped, so a requeued or retried task redoes only the missing ones.\n"
      "set -euo pipefail\n",
      what);
}

/// The lines that turn SLURM_ARRAY_TASK_ID into this task's frames (chunk i: first + i*chunk ...).
std::string chunkLines(const Plan& plan, int chunk) {
  std::string table;
  for (const Chunk& c : plan.chunks)
    table += fmt::format("#   task {}: frames {}-{}\n", c.index, c.frames.first, c.frames.last);
  return fmt::format(
      "# Array task -> frames ({} frames per task):\n{}"
      "id=${{SLURM_ARRAY_TASK_ID:?this script runs as a Slurm array task}}\n"
      "first=$(( {} + id * {} ))\n"
      "last=$(( first + {} - 1 ))\n"
      "if (( last > {} )); then last={}; fi\n"
      "threads=${{SLURM_CPUS_PER_TASK:-1}}\n",
      chunk, table, plan.frames.first, chunk, chunk, plan.frames.last, plan.frames.last);
}

std::string simulateScript(const Plan& plan, const SubmitOptions& o, const std::string& exe) {
  // A GPU node has a device for EGL; elsewhere auto falls back to llvmpipe (EGL surfaceless).
  const std::string gl = o.simGres.empty() ? "auto" : "egl-device";
  return scriptHeader("simulate the whole shot (one job, sequential in time).") +
         "# --resume continues after the last restart file (bit-identical to an uninterrupted run).\n"
         "export LP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}\n" +
         fmt::format("exec {} simulate {} -o {} --resume --gl {}\n", shellQuote(exe),
                     shellQuote(farmScenePath(plan.shotDir)), shellQuote(plan.shotDir), gl);
}

std::string surfaceScript(const Plan& plan, const SubmitOptions& o, const std::string& exe) {
  return scriptHeader("surface one chunk of frames (CPU only, no GL).") + chunkLines(plan, o.chunk) +
         fmt::format("exec {} surface {} --frames \"$first-$last\" --threads \"$threads\"\n", shellQuote(exe),
                     shellQuote(plan.shotDir));
}

std::string renderScript(const Plan& plan, const SubmitOptions& o, const std::string& exe) {
  return scriptHeader("render one chunk of frames on a CPU node (llvmpipe).") + chunkLines(plan, o.chunk) +
         "export LP_NUM_THREADS=\"$threads\"\n" +
         fmt::format("exec {} render {} --frames \"$first-$last\" --no-contact-sheet --gl egl-surfaceless\n",
                     shellQuote(exe), shellQuote(plan.shotDir));
}

std::string finishScript(const Plan& plan, const SubmitOptions& o, const std::string& exe) {
  return scriptHeader(
             "contact sheet (and movie) from the rendered frames; renders any frame still missing.") +
         "export LP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}\n" +
         fmt::format("exec {} render {} --gl egl-surfaceless{}\n", shellQuote(exe), shellQuote(plan.shotDir),
                     o.movie ? " --movie" : "");
}

std::vector<std::string> resources(const SubmitOptions& o, bool gpu) {
  std::vector<std::string> r{fmt::format("--cpus-per-task={}", o.cpusPerTask)};
  if (!o.partition.empty()) r.push_back("--partition=" + o.partition);
  if (gpu && !o.simGres.empty()) r.push_back("--gres=" + o.simGres);
  return r;
}

/// Chunks with a frame that the surface or the render stage has not written yet.
std::vector<int> chunksWithWork(const Plan& plan, const Scene& scene, bool simulationDone) {
  std::vector<int> out;
  for (const Chunk& c : plan.chunks) {
    const int n = c.frames.count();
    if (!simulationDone || framesDone(plan.shotDir, scene, "surface", c.frames) < n ||
        framesDone(plan.shotDir, scene, "render", c.frames) < n)
      out.push_back(c.index);
  }
  return out;
}

}  // namespace

Plan planSubmission(const SubmitOptions& o) {
  validate(o);
  const Scene scene = loadScene(o.sceneFile, o.sets);
  Plan plan;
  plan.shotDir = fs::absolute(o.shotDir).lexically_normal().string();
  while (plan.shotDir.size() > 1 && plan.shotDir.back() == '/') plan.shotDir.pop_back();
  const ManifestJson resolved = ManifestJson::parse(sceneToJson(scene).dump());
  plan.sceneJson = resolved.dump(2) + "\n";
  plan.frames = {scene.time.startFrame, scene.time.endFrame};
  plan.chunks = makeChunks(plan.frames, o.chunk);
  const std::string exe = o.sphfx.empty() ? executablePath() : o.sphfx;
  plan.sphfx = exe;

  // The simulate job resumes from the shot's restart file, which must belong to this scene.
  if (holdsOtherSimulation(plan.shotDir, resolved))
    throw InputError(
        fmt::format("{}: holds a simulation of another scene (manifest.json simulate.scene); "
                    "submit to a new shot folder",
                    plan.shotDir));
  const bool simulated = simulationComplete(plan.shotDir, resolved);
  const std::string farm = farmDir(plan.shotDir);
  if (!simulated)
    plan.jobs.push_back(
        {"simulate", farm + "/simulate.sh", simulateScript(plan, o, exe), {}, "", "", resources(o, true)});
  const std::vector<int> work = chunksWithWork(plan, scene, simulated);
  if (!work.empty()) {
    plan.jobs.push_back({"surface", farm + "/surface.sh", surfaceScript(plan, o, exe), work,
                         simulated ? "" : "simulate", "afterok", resources(o, false)});
    plan.jobs.push_back({"render", farm + "/render.sh", renderScript(plan, o, exe), work, "surface",
                         "aftercorr", resources(o, false)});
  }
  if (!work.empty() || !fs::exists(contactSheetPath(plan.shotDir, scene)))
    plan.jobs.push_back({"finish",
                         farm + "/finish.sh",
                         finishScript(plan, o, exe),
                         {},
                         work.empty() ? "" : "render",
                         "afterok",
                         resources(o, false)});
  return plan;
}

namespace {

/// "0-4" for consecutive tasks, else "1,3,7".
std::string arraySpec(const std::vector<int>& tasks) {
  bool consecutive = true;
  for (size_t i = 1; i < tasks.size(); ++i) consecutive = consecutive && tasks[i] == tasks[i - 1] + 1;
  if (consecutive && tasks.size() > 1) return fmt::format("{}-{}", tasks.front(), tasks.back());
  return fmt::format("{}", fmt::join(tasks, ","));
}

}  // namespace

std::vector<std::string> sbatchCommand(const Plan& plan, const PlannedJob& job,
                                       const std::string& dependencyJobId) {
  const std::string shotName = fs::path(plan.shotDir).filename().string();
  std::vector<std::string> cmd{"sbatch", "--parsable", "--requeue",
                               fmt::format("--job-name=sphfx-{}-{}", job.stage, shotName)};
  if (job.arrayTasks.empty()) {
    cmd.push_back(fmt::format("--output={}/%x.%j.log", logsDir(plan.shotDir)));
  } else {
    cmd.push_back("--array=" + arraySpec(job.arrayTasks));
    cmd.push_back(fmt::format("--output={}/%x.%A_%a.log", logsDir(plan.shotDir)));
  }
  cmd.insert(cmd.end(), job.resources.begin(), job.resources.end());
  if (!dependencyJobId.empty()) {
    // A dependency that fails (a cancelled or failed task) cancels the waiting jobs instead of leaving
    // them pending forever; `sphfx farm retry` resubmits what is missing.
    cmd.push_back(fmt::format("--dependency={}:{}", job.dependency, dependencyJobId));
    cmd.push_back("--kill-on-invalid-dep=yes");
  }
  cmd.push_back(job.scriptPath);
  return cmd;
}

std::string describePlan(const Plan& plan) {
  std::string out = fmt::format("# shot {}: frames {}-{} in {} chunks\n", plan.shotDir, plan.frames.first,
                                plan.frames.last, plan.chunks.size());
  if (plan.jobs.empty()) return out + "# nothing to submit: every frame and the contact sheet are done\n";
  for (const PlannedJob& job : plan.jobs) {
    out += fmt::format("\n# ---- {} ----\n{}", job.scriptPath, job.script);
    std::string dep;
    if (!job.dependsOn.empty()) {
      dep = "$" + job.dependsOn + "_JOB";
      std::transform(dep.begin(), dep.end(), dep.begin(), ::toupper);
    }
    std::vector<std::string> quoted;
    for (const std::string& a : sbatchCommand(plan, job, dep))
      quoted.push_back(a.find_first_of(" '\"\\") == std::string::npos ? a : shellQuote(a));
    std::string var = job.stage + "_JOB";
    std::transform(var.begin(), var.end(), var.begin(), ::toupper);
    out += fmt::format("# sbatch line:\n{}=$({})\n", var, fmt::join(quoted, " "));
  }
  return out;
}

}  // namespace sphfx::farm
