#pragma once
/// @file farm.h
/// @brief A shot on a render farm (Slurm): job scripts in SHOT/farm/, sbatch submission with stage
/// dependencies, status from the frame files and the scheduler, cancel and retry.
///
/// The shot's stages map onto jobs: simulate (one job, sequential in time), surface (an array over frame
/// chunks, after the whole simulation), render (an array over the same chunks, each task after its own
/// surface task: aftercorr), finish (contact sheet and movie, after every render task). Every task runs
/// an ordinary `sphfx` command that skips finished frames, so a retried task redoes only what is missing.
/// What is done is read from the frame files, never from the scheduler, so a resubmission submits only
/// the stages and chunks with missing frames.

#include <string>
#include <vector>

#include "sphfx/core/frame_files.h"

namespace sphfx::farm {

/// A contiguous block of frames handled by one array task; `index` is the task's SLURM_ARRAY_TASK_ID.
struct Chunk {
  int index = 0;
  FrameRange frames;
};

/// Splits `frames` into chunks of `size` frames, the last one possibly shorter.
/// @throws InputError if size < 1.
std::vector<Chunk> makeChunks(const FrameRange& frames, int size);

/// Options of `sphfx farm submit` (also recorded in SHOT/farm/submit.json for `sphfx farm retry`).
struct SubmitOptions {
  std::string sceneFile;          ///< scene JSON (resolved and copied to SHOT/farm/scene.json)
  std::vector<std::string> sets;  ///< --set overrides applied to the scene
  std::string shotDir;
  std::string scheduler = "slurm";
  int chunk = 10;         ///< frames per surface/render array task
  std::string partition;  ///< empty: the cluster's default partition
  std::string simGres;    ///< e.g. "gpu:1"; when set, the simulation uses the EGL device backend
  int cpusPerTask = 1;    ///< --cpus-per-task of every job; tasks take their thread counts from it
  bool movie = false;     ///< the finish job also assembles an MP4 (if ffmpeg is on the node)
  bool dryRun = false;
  std::string sphfx;  ///< absolute path of the sphfx the jobs run; empty: this executable
};

/// One sbatch submission of a plan.
struct PlannedJob {
  std::string stage;                   ///< "simulate", "surface", "render" or "finish"
  std::string scriptPath;              ///< SHOT/farm/<stage>.sh
  std::string script;                  ///< the script's text
  std::vector<int> arrayTasks;         ///< chunk indices; empty for a single job
  std::string dependsOn;               ///< stage whose job this one waits for; empty: none
  std::string dependency;              ///< "afterok" or "aftercorr"
  std::vector<std::string> resources;  ///< sbatch options: --cpus-per-task, --partition, --gres
};

/// What a submission will do: the chunks of the shot and the jobs for the work that is still missing.
struct Plan {
  std::string shotDir;    ///< absolute
  std::string sceneJson;  ///< the resolved scene (written to SHOT/farm/scene.json)
  std::string sphfx;      ///< absolute path of the sphfx the jobs run
  FrameRange frames;
  std::vector<Chunk> chunks;
  std::vector<PlannedJob> jobs;  ///< in submission order; empty when every frame is done
};

/// Works out the plan: validates the options, loads the scene, and checks the shot's files for which
/// stages and chunks still have missing frames. Writes nothing.
/// @throws InputError for an unknown scheduler, a bad chunk size or CPU count, a bad scene, a shot that
/// holds a simulation of another scene, or (unless dry-run) no sbatch on PATH.
Plan planSubmission(const SubmitOptions& options);

/// The sbatch command line for `job` (argv, sbatch first). `dependencyJobId` is the id of the job of
/// job.dependsOn (empty: none).
std::vector<std::string> sbatchCommand(const Plan& plan, const PlannedJob& job,
                                       const std::string& dependencyJobId);

/// The dry-run listing: each script and its sbatch line, with $<STAGE>_JOB for the ids not yet known.
std::string describePlan(const Plan& plan);

struct SubmittedJob {
  std::string stage;
  std::string jobId;
  std::vector<int> arrayTasks;
};

/// Writes SHOT/farm/ (scene.json, the scripts, submit.json, logs/), submits the plan's jobs with sbatch
/// and appends them to SHOT/farm/jobs.json. If an sbatch fails, the jobs this call submitted are
/// cancelled again. @throws Error naming sbatch's message if it fails; IoError if SHOT/farm cannot be
/// written.
std::vector<SubmittedJob> submitPlan(const Plan& plan, const SubmitOptions& options);

/// One row of `sphfx farm status`: a stage's chunk (chunk -1 for simulate and finish).
struct ChunkStatus {
  std::string stage;
  int chunk = -1;
  FrameRange frames;
  int done = 0;  ///< frames whose output file exists
  int total = 0;
  std::string jobId;  ///< the latest job (JOB_TASK for arrays) that was submitted for it
  std::string state;  ///< "done", else the scheduler's state (PENDING, RUNNING, FAILED, ...), else "missing"
};

/// Status of a submitted shot, from its frame files and, where they answer, squeue and sacct.
/// @throws InputError if SHOT/farm/submit.json does not exist (the shot was never submitted).
std::vector<ChunkStatus> shotStatus(const std::string& shotDir);

/// The status as a table, one row per stage and chunk.
std::string formatStatus(const std::vector<ChunkStatus>& rows);

/// Cancels the shot's recorded jobs that the scheduler still has queued or running (scancel).
/// Returns the ids cancelled. @throws InputError if the shot has no SHOT/farm/jobs.json or scancel is
/// not on PATH.
std::vector<std::string> cancelShot(const std::string& shotDir);

/// Reads the options recorded by the shot's last submission (SHOT/farm/submit.json).
/// @throws InputError if there is none.
SubmitOptions recordedOptions(const std::string& shotDir);

}  // namespace sphfx::farm
