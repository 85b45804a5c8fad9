#include "huge_pages.hpp"

#include <sys/auxv.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace statepack::packager {
namespace {

constexpr const char* kTunables =
    "glibc.malloc.hugetlb=1:glibc.malloc.top_pad=67108864:glibc.malloc.trim_threshold=1073741824";
// Set for the re-executed process only (and removed by it at once): it never re-executes again, even
// where glibc drops GLIBC_TUNABLES (a setuid start).
constexpr const char* kMarker = "STATEPACK_REEXECUTED";

// Whether the kernel gives huge pages to memory that asks (madvise) or to all: "[never]" says neither.
bool kernel_has_huge_pages() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  return std::getline(in, modes) && modes.find("[never]") == std::string::npos;
}

// Whether /proc/self/exe is the file this code runs from: not when the program was started through the
// dynamic loader (`ld-linux.so statepack ...`), where it is the loader, and executing that with these
// arguments would run something else. The mapping that holds this function names its file's inode.
bool running_from_self_exe() {
  struct stat exe {};
  if (::stat("/proc/self/exe", &exe) != 0) return false;
  std::ifstream maps("/proc/self/maps");
  const auto here = reinterpret_cast<uintptr_t>(&running_from_self_exe);
  for (std::string line; std::getline(maps, line);) {
    unsigned long long from = 0, to = 0, inode = 0;
    char device[32] = {};
    if (std::sscanf(line.c_str(), "%llx-%llx %*s %*s %31s %llu", &from, &to, device, &inode) != 4) continue;
    if (here >= from && here < to) return inode == exe.st_ino;
  }
  return false;
}

}  // namespace

bool was_reexecuted() {
  static const bool reexecuted = [] {
    if (!std::getenv(kMarker)) return false;
    ::unsetenv(kMarker);  // (nothing this process starts inherits it)
    return true;
  }();
  return reexecuted;
}

void use_huge_pages(char** argv) {
  if (was_reexecuted()) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string given = tunables ? tunables : "";
  if (given.find("glibc.malloc.hugetlb") != std::string::npos) return;
  if (const char* preload = std::getenv("LD_PRELOAD"); preload && *preload) return;
  if (getauxval(AT_SECURE) || !running_from_self_exe() || !kernel_has_huge_pages()) return;
  const std::string wanted = given.empty() ? kTunables : given + ":" + kTunables;
  if (::setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0 || ::setenv(kMarker, "1", 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // Not executed (no /proc, a binary replaced under us): go on as we are, and leave the environment as
  // it was for anything this process starts.
  ::unsetenv(kMarker);
  if (tunables)
    ::setenv("GLIBC_TUNABLES", given.c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
}

}  // namespace statepack::packager
