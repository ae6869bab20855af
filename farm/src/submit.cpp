// Submission: SHOT/farm/ written, sbatch run per job, the job ids recorded in SHOT/farm/jobs.json.
#include <fmt/format.h>
#include <sys/stat.h>

#include <filesystem>
#include <map>

#include "shot_files.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/farm/farm.h"
#include "sphfx/farm/process.h"

namespace fs = std::filesystem;

namespace sphfx::farm {

namespace {

ManifestJson optionsJson(const SubmitOptions& o) {
  return {{"scheduler", o.scheduler},
          {"scene", fs::absolute(o.sceneFile).string()},
          {"sets", o.sets},
          {"chunk", o.chunk},
          {"partition", o.partition},
          {"sim_gres", o.simGres},
          {"cpus_per_task", o.cpusPerTask},
          {"movie", o.movie},
          {"sphfx", o.sphfx}};
}

void writeFarmFolder(const Plan& plan, const SubmitOptions& o) {
  std::error_code ec;
  fs::create_directories(logsDir(plan.shotDir), ec);
  if (ec) throw IoError(logsDir(plan.shotDir) + ": cannot create: " + ec.message());
  writeTextAtomically(farmScenePath(plan.shotDir), plan.sceneJson);
  // The recorded scene is the resolved one, so a retry resubmits exactly what was submitted first.
  SubmitOptions recorded = o;
  recorded.sceneFile = farmScenePath(plan.shotDir);
  recorded.sets.clear();
  recorded.sphfx = plan.sphfx;
  writeTextAtomically(submitPath(plan.shotDir), optionsJson(recorded).dump(2) + "\n");
  for (const PlannedJob& job : plan.jobs) {
    writeTextAtomically(job.scriptPath, job.script);
    ::chmod(job.scriptPath.c_str(), 0755);
  }
}

/// "123" from sbatch --parsable's "123" or "123;cluster".
std::string parseJobId(const std::string& out) {
  std::string id = out.substr(0, out.find_first_of(";\n"));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos) return {};
  return id;
}

void cancelQuietly(const std::vector<SubmittedJob>& jobs) {
  const std::string scancel = findOnPath("scancel");
  if (scancel.empty() || jobs.empty()) return;
  std::vector<std::string> cmd{scancel};
  for (const SubmittedJob& j : jobs) cmd.push_back(j.jobId);
  runProcess(cmd);
}

void recordJobs(const std::string& shotDir, const std::vector<SubmittedJob>& jobs) {
  ManifestJson record = ManifestJson::object();
  if (fs::exists(jobsPath(shotDir))) record = ManifestJson::parse(readTextFile(jobsPath(shotDir)));
  ManifestJson submission = ManifestJson::array();
  for (const SubmittedJob& j : jobs)
    submission.push_back({{"stage", j.stage}, {"job_id", j.jobId}, {"array_tasks", j.arrayTasks}});
  record["submissions"].push_back(submission);
  writeTextAtomically(jobsPath(shotDir), record.dump(2) + "\n");
}

}  // namespace

std::vector<SubmittedJob> submitPlan(const Plan& plan, const SubmitOptions& o) {
  writeFarmFolder(plan, o);
  const std::string sbatch = findOnPath("sbatch");
  if (sbatch.empty()) throw InputError("farm submit: sbatch is not on PATH; run this on a Slurm submit host");
  std::vector<SubmittedJob> submitted;
  std::map<std::string, std::string> idOf;
  for (const PlannedJob& job : plan.jobs) {
    const std::string dependency = job.dependsOn.empty() ? "" : idOf.at(job.dependsOn);
    std::vector<std::string> cmd = sbatchCommand(plan, job, dependency);
    cmd[0] = sbatch;
    const ProcessResult r = runProcess(cmd);
    const std::string id = r.status == 0 ? parseJobId(r.out) : "";
    if (id.empty()) {
      cancelQuietly(submitted);
      throw Error(fmt::format("farm submit: sbatch failed for the {} job (status {}): {}{}", job.stage,
                              r.status, r.err.empty() ? r.out : r.err,
                              submitted.empty() ? "" : "; the jobs submitted before it were cancelled"));
    }
    idOf[job.stage] = id;
    submitted.push_back({job.stage, id, job.arrayTasks});
    logVerbose(fmt::format("farm: {} -> job {}", fmt::join(cmd, " "), id));
  }
  recordJobs(plan.shotDir, submitted);
  return submitted;
}

SubmitOptions recordedOptions(const std::string& shotDir) {
  const std::string path = submitPath(shotDir);
  if (!fs::exists(path))
    throw InputError(fmt::format("{}: the shot was never submitted (no {})", shotDir, path));
  const ManifestJson j = ManifestJson::parse(readTextFile(path));
  SubmitOptions o;
  o.shotDir = shotDir;
  o.scheduler = j.value("scheduler", "slurm");
  o.sceneFile = j.value("scene", farmScenePath(shotDir));
  o.sets = j.value("sets", std::vector<std::string>{});
  o.chunk = j.value("chunk", 10);
  o.partition = j.value("partition", "");
  o.simGres = j.value("sim_gres", "");
  o.cpusPerTask = j.value("cpus_per_task", 1);
  o.movie = j.value("movie", false);
  o.sphfx = j.value("sphfx", "");
  return o;
}

}  // namespace sphfx::farm
