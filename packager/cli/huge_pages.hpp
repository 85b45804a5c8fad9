#pragma once
// A pack's heap on transparent huge pages. Before its first compile, glslang builds the built-in symbol
// tables of every stage (~30 MB in small allocations), once per process; each fresh 4 KiB page then costs
// a page fault, ~15 us on a virtual machine: two thirds of a repack after one shader changed was faults.
//
// glibc's malloc madvises its heaps for huge pages only when GLIBC_TUNABLES says so before the process
// starts (glibc.malloc.hugetlb=1; there is no mallopt for it). Until 0.5.3 the pack re-executed itself
// with it set, but a second start of this program (its code faulted in again, the cache and stamps read
// again) cost a third of such a repack. So the pack asks itself, in-process: a 64 MiB top pad and no
// trimming (mallopt), the main heap grown by that pad at once and advised (MADV_HUGEPAGE), and a few
// thread heaps ("arenas") made by short-lived threads, advised, and left on glibc's free list, where the
// pack's own threads take them. What is advised is found in /proc/self/maps (the mapping holding a block
// just allocated), never from glibc's internal layout; anything not found is left on 4 KiB pages, which
// only costs time.

#include <cstddef>

namespace statepack::packager {

// Does the above for a process that will run up to `threads` threads at once, and returns how many heaps
// it advised (0: none). Nothing at all is done when GLIBC_TUNABLES names glibc.malloc.hugetlb (a user's
// choice: =0 keeps 4 KiB pages; =1 has glibc do it), when LD_PRELOAD is set (another allocator or a tool
// such as valgrind), in a build with a sanitizer (its own allocator), when the kernel's transparent huge
// pages are off, or when /proc/self/maps cannot be read. Once per process, before the pack's own threads
// start.
size_t use_huge_pages(size_t threads);

}  // namespace statepack::packager
