#include "isocorr/util/huge_page_malloc.h"

#include <unistd.h>

#include <cstdlib>

namespace isocorr {

void restart_with_huge_page_malloc(char** argv) {
  if (std::getenv("GLIBC_TUNABLES") != nullptr) return;
  if (setenv("GLIBC_TUNABLES", kHugePageMallocTunables, 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GLIBC_TUNABLES");  // still this image: run on without the setting
}

std::string malloc_tunables() {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  return tunables ? tunables : "";
}

}  // namespace isocorr
