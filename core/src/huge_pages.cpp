#include "sphfx/core/huge_pages.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace sphfx {
namespace {

constexpr const char* kTunable = "glibc.malloc.hugetlb";

bool kernelHugePagesOnRequest() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::stringstream mode;
  mode << in.rdbuf();
  return mode.str().find("[madvise]") != std::string::npos;
}

}  // namespace

void reexecWithHugePageMalloc(char** argv) {
#ifdef __GLIBC__
  const char* off = std::getenv("SPHFX_HUGE_PAGES");
  if (off && std::string(off) == "0") return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::string value = tunables ? tunables : "";
  if (value.find(kTunable) != std::string::npos || !kernelHugePagesOnRequest()) return;
  value += (value.empty() ? "" : ":") + std::string(kTunable) + "=1";
  if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // Exec failed (no /proc, say): go on with the malloc we have; the setting stays in the environment
  // so that no child tries again.
#else
  (void)argv;
#endif
}

}  // namespace sphfx
