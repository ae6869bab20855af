#pragma once
/// @file error.h
/// @brief Typed exceptions of sphfx. Each carries a complete, user-facing message; the CLI maps each type
/// to an exit code (see exitCodeFor()).

#include <stdexcept>
#include <string>

namespace sphfx {

/// Base of every sphfx exception.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad user input: a scene file, an override, a command-line value or a cache that is not what was
/// expected. The message names the file, the JSON path (where there is one) and what was expected.
/// The CLI exits with code 2.
class InputError : public Error {
 public:
  using Error::Error;
};

/// No usable OpenGL context, or a shader that does not compile or link.
class GLError : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A simulation that stopped itself because a health check failed (NaN, escape, density blow-up).
/// The message names the frame, the substep and the cause.
class SimulationError : public Error {
 public:
  using Error::Error;
};

/// Exit code the CLI uses for an exception: 2 for bad input, 3 for a simulation stopped by a health
/// check, 1 for anything else.
int exitCodeFor(const std::exception& e) noexcept;

}  // namespace sphfx
