#pragma once
/// @file study.h
/// @brief `sphfx study`: a grid of simulations on validation scenes, each measured for error against an
/// independent reference and for wall time, reported as a table, a log-log plot with the Pareto front,
/// and a Markdown report.
///
/// A study talks to the simulator only through the `sphfx simulate` command and the caches it writes,
/// like every other stage: each run is a subprocess with a time limit, so a crash or a hang is recorded
/// as a failed run instead of ending the study.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sphfx/core/scene.h"
#include "sphfx/core/schema.h"

namespace sphfx::study {

using schema::Json;

enum class Validation { DamBreak, Hydrostatic, Poiseuille, TaylorGreen };

/// One parameter axis of the grid: a scene path (as for --set) and the values it takes.
struct Axis {
  std::string path;
  Json values;  ///< array of JSON values
};

/// One validation scene and its grid.
struct StudyCase {
  std::string name;
  std::string scene;  ///< scene file, relative to the study file
  Validation validation = Validation::DamBreak;
  std::vector<std::string> set;  ///< overrides applied to every run
  std::vector<Axis> axes;        ///< the grid is their Cartesian product
  std::string convergenceAxis;   ///< axis along which the observed order is computed ("" = none)
  std::string seriesAxis;        ///< axis whose values are the plot's series (e.g. solver.method)
  std::string metric;            ///< error the front and the plot rank by ("" = primaryMetric(validation))
};

struct StudySpec {
  std::string name;
  double timeoutSeconds = 0;  ///< per run
  std::vector<StudyCase> cases;
  std::string directory;  ///< folder of the study file (scene paths are relative to it)
  /// Overrides for every run, after each case's own and before its grid point (`sphfx study --set`): the
  /// study under another setting. One that names an axis of a case is an error (the axis would vanish).
  std::vector<std::string> overrides;
};

/// Reads and validates a study file. @throws InputError naming the file and JSON path.
StudySpec loadStudy(const std::string& path);

/// One run of a case: a value for each axis, as (scene path, value).
using GridPoint = std::vector<std::pair<std::string, Json>>;
/// Every run of a case: the Cartesian product of its axes, the first axis varying slowest.
std::vector<GridPoint> gridPoints(const StudyCase& studyCase);
/// The scene a run simulates: the case's scene file, its "set" overrides, the study's, then the grid point.
/// A study override that the run's settings leave unread (applyOverrideIfRead) is left out, and added to
/// `dropped` where given.
/// @throws InputError if the file is unreadable or the resulting scene is invalid (names case and path).
Scene resolveRunScene(const StudySpec& spec, const StudyCase& studyCase, const GridPoint& point,
                      std::vector<std::string>* dropped = nullptr);

/// A digest (16 hex digits, FNV-1a) of everything a study's report depends on besides the code: the
/// study's name and every run's resolved scene, defaults included. The report states it, so a test can
/// tell that a committed report no longer matches the shipped study (a scene, an axis or a default
/// changed). @throws InputError as loadScene.
std::string studyInputsDigest(const StudySpec& spec);

/// "<!-- inputs digest: D -->": the line a report carries, and the one a staleness check looks for.
std::string inputsDigestLine(const std::string& digest);

/// How one simulation ended.
enum class RunStatus { Completed, StoppedCleanly, Failed };
std::string toString(RunStatus s);

/// A run of `sphfx simulate` and what it left behind.
struct RunOutcome {
  RunStatus status = RunStatus::Failed;
  int exitCode = -1;
  double wallSeconds = 0;  ///< the simulator's own figure from the manifest if present, else the process's
  /// The error line for stopped or failed runs; for completed runs, solverWarnings.
  std::string message;
  /// From the manifest: how many frames carry solver warnings (a DFSPH solve stopped above its
  /// tolerance) and the first; empty when none does.
  std::string solverWarnings;
  std::string shotDir;
  long substeps = 0;
  double dtMean = 0;
};

/// Runs `sphfx simulate SCENE -o SHOT -q` as a subprocess with a time limit. A run that exits 3
/// (health check) counts as stopped cleanly only if its message names the frame, the substep and a
/// cause; any other non-zero exit, a signal or the time limit is a failure. Completed runs are then
/// checked for caches that should not exist (NaN/Inf or particles outside the domain): failed.
RunOutcome runSimulation(const std::string& sphfxExe, const std::string& sceneFile,
                         const std::string& shotDir, double timeoutSeconds,
                         const std::vector<std::string>& extraArgs = {});

/// One row of results.csv.
struct RunResult {
  std::string caseName;
  std::map<std::string, std::string> parameters;  ///< axis path -> value text
  size_t particles = 0;
  RunOutcome outcome;
  std::map<std::string, double> metrics;  ///< name -> value
  std::string primaryMetric;              ///< the metric plotted against time
  /// Dam break: (t, the surge front's distance from the column's back wall) per frame, for
  /// addFrontSelfConvergence(); not written to results.csv.
  std::vector<std::pair<double, double>> front;
};

/// Metrics of a finished shot for a validation type (reads the caches and the resolved scene); for the
/// dam break, `front` (if given) receives the front per frame as RunResult::front.
/// @throws InputError / IoError if the caches are missing or lack needed attributes.
std::map<std::string, double> measureShot(Validation validation, const std::string& sceneFile,
                                          const std::string& shotDir,
                                          std::vector<std::pair<double, double>>* front = nullptr);

/// The dam break's self-convergence (a reference free of what the experiment has and the scene does not:
/// gate, friction, air): for each completed run of `runs` with a front, against the run with the
/// smallest fluid.spacing among those with the same other parameters, the metric "front_self": the RMS
/// over the reference's frames from 0.05 s until its front has run 90 % of the way from the column's
/// back wall to the far wall of (x - x_ref) / (x_ref - a), a the column's width. `scene` gives the
/// geometry (any run's: the spacing does not change it). The reference itself gets no value. Does
/// nothing unless `c` is a dam break converging along fluid.spacing. Throws nothing.
void addFrontSelfConvergence(const StudyCase& c, const Scene& scene, std::vector<RunResult*> runs);
/// The metric a validation type is judged by (plotted against wall time).
std::string primaryMetric(Validation validation);
/// The errors a case of `validation` may rank its runs by (StudyCase::metric): primaryMetric() first.
std::vector<std::string> errorMetrics(Validation validation);

struct StudyOptions {
  std::string sphfxExe;         ///< the sphfx executable to run (normally /proc/self/exe)
  std::vector<std::string> gl;  ///< extra args for simulate, e.g. {"--gl", "egl-surfaceless"}
  bool keepShots = false;       ///< keep every run's caches (default: only the manifest and log)
};

/// Runs every case of the study into `outDir` and writes results.csv, error_vs_time.png (if gnuplot is
/// installed; a warning otherwise) and report.md. Returns the results.
/// @throws InputError for bad studies (an override that no run reads included), IoError if outDir cannot
/// be written.
std::vector<RunResult> runStudy(const StudySpec& spec, const std::string& outDir,
                                const StudyOptions& options);

}  // namespace sphfx::study
