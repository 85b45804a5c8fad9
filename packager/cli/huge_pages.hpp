#pragma once
// A pack's heap on transparent huge pages. Before its first compile, glslang builds the built-in symbol
// tables of every stage (~30 MB in small allocations), once per process; each fresh 4 KiB page then costs
// a page fault, ~15 us on a virtual machine: two thirds of a repack after one shader changed was faults.
// glibc's malloc asks the kernel for 2 MiB pages only when the GLIBC_TUNABLES environment variable says so
// before the process starts (glibc.malloc.hugetlb=1; there is no mallopt for it), so a pack re-executes
// itself once with it set, with a 64 MiB top pad and no trimming so that the heap grows in large steps and
// keeps them (a pack is short-lived; freed memory is reused, and returned at exit).

namespace statepack::packager {

// Re-executes this program (/proc/self/exe, the same arguments) with those tunables added to
// GLIBC_TUNABLES, and returns only when it does not: this process is the re-executed one, GLIBC_TUNABLES
// already names glibc.malloc.hugetlb (a user's choice: =0 keeps 4 KiB pages), LD_PRELOAD is set (a tool
// such as valgrind runs this process and would not follow), the start was a secure one (setuid) or
// through the dynamic loader, the kernel's transparent huge pages are off, or the exec fails.
void use_huge_pages(char** argv);

// Whether this process is the re-execution (asked once; the mark is then removed from the environment).
bool was_reexecuted();

}  // namespace statepack::packager
