// `sphfx inspect SHOT`: the physics of a simulated shot read back from its caches (energy, fastest
// particle, free surface, bulk density, closest approach to a wall), the stability criteria's verdicts and
// the solver's warnings.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "sphfx/core/error.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/scene.h"
#include "sphfx/study/physics_checks.h"

namespace sphfx::cli {
namespace {

Scene shotScene(const std::string& shot) {
  const ManifestJson m = readManifest(shot);
  if (!m.contains("simulate") || !m["simulate"].contains("scene"))
    throw InputError(manifestPath(shot) + ": no simulation recorded (expected /simulate/scene)");
  return parseScene(schema::Json::parse(m["simulate"]["scene"].dump()),
                    manifestPath(shot) + " /simulate/scene");
}

void printStates(const std::vector<study::FrameState>& states, double spacing, size_t every) {
  std::printf("%6s %8s %9s %11s %11s %9s %10s %9s\n", "frame", "t (s)", "particles", "KE/m J/kg", "E/m J/kg",
              "vmax m/s", "surface m", "bulk rho");
  for (size_t i = 0; i < states.size(); ++i) {
    if (i % every != 0 && i + 1 != states.size()) continue;
    const auto& s = states[i];
    std::printf("%6d %8.4f %9zu %11.3e %11.5f %9.4f %10.5f %9s   gap %.3f spacings\n", s.frame, s.time,
                s.particles, s.kineticPerMass, s.energyPerMass, s.maxSpeed, s.surfaceHeight,
                std::isfinite(s.bulkDensityRatio) ? fmt::format("{:.4f}", s.bulkDensityRatio).c_str() : "-",
                s.closest.wallGap / spacing);
  }
}

// The solver's own warnings, from the manifest's per-frame entries (sim::FrameStats::warnings): a
// frame's verdicts rest on results the solver could not trust there.
void printSolverWarnings(const std::string& shot) {
  const ManifestJson m = readManifest(shot);
  std::vector<std::pair<int, std::string>> warnings;
  for (const auto& f : m["simulate"].value("per_frame", ManifestJson::array()))
    for (const auto& w : f.value("warnings", ManifestJson::array()))
      warnings.emplace_back(f["frame"].get<int>(), w.get<std::string>());
  if (warnings.empty()) {
    std::printf("solver  no warnings\n");
    return;
  }
  std::printf("solver  %zu warnings, frames %d to %d; the first, frame %d: %s\n", warnings.size(),
              warnings.front().first, warnings.back().first, warnings.front().first,
              warnings.front().second.c_str());
}

}  // namespace

void addInspectCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "inspect", "Physics of a simulated shot from its caches, judged by the stability criteria");
  auto shot = std::make_shared<std::string>();
  auto every = std::make_shared<size_t>(1);
  auto criteria = std::make_shared<std::vector<std::string>>(
      std::vector<std::string>{"rest", "energy", "walls", "speed"});
  cmd->add_option("SHOT", *shot, "Shot directory")->required();
  cmd->add_option("--every", *every, "Print every Nth frame (the last is always printed)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--criteria", *criteria, "Criteria to judge: rest, energy, walls, speed");
  cmd->callback([shot, every, criteria] {
    const Scene scene = shotScene(*shot);
    const auto states = study::measureShot(*shot, scene);
    if (states.empty()) throw InputError(*shot + "/cache: no particle caches");
    printStates(states, scene.fluid.spacing, *every);
    for (const auto& name : *criteria) {
      const auto r = study::judge(study::parseCriterion(name), states, scene);
      if (!r.judged) {
        std::printf("%-7s -: %s (%s)\n", name.c_str(), r.measured.c_str(), r.bound.c_str());
        continue;
      }
      std::printf("%-7s %s: %s (bound %s; worst at frame %d)\n", name.c_str(), r.passed ? "pass" : "FAIL",
                  r.measured.c_str(), r.bound.c_str(), r.worstFrame);
    }
    printSolverWarnings(*shot);
  });
}

}  // namespace sphfx::cli
