#include "sphfx/study/stability.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "metrics.h"
#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/hash.h"
#include "sphfx/core/log.h"
#include "sphfx/core/scene.h"

namespace fs = std::filesystem;

namespace sphfx::study {

using schema::makeSchema;
using schema::Object;
using schema::Range;
using schema::SchemaError;

namespace {

const Object<StabilitySuite>& suiteSchema() {
  static const auto caseSchema = makeSchema<StabilityCase>([](Object<StabilityCase>& o) {
    o.text("name", &StabilityCase::name, "", "Case name.")
        .text("description", &StabilityCase::description, "", "What the case stresses.")
        .text("scene", &StabilityCase::scene, "", "Scene file, relative to the suite file.")
        .textList("set", &StabilityCase::set, "Overrides (path=value).")
        .flag("quick", &StabilityCase::quick, false, "Part of the quick set run in CI.")
        .flag("sweep", &StabilityCase::sweep, false, "Find the largest stable fixed time step.")
        .flag("energy", &StabilityCase::energy, false, "Report kinetic + potential energy over time.")
        .flag("may_stop", &StabilityCase::mayStop, false,
              "A clean stop by the health check is an acceptable outcome for this case.")
        .textList("criteria", &StabilityCase::criteriaNames,
                  "Physical criteria a completed run must meet: rest, energy, walls, speed "
                  "(sphfx::study::Criterion).")
        .textList("known_misses", &StabilityCase::knownMisses,
                  "Criteria the case is known to miss, as \"solver:criterion\" (open work; the "
                  "report lists them, and any other miss fails the suite).")
        .check([](const StabilityCase& c, const Json&, const std::string& path) {
          if (c.name.empty() || c.scene.empty()) throw SchemaError(path, "a case needs a name and a scene");
          for (const auto& name : c.criteriaNames) try {
              parseCriterion(name);
            } catch (const InputError& e) {
              throw SchemaError(schema::childPath(path, "criteria"), e.what());
            }
          for (const auto& miss : c.knownMisses) {
            const auto colon = miss.find(':');
            bool listed = false;
            if (colon != std::string::npos)
              for (const auto& name : c.criteriaNames) listed |= name == miss.substr(colon + 1);
            if (!listed)
              throw SchemaError(
                  schema::childPath(path, "known_misses"),
                  "expected \"solver:criterion\" with a criterion the case lists, got \"" + miss + "\"");
          }
        });
  });
  static const auto schema = makeSchema<StabilitySuite>([](Object<StabilitySuite>& o) {
    o.text("name", &StabilitySuite::name, "stability", "Suite name.")
        .number("timeout", &StabilitySuite::timeoutSeconds, 600, "s", Range{0, 1e6, true, false},
                "Wall-clock limit per run; over it the run is a failure (hang).")
        .textList("solvers", &StabilitySuite::solvers, "Solvers every case runs with (solver.method values).")
        .anyJson("dt_sweep", &StabilitySuite::dtSweep, Json::array(),
                 "Fixed time steps tried, increasing (s).")
        .list("cases", &StabilitySuite::cases, caseSchema, 1, 256, "The cases.")
        .check([](const StabilitySuite& s, const Json&, const std::string& path) {
          if (s.solvers.empty())
            throw SchemaError(schema::childPath(path, "solvers"), "expected at least one solver");
          if (!s.dtSweep.is_array())
            throw SchemaError(schema::childPath(path, "dt_sweep"), "expected an array");
          for (const auto& v : s.dtSweep)
            if (!v.is_number() || !(v.get<double>() > 0))
              throw SchemaError(schema::childPath(path, "dt_sweep"), "expected positive numbers");
        });
  });
  return *schema;
}

std::vector<std::pair<double, double>> energyOverTime(const std::string& sceneFile,
                                                      const std::string& shotDir) {
  const Scene scene = loadScene(sceneFile);
  const double m = scene.particleMass(), g = -scene.gravity[1];
  std::vector<std::pair<double, double>> e;
  for (int f : listFrames((fs::path(shotDir) / "cache").string(), "particles", "vdb")) {
    const ParticleFrame p = readParticleCache(particleCachePath(shotDir, f));
    e.emplace_back(p.time, kineticEnergy(p, m) + potentialEnergy(p, m, g));
  }
  return e;
}

StabilityRun runCase(const StabilitySuite& suite, const StabilityCase& c, const std::string& solver,
                     double dt, const std::string& outDir, const StudyOptions& options) {
  StabilityRun run;
  run.caseName = c.name;
  run.solver = solver;
  run.fixedDt = dt;
  const std::string label = dt > 0 ? fmt::format("{}-{}-dt{:g}", c.name, solver, dt) : c.name + "-" + solver;
  const fs::path runDir = fs::path(outDir) / "runs" / label;
  fs::remove_all(runDir);
  fs::create_directories(runDir);

  const Scene scene = resolveStabilityScene(suite, c, solver, dt);
  run.particles = countInitialParticles(scene);
  const std::string sceneFile = (runDir / "scene.json").string();
  writeTextAtomically(sceneFile, sceneToJson(scene).dump(2) + "\n");
  const std::string shotDir = (runDir / "shot").string();
  run.outcome = runSimulation(options.sphfxExe, sceneFile, shotDir, suite.timeoutSeconds, options.gl);
  if (run.outcome.status == RunStatus::Completed && !c.criteria.empty()) {
    const auto states = measureShot(shotDir, scene);
    for (Criterion k : c.criteria) {
      run.verdicts.push_back(judge(k, states, scene));
      run.known.push_back(c.knownMiss(solver, k));
    }
  }
  run.acceptable = (run.outcome.status == RunStatus::Completed && run.criteriaMet()) ||
                   (run.outcome.status == RunStatus::StoppedCleanly && (c.mayStop || dt > 0));
  if (c.energy && run.outcome.status == RunStatus::Completed && dt == 0)
    run.energy = energyOverTime(sceneFile, shotDir);
  if (!options.keepShots) fs::remove_all(fs::path(shotDir) / "cache");
  return run;
}

std::string energyText(const StabilityRun& r) {
  if (r.energy.size() < 2) return {};
  const double e0 = r.energy.front().second;
  std::string t = fmt::format(
      "\nEnergy (kinetic + potential) of `{}` with {}: relative change from the first frame\n\n"
      "| t (s) | E (J) | (E - E0)/|E0| |\n|---|---|---|\n",
      r.caseName, r.solver);
  const size_t step = std::max<size_t>(1, r.energy.size() / 12);
  for (size_t i = 0; i < r.energy.size(); i += step)
    t += fmt::format("| {:.3f} | {:.6g} | {:+.2e} |\n", r.energy[i].first, r.energy[i].second,
                     (r.energy[i].second - e0) / std::fabs(e0));
  return t;
}

std::string failedCriteria(const StabilityRun& r) {
  std::string t;
  for (const auto& v : r.verdicts)
    if (!v.passed) t += std::string(t.empty() ? "" : ", ") + toString(v.criterion);
  return "completed, missed " + t;
}

// Each criterion's figure and, where it is not met, the miss: "energy +0.000 % of g H; walls 0.222
// spacings; speed 2.877 m/s MISSED (known)".
std::string criteriaCell(const StabilityRun& r) {
  if (r.verdicts.empty()) return r.outcome.status == RunStatus::Completed ? "none asked" : "-";
  std::string t;
  for (size_t i = 0; i < r.verdicts.size(); ++i) {
    const auto& v = r.verdicts[i];
    t += fmt::format("{}{} {}{}", t.empty() ? "" : "; ", toString(v.criterion),
                     v.judged ? v.figure : "not judged",
                     v.passed ? "" : (r.known[i] ? " MISSED (known)" : " MISSED"));
  }
  return t;
}

// The criteria that were missed, and those the suite lists as known misses, in full: measured figure with
// its place and extent, bound, verdict. Every other criterion's figure is in the runs table.
std::string verdictText(const StabilityReport& report) {
  std::string t =
      "\nMissed criteria and known misses (measured from the caches; every criterion's figure is in the "
      "table above, its bound in docs/validation.md):\n\n"
      "| case | solver | particles | criterion | measured | bound | verdict |\n"
      "|---|---|---|---|---|---|---|\n";
  size_t rows = 0;
  for (const auto& r : report.runs)
    if (r.fixedDt == 0)
      for (size_t i = 0; i < r.verdicts.size(); ++i) {
        const auto& v = r.verdicts[i];
        if (!v.judged || (v.passed && !r.known[i])) continue;
        const std::string verdict = v.passed
                                        ? "met (listed as a known miss)"
                                        : fmt::format("{} (worst at frame {})",
                                                      r.known[i] ? "missed, known" : "MISSED", v.worstFrame);
        t += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", r.caseName, r.solver, r.particles,
                         toString(v.criterion), v.measured, v.bound, verdict);
        ++rows;
      }
  return rows ? t : t + "| (none) | | | | | | |\n";
}

void writeStabilityOutputs(const StabilitySuite& suite, bool quick, const StabilityReport& report,
                           const std::string& outDir) {
  std::string csv = "case,solver,fixed_dt,particles,status,criteria,acceptable,wall_s,substeps,message\n";
  for (const auto& r : report.runs)
    csv += fmt::format("{},{},{},{},{},\"{}\",{},{:.2f},{},\"{}\"\n", r.caseName, r.solver, r.fixedDt,
                       r.particles, toString(r.outcome.status), criteriaCell(r), r.acceptable ? "yes" : "no",
                       r.outcome.wallSeconds, r.outcome.substeps, r.outcome.message);
  writeTextAtomically((fs::path(outDir) / "stability.csv").string(), csv);

  std::string md = fmt::format(
      "# Stability suite: {}{}\n\n{} runs; failed: {}; stopped although the case must "
      "stay stable: {}; completed but missed a physical criterion: {}; known misses (open work, "
      "listed in the suite): {}, of which met this time: {}.\n\n{}\n\n",
      suite.name, quick ? " (quick set)" : "", report.runs.size(), report.failed, report.unexpected,
      report.violations, report.knownMisses, report.nowMet,
      inputsDigestLine(stabilityInputsDigest(suite, quick)));
  if (!suite.overrides.empty())
    md += fmt::format("Every run with `--set {}`.\n\n", fmt::join(suite.overrides, "`, `--set "));
  md += "| case | solver | particles | status | criteria | wall s | note |\n|---|---|---|---|---|---|---|\n";
  for (const auto& r : report.runs)
    if (r.fixedDt == 0)
      md +=
          fmt::format("| {} | {} | {} | {} | {} | {:.1f} | {} |\n", r.caseName, r.solver, r.particles,
                      toString(r.outcome.status), criteriaCell(r), r.outcome.wallSeconds, r.outcome.message);
  md += verdictText(report);
  // The largest fixed dt that completed, per case and solver.
  std::map<std::pair<std::string, std::string>, std::pair<double, std::string>> largest;
  for (const auto& r : report.runs) {
    if (r.fixedDt == 0) continue;
    auto& entry = largest[{r.caseName, r.solver}];
    const bool stable = r.outcome.status == RunStatus::Completed && r.criteriaMet();
    if (stable && r.fixedDt > entry.first) entry.first = r.fixedDt;
    if (!stable && entry.second.empty())
      entry.second =
          fmt::format("{:g} s: {}", r.fixedDt,
                      r.outcome.status == RunStatus::Completed ? failedCriteria(r)
                                                               : std::string(toString(r.outcome.status)));
  }
  if (!largest.empty()) {
    md +=
        "\nLargest stable fixed time step (the largest tried that completed and met the case's criteria; "
        "the smallest tried that did not, and how it ended):\n\n| case | solver | largest stable dt (s) | "
        "first unstable |\n|---|---|---|---|\n";
    for (const auto& [key, value] : largest)
      md += fmt::format("| {} | {} | {} | {} |\n", key.first, key.second,
                        value.first > 0 ? fmt::format("{:g}", value.first) : "none of those tried",
                        value.second.empty() ? "(every one tried was stable)" : value.second);
  }
  md += "\nStopped runs and their causes:\n\n";
  for (const auto& r : report.runs)
    if (r.outcome.status != RunStatus::Completed)
      md += fmt::format("- `{}` {}{}: {}: {}\n", r.caseName, r.solver,
                        r.fixedDt > 0 ? fmt::format(" dt={:g}", r.fixedDt) : "", toString(r.outcome.status),
                        r.outcome.message);
  for (const auto& r : report.runs) md += energyText(r);
  writeTextAtomically((fs::path(outDir) / "stability.md").string(), md);
}

}  // namespace

bool StabilityCase::knownMiss(const std::string& solver, Criterion c) const {
  return std::find(knownMisses.begin(), knownMisses.end(), solver + ":" + toString(c)) != knownMisses.end();
}

bool StabilityRun::criteriaMet() const {
  for (size_t i = 0; i < verdicts.size(); ++i)
    if (!verdicts[i].passed && !known[i]) return false;
  return true;
}

StabilitySuite loadStabilitySuite(const std::string& path) {
  StabilitySuite suite =
      schema::readDocument(suiteSchema(), schema::readJsonFile(path, "stability suite"), path);
  for (auto& c : suite.cases)
    for (const auto& name : c.criteriaNames) c.criteria.push_back(parseCriterion(name));
  suite.directory = fs::path(path).parent_path().string();
  return suite;
}

Scene resolveStabilityScene(const StabilitySuite& suite, const StabilityCase& c, const std::string& solver,
                            double dt, std::vector<std::string>* dropped) {
  const std::string base = (fs::path(suite.directory) / c.scene).string();
  Json raw = schema::readJsonFile(base, "scene");
  for (const auto& o : c.set) applyOverride(raw, o);
  const auto applyRun = [&](Json& j) {
    applyOverride(j, "solver.method=" + solver);
    if (dt > 0) {
      applyOverride(j, "time.dt_mode=fixed");
      applyOverride(j, fmt::format("time.dt={}", dt));
    }
  };
  applyRun(raw);  // first, so that a suite override is judged with the run's solver
  for (const auto& o : suite.overrides)
    if (!applyOverrideIfRead(raw, o) && dropped) dropped->push_back(o);
  applyRun(raw);  // last, as before the suite's overrides: the run's solver and step win
  return parseScene(raw, base + " (stability case " + c.name + ", " + solver + ")");
}

namespace {
/// Every (case, solver, fixed dt or 0) the suite runs, in order.
std::vector<std::tuple<const StabilityCase*, std::string, double>> stabilityPlan(const StabilitySuite& suite,
                                                                                 bool quick) {
  std::vector<std::tuple<const StabilityCase*, std::string, double>> plan;
  for (const auto& c : suite.cases) {
    if (quick && !c.quick) continue;
    for (const auto& solver : suite.solvers) {
      plan.emplace_back(&c, solver, 0.0);
      if (c.sweep)
        for (const auto& dt : suite.dtSweep) plan.emplace_back(&c, solver, dt.get<double>());
    }
  }
  return plan;
}
}  // namespace

std::string stabilityInputsDigest(const StabilitySuite& suite, bool quick) {
  std::string text = suite.name + (quick ? " quick\n" : "\n");
  for (const auto& [c, solver, dt] : stabilityPlan(suite, quick))
    text += fmt::format("{} {} {} criteria {} known {}\n{}\n", c->name, solver, dt,
                        fmt::join(c->criteriaNames, ","), fmt::join(c->knownMisses, ","),
                        sceneIdentityJson(resolveStabilityScene(suite, *c, solver, dt)).dump());
  return fnv1aHex(text);
}

StabilityReport runStabilitySuite(const StabilitySuite& suite, bool quick, const std::string& outDir,
                                  const StudyOptions& options) {
  const auto plan = stabilityPlan(suite, quick);
  // Every run's scene first, so that a bad override stops the suite before its first run, not hours in.
  // An override that no run reads is a mistake; one that some cases' settings leave unread is dropped
  // for them (fluid.wall_drag where a case has no viscosity).
  std::map<std::string, int> readBy;
  std::vector<std::string> notes;
  for (const auto& [c, solver, dt] : plan) {
    std::vector<std::string> dropped;
    resolveStabilityScene(suite, *c, solver, dt, &dropped);
    for (const auto& o : suite.overrides)
      if (std::find(dropped.begin(), dropped.end(), o) == dropped.end()) ++readBy[o];
    for (const auto& o : dropped)
      if (dt == 0)
        notes.push_back(
            fmt::format("--set {}: not read by stability case {} ({}); left out there", o, c->name, solver));
  }
  for (const auto& o : suite.overrides)
    if (readBy[o] == 0)
      throw InputError(fmt::format("--set {}: no run of the suite reads it with its settings", o));
  for (const auto& note : notes) logInfo(note);
  StabilityReport report;
  Progress progress("stability", int64_t(plan.size()));
  std::map<std::pair<std::string, std::string>, bool> sweepDone;
  for (const auto& [c, solver, dt] : plan) {
    // Once a sweep has failed to complete at some dt, larger ones are not run: they only cost time.
    if (dt > 0 && sweepDone[{c->name, solver}]) continue;
    StabilityRun run = runCase(suite, *c, solver, dt, outDir, options);
    if (run.outcome.status == RunStatus::Failed) ++report.failed;
    if (!run.acceptable && run.outcome.status == RunStatus::StoppedCleanly) ++report.unexpected;
    if (dt == 0 && run.outcome.status == RunStatus::Completed && !run.criteriaMet()) ++report.violations;
    for (size_t i = 0; dt == 0 && i < run.verdicts.size(); ++i) {
      if (run.known[i] && !run.verdicts[i].passed) ++report.knownMisses;
      if (run.known[i] && run.verdicts[i].passed && run.verdicts[i].judged) ++report.nowMet;
    }
    if (dt > 0 && !(run.outcome.status == RunStatus::Completed && run.criteriaMet()))
      sweepDone[{c->name, solver}] = true;
    progress.update(int64_t(report.runs.size() + 1),
                    fmt::format("{} {} {}", c->name, solver, toString(run.outcome.status)));
    report.runs.push_back(std::move(run));
  }
  progress.finish();
  writeStabilityOutputs(suite, quick, report, outDir);
  return report;
}

}  // namespace sphfx::study
