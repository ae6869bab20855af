#pragma once
/// @file report.h
/// @brief A study's outputs: results.csv, the error-against-time plot (gnuplot), report.md.

#include <string>
#include <vector>

#include "sphfx/study/study.h"

namespace sphfx::study {

/// One row per run: case, status, parameters, particles, substeps, wall seconds, particle-steps/s,
/// every metric, message. Written atomically. @throws IoError.
void writeResultsCsv(const std::string& path, const std::vector<RunResult>& results);

/// Writes OUT/error_vs_time.png: per case a log-log panel of the primary metric against wall seconds,
/// one series per value of the case's series axis, the Pareto front drawn as a line. Returns false (with
/// a warning) when gnuplot is not installed; the data files and script are written either way.
bool plotErrorAgainstTime(const StudySpec& spec, const std::vector<RunResult>& results,
                          const std::string& outDir);

/// Writes OUT/report.md: tables, the plot, the Pareto front, the best configuration per time budget and
/// the observed orders of convergence. @throws IoError.
void writeStudyReport(const StudySpec& spec, const std::vector<RunResult>& results, const std::string& outDir,
                      bool plotted);

/// Particle-steps per second of a run (0 if unknown).
double particleStepsPerSecond(const RunResult& r);

}  // namespace sphfx::study
