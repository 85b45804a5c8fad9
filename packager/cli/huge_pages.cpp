#include "huge_pages.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace statepack::packager {
namespace {

constexpr const char* kTunables =
    "glibc.malloc.hugetlb=1:glibc.malloc.top_pad=67108864:glibc.malloc.trim_threshold=1073741824";

// Whether the kernel gives huge pages to memory that asks (madvise) or to all: "[never]" says neither.
bool kernel_has_huge_pages() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  return std::getline(in, modes) && modes.find("[never]") == std::string::npos;
}

}  // namespace

void use_huge_pages(char** argv) {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string given = tunables ? tunables : "";
  if (given.find("glibc.malloc.hugetlb") != std::string::npos) return;
  if (const char* preload = std::getenv("LD_PRELOAD"); preload && *preload) return;
  if (!kernel_has_huge_pages()) return;
  const std::string wanted = given.empty() ? kTunables : given + ":" + kTunables;
  if (::setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // Not executed (no /proc, a binary replaced under us): go on as we are, and leave the environment as
  // it was for anything this process starts.
  if (tunables)
    ::setenv("GLIBC_TUNABLES", given.c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
}

}  // namespace statepack::packager
