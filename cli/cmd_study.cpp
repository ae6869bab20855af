#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "sphfx/core/data_files.h"
#include "sphfx/core/error.h"
#include "sphfx/study/stability.h"
#include "sphfx/study/study.h"

namespace fs = std::filesystem;

namespace sphfx::cli {
namespace {

std::vector<std::string> glArgs(const GLContextOptions& gl) {
  std::vector<std::string> args{"--gl", toString(gl.backend)};
  if (gl.debug) args.push_back("--gl-debug");
  return args;
}

}  // namespace

void addStudyCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("study",
                                     "Run an error-against-run-time study: a grid of simulations on "
                                     "validation scenes, measured against independent references");
  auto file = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto keep = std::make_shared<bool>(false);
  cmd->add_option("STUDY", *file, "Study JSON file (e.g. studies/quick.json)")
      ->required()
      ->transform(resolveShippedFile, "", "");
  cmd->add_option("-o,--output", *out, "Output folder (results.csv, error_vs_time.png, report.md)")
      ->required();
  cmd->add_flag("--keep-shots", *keep, "Keep every run's particle caches");
  auto sets = addSetOption(cmd,
                           "Override a scene parameter in every run, after the case's own and before "
                           "its grid point (an axis is an error)");
  auto gl = addGLOptions(cmd);
  cmd->callback([=] {
    study::StudySpec spec = study::loadStudy(*file);
    spec.overrides = *sets;  // after each case's own overrides, before its grid point
    const auto results = study::runStudy(spec, *out, {executablePath(), glArgs(*gl), *keep});
    size_t failed = 0;
    for (const auto& r : results) failed += r.outcome.status == study::RunStatus::Failed ? 1 : 0;
    std::printf("%zu runs, %zu failed; report: %s\n", results.size(), failed,
                (fs::path(*out) / "report.md").c_str());
    if (failed)
      throw Error(fmt::format("{} of {} study runs failed (see {}/report.md)", failed, results.size(), *out));
  });
}

void addStabilityCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("stability",
                                     "Run the stability suite on stiff and extreme cases; exits "
                                     "non-zero if any run fails (crash, hang, garbage), stops "
                                     "where it must not, or misses a physical criterion");
  auto file = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>("stability");
  auto quick = std::make_shared<bool>(false);
  auto keep = std::make_shared<bool>(false);
  auto solvers = std::make_shared<std::vector<std::string>>();
  cmd->add_option("--suite", *file, "Suite file (default: the shipped studies/stability.json)");
  cmd->add_option("-o,--output", *out, "Output folder (stability.csv, stability.md)")->capture_default_str();
  cmd->add_flag("--quick", *quick, "Only the quick set (what CI runs)");
  cmd->add_option("--solvers", *solvers, "Override the suite's solvers (e.g. --solvers wcsph)")
      ->delimiter(',');
  cmd->add_flag("--keep-shots", *keep, "Keep every run's particle caches");
  auto sets = addSetOption(cmd, "Override a scene parameter in every run, after the case's own");
  auto gl = addGLOptions(cmd);
  cmd->callback([=] {
    // Runs are subprocesses of this very executable, so the suite measures the build it is part of.
    const std::string suiteFile =
        file->empty() ? dataDirectory() + "/studies/stability.json" : resolveShippedFile(*file);
    study::StabilitySuite suite = study::loadStabilitySuite(suiteFile);
    if (!solvers->empty()) suite.solvers = *solvers;
    suite.overrides = *sets;  // after each case's own overrides, in every run
    const auto report = study::runStabilitySuite(suite, *quick, *out, {executablePath(), glArgs(*gl), *keep});
    std::printf(
        "%zu runs: %zu failed, %zu stopped although they must stay stable, %zu missed a physical "
        "criterion (%zu known misses, %zu of the known met this time); report: %s\n",
        report.runs.size(), report.failed, report.unexpected, report.violations, report.knownMisses,
        report.nowMet, (fs::path(*out) / "stability.md").c_str());
    if (report.failed || report.unexpected || report.violations)
      throw Error(fmt::format(
          "stability suite: {} failed, {} unexpected stops, {} missed criteria (see {}/stability.md)",
          report.failed, report.unexpected, report.violations, *out));
  });
}

}  // namespace sphfx::cli
