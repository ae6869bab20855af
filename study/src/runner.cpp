#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"
#include "sphfx/study/study.h"

extern char** environ;
namespace fs = std::filesystem;

namespace sphfx::study {
namespace {

/// The last "sphfx: error: ..." line of a log (what the user would read).
std::string lastErrorLine(const std::string& logPath) {
  std::ifstream in(logPath);
  std::string line, last;
  while (std::getline(in, line))
    if (line.rfind("sphfx: error: ", 0) == 0) last = line.substr(14);
  return last;
}

bool namesFrameSubstepAndCause(const std::string& message) {
  // The simulator's health errors read "frame F, substep S: CAUSE ..."; all three must be there.
  return message.find("frame") != std::string::npos && message.find("substep") != std::string::npos &&
         message.find(':') != std::string::npos;
}

/// A finished run must not have written garbage: every cached particle finite and inside the domain.
std::string checkCaches(const std::string& sceneFile, const std::string& shotDir) {
  const Scene scene = loadScene(sceneFile);
  const std::string cacheDir = (fs::path(shotDir) / "cache").string();
  const std::vector<int> frames = listFrames(cacheDir, "particles", "vdb");
  if (frames.empty()) return "no cache frames written";
  for (int f : frames) {
    const ParticleFrame p = readParticleCache(particleCachePath(shotDir, f));
    for (size_t i = 0; i < p.size(); ++i)
      for (int a = 0; a < 3; ++a) {
        const double x = p.position[i][a], v = p.velocity[i][a];
        const double slack = 1e-4 * (scene.domain.max[a] - scene.domain.min[a]);
        if (!std::isfinite(x) || !std::isfinite(v))
          return fmt::format("frame {}: particle {} has a non-finite position or velocity", f, i);
        if (x < scene.domain.min[a] - slack || x > scene.domain.max[a] + slack)
          return fmt::format("frame {}: particle {} is outside the domain ({} = {})", f, i, "xyz"[a], x);
      }
  }
  return {};
}

// The frames whose manifest entries carry solver warnings (sim::FrameStats::warnings), and the first.
std::string solverWarningsText(const ManifestJson& simulate) {
  int frames = 0;
  std::string first;
  for (const auto& f : simulate.value("per_frame", ManifestJson::array())) {
    const auto warnings = f.value("warnings", ManifestJson::array());
    if (warnings.empty()) continue;
    if (frames++ == 0)
      first = fmt::format("frame {}: {}", f.value("frame", 0), warnings[0].get<std::string>());
  }
  return frames ? fmt::format("solver warnings in {} frames; the first, {}", frames, first) : "";
}

void readSimulatorFigures(const std::string& shotDir, RunOutcome& out) {
  try {
    const ManifestJson m = readManifest(shotDir);
    if (!m.contains("simulate")) return;
    const auto& s = m["simulate"];
    if (s.contains("wall_seconds") && s["wall_seconds"].is_number())
      out.wallSeconds = s["wall_seconds"].get<double>();
    if (s.contains("substeps") && s["substeps"].is_number()) out.substeps = s["substeps"].get<long>();
    if (s.contains("dt") && s["dt"].contains("mean") && s["dt"]["mean"].is_number())
      out.dtMean = s["dt"]["mean"].get<double>();
    out.solverWarnings = solverWarningsText(s);
  } catch (const Error&) {
    // A run killed mid-write has no usable manifest; the process figures stand.
  }
}

}  // namespace

RunOutcome runSimulation(const std::string& sphfxExe, const std::string& sceneFile,
                         const std::string& shotDir, double timeoutSeconds,
                         const std::vector<std::string>& extraArgs) {
  RunOutcome out;
  out.shotDir = shotDir;
  fs::create_directories(shotDir);
  const std::string logPath = (fs::path(shotDir) / "simulate.log").string();

  std::vector<std::string> args = {sphfxExe, "-q", "simulate", sceneFile, "-o", shotDir};
  args.insert(args.end(), extraArgs.begin(), extraArgs.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const auto start = std::chrono::steady_clock::now();
  const int spawnError = posix_spawn(&pid, sphfxExe.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawnError != 0) throw IoError(sphfxExe + ": cannot start: " + std::strerror(spawnError));

  int status = 0;
  bool timedOut = false;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > timeoutSeconds) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      timedOut = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  out.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  readSimulatorFigures(shotDir, out);
  out.message = lastErrorLine(logPath);

  if (timedOut) {
    out.message = fmt::format("did not finish within {} s (hang or far too slow)", timeoutSeconds);
    return out;
  }
  if (WIFSIGNALED(status)) {
    out.message = fmt::format("crashed with signal {}", WTERMSIG(status));
    return out;
  }
  out.exitCode = WEXITSTATUS(status);
  if (out.exitCode == 3) {
    out.status = namesFrameSubstepAndCause(out.message) ? RunStatus::StoppedCleanly : RunStatus::Failed;
    if (out.status == RunStatus::Failed)
      out.message = "stopped without naming frame, substep and cause: " + out.message;
    // The frames finished before the stop must be sound too.
    const std::string garbage = checkCaches(sceneFile, shotDir);
    if (!garbage.empty() && garbage != "no cache frames written") {
      out.status = RunStatus::Failed;
      out.message = "stopped, but an earlier frame holds garbage: " + garbage;
    }
  } else if (out.exitCode == 0) {
    const std::string garbage = checkCaches(sceneFile, shotDir);
    out.status = garbage.empty() ? RunStatus::Completed : RunStatus::Failed;
    out.message = garbage.empty() ? out.solverWarnings : "completed but wrote garbage: " + garbage;
  } else if (out.message.empty()) {
    out.message = fmt::format("exit code {}", out.exitCode);
  }
  return out;
}

}  // namespace sphfx::study
