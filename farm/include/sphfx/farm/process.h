#pragma once
/// @file process.h
/// @brief Running the scheduler's command-line tools (sbatch, squeue, sacct, scancel) without a shell.

#include <string>
#include <vector>

namespace sphfx::farm {

struct ProcessResult {
  int status = -1;  ///< exit status; -1 if the program could not be started or was killed by a signal
  std::string out;  ///< standard output
  std::string err;  ///< standard error
};

/// Absolute path of `program` found on PATH, or empty if it is not there.
std::string findOnPath(const std::string& program);

/// Runs `args[0]` (a path) with `args`, waits, and returns its status and output. Never throws for a
/// failing program; the caller decides what a non-zero status means.
ProcessResult runProcess(const std::vector<std::string>& args);

}  // namespace sphfx::farm
