#pragma once
/// @file stability.h
/// @brief `sphfx stability`: stiff and extreme cases, each run classified as stable, stopped cleanly (the
/// health check caught it and named frame, substep and cause) or failed (crash, hang, error without
/// frame/substep/cause, or garbage in a written cache). Also finds each solver's largest stable fixed
/// time step per case and tracks energy for resting and sloshing cases.

#include <string>
#include <vector>

#include "sphfx/study/physics_checks.h"
#include "sphfx/study/study.h"

namespace sphfx::study {

struct StabilityCase {
  std::string name;
  std::string description;
  std::string scene;                       ///< relative to the suite file
  std::vector<std::string> set;            ///< overrides
  bool quick = false;                      ///< part of the quick set (CI)
  bool sweep = false;                      ///< find the largest stable fixed dt
  bool energy = false;                     ///< report kinetic + potential energy over time
  bool mayStop = false;                    ///< a clean stop is an acceptable outcome (e.g. dt far above CFL)
  std::vector<std::string> criteriaNames;  ///< as given in the suite file
  std::vector<Criterion> criteria;         ///< parsed from criteriaNames: what a completed run must meet
  /// "solver:criterion" pairs this case is known to miss (open work, listed so that the report shows
  /// them and any other miss fails the suite).
  std::vector<std::string> knownMisses;
  bool knownMiss(const std::string& solver, Criterion c) const;
};

struct StabilitySuite {
  std::string name;
  double timeoutSeconds = 0;
  std::vector<std::string> solvers;
  Json dtSweep;  ///< array of fixed time steps to try, increasing
  std::vector<StabilityCase> cases;
  std::string directory;
  /// Overrides for every run, after each case's own (`sphfx stability --set`): the suite's cases under
  /// another setting. The solver and a sweep's fixed dt still come last.
  std::vector<std::string> overrides;
};

/// @throws InputError naming the file and JSON path.
StabilitySuite loadStabilitySuite(const std::string& path);

struct StabilityRun {
  std::string caseName, solver;
  double fixedDt = 0;  ///< 0: the case's own time step control
  size_t particles = 0;
  RunOutcome outcome;
  /// Completed and every criterion met, or stopped cleanly where the case allows it.
  bool acceptable = false;
  std::vector<CriterionResult> verdicts;          ///< the case's criteria on a completed run
  std::vector<bool> known;                        ///< per verdict: a miss the case lists as known
  std::vector<std::pair<double, double>> energy;  ///< (time, kinetic + potential) when asked
  /// Every criterion met, known misses aside.
  bool criteriaMet() const;
};

struct StabilityReport {
  std::vector<StabilityRun> runs;
  size_t failed = 0;       ///< runs classified failed: must be zero
  size_t unexpected = 0;   ///< runs that stopped although the case must stay stable
  size_t violations = 0;   ///< completed runs (own time step control) that miss a criterion not listed known
  size_t knownMisses = 0;  ///< misses the suite lists as known (open work)
  size_t nowMet = 0;       ///< known misses that this run met (the list can shrink)
};

/// The scene of one run: the case's scene with its overrides, the suite's, the solver, and a fixed `dt`
/// if > 0. A suite override that the run's settings leave unread (fluid.wall_drag in a case without
/// viscosity) is left out, and added to `dropped` where given.
/// @throws InputError as loadScene, naming the case and the solver.
Scene resolveStabilityScene(const StabilitySuite& suite, const StabilityCase& c, const std::string& solver,
                            double dt, std::vector<std::string>* dropped = nullptr);

/// As studyInputsDigest, for the suite's runs (the quick subset if `quick`).
std::string stabilityInputsDigest(const StabilitySuite& suite, bool quick);

/// Runs the suite (the quick subset if `quick`) into `outDir` and writes stability.csv and stability.md.
/// @throws InputError before the first run if any run's scene does not resolve (resolveStabilityScene), or
/// if no run reads one of the suite's overrides.
StabilityReport runStabilitySuite(const StabilitySuite& suite, bool quick, const std::string& outDir,
                                  const StudyOptions& options);

}  // namespace sphfx::study
