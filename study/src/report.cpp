#include "report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include "metrics.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/log.h"

namespace fs = std::filesystem;

namespace sphfx::study {
namespace {

template <class F>
std::set<std::string> unionOf(const std::vector<RunResult>& results, F keys) {
  std::set<std::string> out;
  for (const auto& r : results)
    for (const auto& [k, v] : keys(r)) out.insert(k);
  return out;
}

std::string csvCell(std::string s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string parameterText(const RunResult& r) {
  std::string s;
  for (const auto& [k, v] : r.parameters) s += (s.empty() ? "" : ", ") + k + "=" + v;
  return s.empty() ? "(base scene)" : s;
}

bool measured(const RunResult& r) {
  auto it = r.metrics.find(r.primaryMetric);
  return r.outcome.status == RunStatus::Completed && it != r.metrics.end() && it->second > 0 &&
         r.outcome.wallSeconds > 0;
}

std::vector<const RunResult*> caseRuns(const std::vector<RunResult>& results, const std::string& name) {
  std::vector<const RunResult*> out;
  for (const auto& r : results)
    if (r.caseName == name) out.push_back(&r);
  return out;
}

/// Indices into `runs` of the measured runs on the Pareto front of (wall seconds, primary error).
std::vector<const RunResult*> caseFront(const std::vector<const RunResult*>& runs) {
  std::vector<const RunResult*> ok;
  std::vector<std::pair<double, double>> points;
  for (const RunResult* r : runs)
    if (measured(*r)) {
      ok.push_back(r);
      points.emplace_back(r->outcome.wallSeconds, r->metrics.at(r->primaryMetric));
    }
  std::vector<const RunResult*> front;
  for (size_t i : paretoFront(points)) front.push_back(ok[i]);
  return front;
}

std::string seriesOf(const StudyCase& c, const RunResult& r) {
  if (c.seriesAxis.empty()) return "all";
  auto it = r.parameters.find(c.seriesAxis);
  return it == r.parameters.end() ? "all" : it->second;
}

}  // namespace

double particleStepsPerSecond(const RunResult& r) {
  return r.outcome.wallSeconds > 0 && r.outcome.substeps > 0
             ? double(r.particles) * double(r.outcome.substeps) / r.outcome.wallSeconds
             : 0;
}

void writeResultsCsv(const std::string& path, const std::vector<RunResult>& results) {
  const auto params = unionOf(results, [](const RunResult& r) { return r.parameters; });
  const auto metrics = unionOf(results, [](const RunResult& r) { return r.metrics; });
  // Cells are appended separately: GCC 12 warns falsely (-Wrestrict) on "," + std::string temporaries.
  auto cell = [](std::string& line, const std::string& text) {
    line += ',';
    line += text;
  };
  std::string out = "case,status";
  for (const auto& p : params) cell(out, csvCell(p));
  out += ",particles,substeps,wall_s,particle_steps_per_s,dt_mean";
  for (const auto& m : metrics) cell(out, m);
  out += ",message\n";
  for (const auto& r : results) {
    out += csvCell(r.caseName);
    cell(out, toString(r.outcome.status));
    for (const auto& p : params) cell(out, csvCell(r.parameters.count(p) ? r.parameters.at(p) : ""));
    out += fmt::format(",{},{},{:.3f},{:.4g},{:.4g}", r.particles, r.outcome.substeps, r.outcome.wallSeconds,
                       particleStepsPerSecond(r), r.outcome.dtMean);
    for (const auto& m : metrics) out += r.metrics.count(m) ? fmt::format(",{:.6g}", r.metrics.at(m)) : ",";
    cell(out, csvCell(r.outcome.message));
    out += '\n';
  }
  writeTextAtomically(path, out);
}

bool plotErrorAgainstTime(const StudySpec& spec, const std::vector<RunResult>& results,
                          const std::string& outDir) {
  const fs::path dataDir = fs::path(outDir) / "plot";
  fs::create_directories(dataDir);
  const size_t panels = spec.cases.size();
  std::string script = fmt::format(
      "set terminal pngcairo size {},{} font 'sans,10'\nset output '{}'\nset multiplot layout 1,{}\n"
      "set termoption noenhanced\nset logscale xy\nset grid\nset key top right\nset xlabel 'wall seconds'\n",
      560 * panels, 460, (fs::path(outDir) / "error_vs_time.png").string(), panels);
  for (const StudyCase& c : spec.cases) {
    const auto runs = caseRuns(results, c.name);
    std::map<std::string, std::string> series;  // series name -> data lines
    for (const RunResult* r : runs)
      if (measured(*r))
        series[seriesOf(c, *r)] +=
            fmt::format("{} {}\n", r->outcome.wallSeconds, r->metrics.at(r->primaryMetric));
    std::string front;
    for (const RunResult* r : caseFront(runs))
      front += fmt::format("{} {}\n", r->outcome.wallSeconds, r->metrics.at(r->primaryMetric));
    script += fmt::format("set title '{}'\nset ylabel '{} (relative)'\nplot ", c.name,
                          runs.empty() ? std::string("error") : runs.front()->primaryMetric);
    std::string plots;
    for (const auto& [name, lines] : series) {
      const fs::path file = dataDir / (c.name + "_" + name + ".dat");
      writeTextAtomically(file.string(), lines);
      plots += fmt::format("{}'{}' using 1:2 with points pointsize 1.5 title '{}'", plots.empty() ? "" : ", ",
                           file.string(), name);
    }
    const fs::path frontFile = dataDir / (c.name + "_pareto.dat");
    writeTextAtomically(frontFile.string(), front);
    if (!front.empty())
      plots += fmt::format(
          "{}'{}' using 1:2 with linespoints dashtype 2 pointtype 6 pointsize 2.5 lc rgb 'black' title "
          "'Pareto front'",
          plots.empty() ? "" : ", ", frontFile.string());
    script += (plots.empty() ? "NaN title 'no measured runs'" : plots) + "\n";
  }
  script += "unset multiplot\n";
  const std::string scriptPath = (fs::path(outDir) / "error_vs_time.gp").string();
  writeTextAtomically(scriptPath, script);
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    logWarning("gnuplot is not installed: error_vs_time.png not drawn (script: " + scriptPath + ")");
    return false;
  }
  if (std::system(("gnuplot '" + scriptPath + "'").c_str()) != 0) {
    logWarning("gnuplot failed on " + scriptPath);
    return false;
  }
  return true;
}

namespace {

std::string resultTable(const std::vector<const RunResult*>& runs) {
  std::set<std::string> metricNames;
  for (const RunResult* r : runs)
    for (const auto& [k, v] : r->metrics) metricNames.insert(k);
  std::string t = "| parameters | particles | status | wall s | particle-steps/s | mean dt |";
  for (const auto& m : metricNames) t += " " + m + " |";
  t += "\n|---|---|---|---|---|---|";
  for (size_t i = 0; i < metricNames.size(); ++i) t += "---|";
  t += "\n";
  for (const RunResult* r : runs) {
    t += fmt::format("| {} | {} | {} | {:.1f} | {:.3g} | {:.3g} |", parameterText(*r), r->particles,
                     toString(r->outcome.status), r->outcome.wallSeconds, particleStepsPerSecond(*r),
                     r->outcome.dtMean);
    for (const auto& m : metricNames)
      t += r->metrics.count(m) ? fmt::format(" {:.4g} |", r->metrics.at(m)) : " |";
    t += "\n";
  }
  return t;
}

/// Observed order along the convergence axis of every error metric (positive at every point; counts
/// and signed quantities left out), for each combination of the other parameters. Primary metric first.
std::string convergenceText(const StudyCase& c, const std::vector<const RunResult*>& runs) {
  if (c.convergenceAxis.empty()) return {};
  const std::string primary = runs.front()->primaryMetric;
  std::map<std::string, std::map<std::string, std::vector<std::pair<double, double>>>> groups;
  std::vector<std::string> names{primary};
  for (const RunResult* r : runs) {
    // Every completed run, so that each error has all its points (the primary one may be missing where
    // it is measured against the finest run, front_self).
    if (r->outcome.status != RunStatus::Completed) continue;
    RunResult key = *r;
    const double h = std::stod(key.parameters.at(c.convergenceAxis));
    key.parameters.erase(c.convergenceAxis);
    for (const auto& [name, value] : r->metrics) {
      const bool count = name.size() > 8 && name.compare(name.size() - 8, 8, "_samples") == 0;
      if (count || name == "energy_change" || name == "settle_time") continue;
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      groups[parameterText(key)][name].emplace_back(h, value);
    }
  }
  std::string t = fmt::format(
      "\nObserved order of convergence of each error along {} (least-squares slope of log error "
      "against log {}):\n\n| other parameters | {} points |",
      c.convergenceAxis, c.convergenceAxis, primary);
  for (const auto& name : names) t += " " + name + " |";
  t += "\n|---|---|";
  for (size_t i = 0; i < names.size(); ++i) t += "---|";
  t += "\n";
  for (const auto& [group, metrics] : groups) {
    t += fmt::format("| {} | {} |", group, metrics.count(primary) ? metrics.at(primary).size() : 0);
    for (const auto& name : names) {
      const auto it = metrics.find(name);
      std::set<double> distinct;
      bool positive = it != metrics.end();
      if (positive)
        for (const auto& [h, e] : it->second) {
          distinct.insert(h);
          positive = positive && e > 0;
        }
      t += positive && distinct.size() >= 2 ? fmt::format(" {:.2f} |", observedOrder(it->second)) : " - |";
    }
    t += "\n";
  }
  return t;
}

std::string budgetText(const std::vector<const RunResult*>& runs) {
  const auto front = caseFront(runs);
  if (front.empty()) return "\nNo run completed and was measured, so no configuration can be recommended.\n";
  std::string t =
      "\nBest configuration for a time budget (the Pareto front: each row is the most accurate run "
      "that fits the budget):\n\n| budget (wall s) | error | configuration |\n|---|---|---|\n";
  for (const RunResult* r : front)
    t += fmt::format("| >= {:.1f} | {:.4g} | {} |\n", r->outcome.wallSeconds, r->metrics.at(r->primaryMetric),
                     parameterText(*r));
  return t;
}

}  // namespace

void writeStudyReport(const StudySpec& spec, const std::vector<RunResult>& results, const std::string& outDir,
                      bool plotted) {
  std::string md = fmt::format(
      "# Study: {}\n\nError against run time, {} runs. Errors are relative to the "
      "independent references (see docs/validation.md); wall seconds are the simulator's "
      "own figure for the whole run (context, compile, simulation, cache writing).\n\n{}\n\n",
      spec.name, results.size(), inputsDigestLine(studyInputsDigest(spec)));
  if (!spec.overrides.empty())
    md += fmt::format("Every run with `--set {}`.\n\n", fmt::join(spec.overrides, "`, `--set "));
  if (plotted) md += "![error against wall time](error_vs_time.png)\n\n";
  for (const StudyCase& c : spec.cases) {
    const auto runs = caseRuns(results, c.name);
    if (runs.empty()) continue;
    md += fmt::format("## {} ({})\n\nScene `{}`; primary metric `{}`.\n\n", c.name, c.scene, c.scene,
                      runs.front()->primaryMetric);
    md += resultTable(runs) + budgetText(runs) + convergenceText(c, runs);
    for (const RunResult* r : runs)
      if (r->outcome.status != RunStatus::Completed || !r->outcome.message.empty())
        md +=
            fmt::format("\n- {} {}: {}", parameterText(*r), toString(r->outcome.status), r->outcome.message);
    md += "\n\n";
  }
  writeTextAtomically((fs::path(outDir) / "report.md").string(), md);
}

}  // namespace sphfx::study
