// `sphfx farm status` and `sphfx farm cancel`: the frame files say what is done, squeue/sacct (where
// they answer) what the scheduler is doing with the rest.
#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "shot_files.h"
#include "sphfx/core/error.h"
#include "sphfx/farm/farm.h"
#include "sphfx/farm/process.h"

namespace fs = std::filesystem;

namespace sphfx::farm {

namespace {

struct RecordedJob {
  std::string stage, jobId;
  std::vector<int> arrayTasks;
};

std::vector<RecordedJob> recordedJobs(const std::string& shotDir) {
  std::vector<RecordedJob> jobs;
  if (!fs::exists(jobsPath(shotDir))) return jobs;
  const ManifestJson record = ManifestJson::parse(readTextFile(jobsPath(shotDir)));
  for (const auto& submission : record.value("submissions", ManifestJson::array()))
    for (const auto& j : submission)
      jobs.push_back(
          {j.value("stage", ""), j.value("job_id", ""), j.value("array_tasks", std::vector<int>{})});
  return jobs;
}

/// Scheduler state per job id ("12") and array task ("13_4"). squeue knows queued jobs and, for
/// MinJobAge, finished ones; sacct (where accounting is on) knows the rest. Either may not answer.
std::map<std::string, std::string> schedulerStates(const std::vector<RecordedJob>& jobs) {
  std::map<std::string, std::string> states;
  std::set<std::string> ids;
  for (const RecordedJob& j : jobs) ids.insert(j.jobId);
  if (ids.empty()) return states;
  std::string list;
  for (const std::string& id : ids) list += (list.empty() ? "" : ",") + id;
  auto parse = [&](const std::string& out, char sep) {
    std::istringstream lines(out);
    for (std::string line; std::getline(lines, line);) {
      const size_t bar = line.find(sep);
      if (bar == std::string::npos) continue;
      std::string state = line.substr(bar + 1);
      state = state.substr(0, state.find(' '));    // "CANCELLED by 0"
      states.emplace(line.substr(0, bar), state);  // squeue (asked first) wins
    }
  };
  if (const std::string squeue = findOnPath("squeue"); !squeue.empty()) {
    const ProcessResult r = runProcess({squeue, "-r", "--states=all", "-h", "-o", "%i|%T", "-j", list});
    if (r.status == 0) parse(r.out, '|');
  }
  if (const std::string sacct = findOnPath("sacct"); !sacct.empty()) {
    const ProcessResult r = runProcess({sacct, "-n", "-P", "-X", "-o", "JobID,State", "-j", list});
    if (r.status == 0) parse(r.out, '|');
  }
  return states;
}

/// The latest recorded job of `stage` that covers `chunk` (-1: a single job): "ID" or "ID_CHUNK".
std::string latestJob(const std::vector<RecordedJob>& jobs, const std::string& stage, int chunk) {
  for (auto it = jobs.rbegin(); it != jobs.rend(); ++it) {
    if (it->stage != stage) continue;
    if (chunk < 0) return it->jobId;
    for (int t : it->arrayTasks)
      if (t == chunk) return fmt::format("{}_{}", it->jobId, chunk);
  }
  return {};
}

ChunkStatus row(const std::string& stage, int chunk, const FrameRange& frames, int done, bool complete,
                const std::vector<RecordedJob>& jobs, const std::map<std::string, std::string>& states) {
  ChunkStatus s{stage, chunk, frames, done, chunk < 0 && stage == "finish" ? 1 : frames.count(), {}, {}};
  s.jobId = latestJob(jobs, stage, chunk);
  const auto known = states.find(s.jobId);
  s.state = complete ? "done" : known != states.end() ? known->second : "missing";
  return s;
}

bool isLive(const std::string& state) {
  static const std::set<std::string> finished{"COMPLETED", "FAILED",    "CANCELLED",
                                              "TIMEOUT",   "NODE_FAIL", "PREEMPTED",
                                              "BOOT_FAIL", "DEADLINE",  "OUT_OF_MEMORY"};
  return !finished.count(state);
}

}  // namespace

std::vector<ChunkStatus> shotStatus(const std::string& shotDir) {
  const SubmitOptions o = recordedOptions(shotDir);
  const Scene scene = loadScene(o.sceneFile, o.sets);
  const FrameRange all{scene.time.startFrame, scene.time.endFrame};
  const std::vector<RecordedJob> jobs = recordedJobs(shotDir);
  const auto states = schedulerStates(jobs);
  const ManifestJson resolved = ManifestJson::parse(sceneToJson(scene).dump());

  std::vector<ChunkStatus> rows;
  const int cached = framesDone(shotDir, scene, "simulate", all);
  rows.push_back(row("simulate", -1, all, cached, simulationComplete(shotDir, resolved), jobs, states));
  for (const std::string stage : {"surface", "render"})
    for (const Chunk& c : makeChunks(all, o.chunk)) {
      const int done = framesDone(shotDir, scene, stage, c.frames);
      rows.push_back(row(stage, c.index, c.frames, done, done == c.frames.count(), jobs, states));
    }
  const bool sheet = fs::exists(contactSheetPath(shotDir, scene));
  rows.push_back(row("finish", -1, all, sheet ? 1 : 0, sheet, jobs, states));
  return rows;
}

std::string formatStatus(const std::vector<ChunkStatus>& rows) {
  std::string out = fmt::format("{:<9} {:>5} {:>11} {:>9}  {:<12} {}\n", "stage", "chunk", "frames", "done",
                                "job", "state");
  for (const ChunkStatus& r : rows)
    out += fmt::format("{:<9} {:>5} {:>11} {:>9}  {:<12} {}\n", r.stage,
                       r.chunk < 0 ? std::string("-") : std::to_string(r.chunk),
                       fmt::format("{}-{}", r.frames.first, r.frames.last),
                       fmt::format("{}/{}", r.done, r.total), r.jobId.empty() ? "-" : r.jobId, r.state);
  return out;
}

std::vector<std::string> cancelShot(const std::string& shotDir) {
  if (!fs::exists(jobsPath(shotDir)))
    throw InputError(fmt::format("{}: no jobs recorded (no {})", shotDir, jobsPath(shotDir)));
  const std::string scancel = findOnPath("scancel");
  if (scancel.empty())
    throw InputError("farm cancel: scancel is not on PATH; run this on a Slurm submit host");
  const std::vector<RecordedJob> jobs = recordedJobs(shotDir);
  const auto states = schedulerStates(jobs);
  std::vector<std::string> live;
  if (states.empty()) {
    // The scheduler did not answer: cancel every recorded job (scancel ignores finished ones).
    for (const RecordedJob& j : jobs) live.push_back(j.jobId);
  } else {
    for (const auto& [id, state] : states)
      if (isLive(state)) live.push_back(id);
  }
  if (live.empty()) return live;
  std::vector<std::string> cmd{scancel};
  cmd.insert(cmd.end(), live.begin(), live.end());
  const ProcessResult r = runProcess(cmd);
  if (r.status != 0 && !states.empty())
    throw Error(fmt::format("farm cancel: scancel failed (status {}): {}", r.status, r.err));
  return live;
}

}  // namespace sphfx::farm
