// The shot manifest under many processes at once (farm tasks of different chunks on a shared shot):
// WRITERS processes each apply UPDATES read-modify-write updates through sphfx::updateManifest (a shared
// counter and a per-writer counter) while a reader process parses SHOT/manifest.json as fast as it can.
// Passes when no update is lost (counter == WRITERS * UPDATES, each writer's == UPDATES) and the reader
// never saw a file that is not valid JSON. Without the lock, concurrent read-modify-writes lose updates.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/manifest.h"

namespace fs = std::filesystem;

namespace {

int writer(const std::string& shot, int id, int updates) {
  for (int i = 0; i < updates; ++i)
    sphfx::updateManifest(shot, [&](sphfx::ManifestJson& m) {
      m["counter"] = m.value("counter", 0) + 1;
      if (!m.contains("writers")) m["writers"] = sphfx::ManifestJson::object();
      m["writers"][std::to_string(id)] = m["writers"].value(std::to_string(id), 0) + 1;
    });
  return 0;
}

/// Parses the manifest until `stopFile` exists; returns the number of invalid reads (0 expected).
int reader(const std::string& shot, const std::string& stopFile) {
  int reads = 0;
  while (!fs::exists(stopFile)) {
    std::string text;
    try {
      text = sphfx::readTextFile(sphfx::manifestPath(shot));
    } catch (const std::exception&) {
      continue;  // not written yet
    }
    if (!sphfx::ManifestJson::accept(text)) {
      std::fprintf(stderr, "reader: invalid JSON after %d reads (%zu bytes)\n", reads, text.size());
      return 1;
    }
    ++reads;
  }
  std::printf("reader: %d valid reads\n", reads);
  return reads > 0 ? 0 : 1;
}

pid_t spawn(const std::function<int()>& body) {
  const pid_t pid = fork();
  if (pid == 0) {
    int code = 1;
    try {
      code = body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "child: %s\n", e.what());
    }
    std::fflush(stdout);
    std::_Exit(code);
  }
  return pid;
}

bool exitedCleanly(pid_t pid) {
  int status = 0;
  return waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s SHOT WRITERS UPDATES\n", argv[0]);
    return 2;
  }
  const std::string shot = argv[1];
  const int writers = std::atoi(argv[2]), updates = std::atoi(argv[3]);
  fs::remove_all(shot);
  fs::create_directories(shot);
  const std::string stop = shot + "/stop";
  const pid_t readerPid = spawn([&] { return reader(shot, stop); });
  std::vector<pid_t> pids;
  for (int w = 0; w < writers; ++w) pids.push_back(spawn([&, w] { return writer(shot, w, updates); }));
  bool ok = true;
  for (pid_t p : pids) ok = exitedCleanly(p) && ok;
  sphfx::writeTextAtomically(stop, "");
  if (!exitedCleanly(readerPid)) {
    std::fprintf(stderr, "FAIL: the reader saw an invalid manifest (or none at all)\n");
    ok = false;
  }
  const sphfx::ManifestJson m = sphfx::readManifest(shot);
  const int counter = m.value("counter", 0);
  std::printf("counter %d, expected %d\n", counter, writers * updates);
  if (counter != writers * updates) ok = false;
  for (int w = 0; w < writers; ++w) {
    const int n = m.contains("writers") ? m["writers"].value(std::to_string(w), 0) : 0;
    if (n != updates) {
      std::fprintf(stderr, "FAIL: writer %d has %d updates, expected %d\n", w, n, updates);
      ok = false;
    }
  }
  std::printf("%s\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}
