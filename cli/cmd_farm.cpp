// `sphfx farm submit|status|cancel|retry`: the shot as Slurm jobs (the logic is in sphfx_farm).
#include <fmt/format.h>

#include <cstdio>

#include "commands.h"
#include "sphfx/core/log.h"
#include "sphfx/farm/farm.h"

namespace sphfx::cli {

namespace {

void printSubmitted(const std::vector<farm::SubmittedJob>& jobs) {
  if (jobs.empty()) std::printf("nothing to submit: every frame and the contact sheet are done\n");
  for (const farm::SubmittedJob& j : jobs) {
    if (j.arrayTasks.empty())
      std::printf("%-9s job %s\n", j.stage.c_str(), j.jobId.c_str());
    else
      std::printf("%-9s job %s, %zu array tasks\n", j.stage.c_str(), j.jobId.c_str(), j.arrayTasks.size());
  }
}

void submitOrPrint(const farm::SubmitOptions& o) {
  const farm::Plan plan = farm::planSubmission(o);
  if (o.dryRun) {
    std::printf("%s", farm::describePlan(plan).c_str());
    return;
  }
  if (plan.jobs.empty()) {
    printSubmitted({});
    return;
  }
  printSubmitted(farm::submitPlan(plan, o));
  logInfo(fmt::format("farm: scripts and logs in {}/farm; `sphfx farm status {}` follows the shot",
                      plan.shotDir, o.shotDir));
}

void addSubmit(CLI::App* farm) {
  CLI::App* cmd = farm->add_subcommand(
      "submit",
      "Write the shot's job scripts to SHOT/farm and submit them (simulate, surface and render "
      "arrays over frame chunks, contact sheet); only stages and chunks with missing frames");
  auto o = std::make_shared<farm::SubmitOptions>();
  cmd->add_option("SCENE", o->sceneFile, "Scene JSON file")
      ->required()
      ->transform(resolveShippedFile, "", "");
  cmd->add_option("-o,--output", o->shotDir, "Shot directory (on storage every node sees)")->required();
  cmd->add_option("--scheduler", o->scheduler, "Scheduler (supported: slurm)")->capture_default_str();
  cmd->add_option("--chunk", o->chunk, "Frames per surface/render array task")->capture_default_str();
  cmd->add_option("--partition", o->partition, "Slurm partition of every job (default: the cluster's)");
  cmd->add_option("--sim-gres", o->simGres,
                  "Generic resource of the simulate job, e.g. gpu:1 (it then uses the EGL device backend)");
  cmd->add_option("--cpus-per-task", o->cpusPerTask, "CPUs of each job; tasks use as many threads")
      ->capture_default_str();
  cmd->add_flag("--movie", o->movie, "The last job also assembles an MP4 (ffmpeg on the node)");
  cmd->add_flag("--dry-run", o->dryRun, "Print the scripts and sbatch lines; write and submit nothing");
  auto sets = addSetOption(cmd);
  cmd->callback([o, sets] {
    o->sets = *sets;
    submitOrPrint(*o);
  });
}

void addStatus(CLI::App* farm) {
  CLI::App* cmd = farm->add_subcommand("status", "Per stage and chunk: frames done, job, state");
  auto shot = std::make_shared<std::string>();
  cmd->add_option("SHOT", *shot, "Shot directory")->required();
  cmd->callback([shot] { std::printf("%s", farm::formatStatus(farm::shotStatus(*shot)).c_str()); });
}

void addCancel(CLI::App* farm) {
  CLI::App* cmd = farm->add_subcommand("cancel", "Cancel the shot's queued and running jobs (scancel)");
  auto shot = std::make_shared<std::string>();
  cmd->add_option("SHOT", *shot, "Shot directory")->required();
  cmd->callback([shot] {
    const auto ids = farm::cancelShot(*shot);
    std::printf("cancelled %zu job(s)%s%s\n", ids.size(), ids.empty() ? "" : ": ",
                fmt::format("{}", fmt::join(ids, " ")).c_str());
  });
}

void addRetry(CLI::App* farm) {
  CLI::App* cmd = farm->add_subcommand(
      "retry",
      "Cancel what is still queued, then resubmit the stages and chunks with missing frames "
      "(with the options of the shot's first submission)");
  auto shot = std::make_shared<std::string>();
  auto dryRun = std::make_shared<bool>(false);
  cmd->add_option("SHOT", *shot, "Shot directory")->required();
  cmd->add_flag("--dry-run", *dryRun, "Print what would be resubmitted; cancel and submit nothing");
  cmd->callback([shot, dryRun] {
    farm::SubmitOptions o = farm::recordedOptions(*shot);
    o.dryRun = *dryRun;
    if (!o.dryRun) {
      const auto ids = farm::cancelShot(*shot);
      if (!ids.empty()) logInfo(fmt::format("farm retry: cancelled {}", fmt::join(ids, " ")));
    }
    submitOrPrint(o);
  });
}

}  // namespace

void addFarmCommand(CLI::App& app) {
  CLI::App* farm = app.add_subcommand("farm", "Run a shot on a render farm (Slurm job arrays)");
  farm->require_subcommand(1);
  addSubmit(farm);
  addStatus(farm);
  addCancel(farm);
  addRetry(farm);
}

}  // namespace sphfx::cli
