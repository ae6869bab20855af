// sphfx: the command-line front end. Thin: it parses options and calls the stage libraries.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "commands.h"
#include "sphfx/core/error.h"
#include "sphfx/core/huge_pages.h"
#include "sphfx/core/log.h"

int main(int argc, char** argv) {
  sphfx::reexecWithHugePageMalloc(argv);  // before anything allocates much
  CLI::App app{"sphfx: offline GPU SPH fluid pipeline (simulate -> surface -> render)", "sphfx"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sphfx 0.1.0");
  bool verbose = false, quiet = false;
  app.add_flag("-v,--verbose", verbose, "More log output");
  app.add_flag("-q,--quiet", quiet, "Errors only");
  app.parse_complete_callback([&] {
    sphfx::setLogLevel(quiet     ? sphfx::LogLevel::Quiet
                       : verbose ? sphfx::LogLevel::Verbose
                                 : sphfx::LogLevel::Info);
  });

  sphfx::cli::addInfoCommand(app);
  sphfx::cli::addSceneCommand(app);
  sphfx::cli::addSimulateCommand(app);
  sphfx::cli::addStudyCommand(app);
  sphfx::cli::addStabilityCommand(app);
  sphfx::cli::addSurfaceCommand(app);
  sphfx::cli::addRenderCommand(app);
  sphfx::cli::addRunCommand(app);
  sphfx::cli::addInspectCommand(app);
  sphfx::cli::addFarmCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version exit 0; a malformed command line is bad input (2).
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sphfx: error: %s\n", e.what());
    return sphfx::exitCodeFor(e);
  }
  return 0;
}
