#include "sphfx/study/study.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "metrics.h"
#include "report.h"
#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/hash.h"
#include "sphfx/core/log.h"
#include "sphfx/core/scene.h"

namespace fs = std::filesystem;

namespace sphfx::study {

namespace {

/// A value as --set takes it: strings bare, everything else as JSON.
std::string valueText(const Json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
}

/// Writes the run's resolved scene (base file + case overrides + grid point) and returns its path.
std::string writeRunScene(const StudySpec& spec, const StudyCase& c, const GridPoint& point,
                          const std::string& runDir, size_t& particles) {
  const Scene scene = resolveRunScene(spec, c, point);
  particles = countInitialParticles(scene);
  const std::string path = (fs::path(runDir) / "scene.json").string();
  writeTextAtomically(path, sceneToJson(scene).dump(2) + "\n");
  return path;
}

/// Keeps the manifest and log of a run, drops its caches (they can be large and are not needed once
/// measured).
void dropCaches(const std::string& shotDir) {
  std::error_code ec;
  fs::remove_all(fs::path(shotDir) / "cache", ec);
}

}  // namespace

std::vector<GridPoint> gridPoints(const StudyCase& c) {
  std::vector<GridPoint> points{{}};
  for (const Axis& axis : c.axes) {
    std::vector<GridPoint> next;
    for (const auto& p : points)
      for (const Json& v : axis.values) {
        auto q = p;
        q.emplace_back(axis.path, v);
        next.push_back(std::move(q));
      }
    points = std::move(next);
  }
  return points;
}

std::string inputsDigestLine(const std::string& digest) {
  return "<!-- inputs digest: " + digest + " -->";
}

std::string studyInputsDigest(const StudySpec& spec) {
  std::string text = spec.name + "\n";
  for (const StudyCase& c : spec.cases)
    for (const GridPoint& point : gridPoints(c))
      text += c.name + "\n" + sceneIdentityJson(resolveRunScene(spec, c, point)).dump() + "\n";
  return fnv1aHex(text);
}

Scene resolveRunScene(const StudySpec& spec, const StudyCase& c, const GridPoint& point,
                      std::vector<std::string>* dropped) {
  const std::string base = (fs::path(spec.directory) / c.scene).string();
  Json raw = schema::readJsonFile(base, "scene");
  for (const auto& o : c.set) applyOverride(raw, o);
  const auto applyPoint = [&](Json& j) {
    for (const auto& [path, value] : point) applyOverride(j, path + "=" + valueText(value));
  };
  applyPoint(raw);  // first, so that an override is judged with the run's settings (its solver)
  for (const auto& o : spec.overrides) {
    const std::string path = o.substr(0, o.find('='));
    for (const Axis& a : c.axes)
      if (a.path == path)
        throw InputError(
            fmt::format("--set {}: {} is an axis of study case {}; the study varies it", o, path, c.name));
    if (!applyOverrideIfRead(raw, o) && dropped) dropped->push_back(o);
  }
  applyPoint(raw);  // last, as before the overrides
  return parseScene(raw, base + " (case " + c.name + ")");
}

std::vector<RunResult> runStudy(const StudySpec& spec, const std::string& outDir,
                                const StudyOptions& options) {
  std::vector<RunResult> results;
  size_t total = 0;
  for (const StudyCase& c : spec.cases) total += gridPoints(c).size();
  // Every run's scene first, so that a bad override stops the study before its first run, not hours in.
  // An override that no run reads is a mistake; one that some runs' settings leave unread is left out of
  // those (fluid.wall_drag in a case with the laplacian viscosity).
  std::map<std::string, int> readBy;
  std::vector<std::string> notes;
  for (const StudyCase& c : spec.cases)
    for (const auto& point : gridPoints(c)) {
      std::vector<std::string> dropped;
      resolveRunScene(spec, c, point, &dropped);
      for (const auto& o : spec.overrides)
        if (std::find(dropped.begin(), dropped.end(), o) == dropped.end()) ++readBy[o];
      for (const auto& o : dropped)
        notes.push_back(
            fmt::format("--set {}: not read by a run of study case {}; left out there", o, c.name));
    }
  for (const auto& o : spec.overrides)
    if (readBy[o] == 0)
      throw InputError(fmt::format("--set {}: no run of the study reads it with its settings", o));
  notes.erase(std::unique(notes.begin(), notes.end()), notes.end());
  for (const auto& note : notes) logInfo(note);
  Progress progress("study " + spec.name, int64_t(total));
  fs::create_directories(outDir);
  for (const StudyCase& c : spec.cases) {
    const size_t caseStart = results.size();
    const std::vector<GridPoint> points = gridPoints(c);
    size_t index = 0;
    for (const auto& point : points) {
      RunResult r;
      r.caseName = c.name;
      r.primaryMetric = c.metric.empty() ? primaryMetric(c.validation) : c.metric;
      for (const auto& [path, value] : point) r.parameters[path] = valueText(value);
      const std::string runDir =
          (fs::path(outDir) / "runs" / fmt::format("{}-{:03d}", c.name, index++)).string();
      fs::remove_all(runDir);
      const std::string sceneFile = writeRunScene(spec, c, point, runDir, r.particles);
      const std::string shotDir = (fs::path(runDir) / "shot").string();
      r.outcome = runSimulation(options.sphfxExe, sceneFile, shotDir, spec.timeoutSeconds, options.gl);
      if (r.outcome.status == RunStatus::Completed) {
        try {
          r.metrics = measureShot(c.validation, sceneFile, shotDir, &r.front);
        } catch (const Error& e) {
          r.outcome.status = RunStatus::Failed;
          r.outcome.message = std::string("cannot measure: ") + e.what();
        }
      }
      if (!options.keepShots) dropCaches(shotDir);
      results.push_back(std::move(r));
      progress.update(int64_t(results.size()),
                      fmt::format("{} {} {:.1f}s", c.name, toString(results.back().outcome.status),
                                  results.back().outcome.wallSeconds));
    }
    if (c.validation == Validation::DamBreak && !points.empty()) {
      std::vector<RunResult*> caseResults;
      for (size_t k = caseStart; k < results.size(); ++k) caseResults.push_back(&results[k]);
      addFrontSelfConvergence(c, resolveRunScene(spec, c, points.front()), caseResults);
    }
  }
  progress.finish();
  writeResultsCsv((fs::path(outDir) / "results.csv").string(), results);
  const bool plotted = plotErrorAgainstTime(spec, results, outDir);
  writeStudyReport(spec, results, outDir, plotted);
  return results;
}

}  // namespace sphfx::study
