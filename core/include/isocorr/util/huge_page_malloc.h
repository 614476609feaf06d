// Backs the process's heap with transparent huge pages (2 MiB) instead of 4 KiB pages.
//
// Why: the numerics allocate large, short-lived buffers (a 52K mesh's eigensolver basis is
// 170 MB, its geodesic fields 55 MB, the Lanczos and GEMM temporaries several MB each), and
// the kernel maps new memory one page fault per 4 KiB page. On the virtual machines we run
// on, those faults took 12% of the eigensolver's time. glibc madvises its memory for huge
// pages when GLIBC_TUNABLES says glibc.malloc.hugetlb=1, but reads that only when a process
// starts. Measured on a 2-core VM (kernel THP mode "madvise"): michael0 -> michael1 (52K
// vertices) 22.7 -> 20.4 s, 5K FAUST pairs 2.97-3.08 -> 2.75-2.91 s, 12.5K SCAPE pairs
// 6.1-6.2 -> 5.7 s, identical maps, peak memory +4% at 52K.
#pragma once

#include <string>

namespace isocorr {

// The setting this asks for.
inline constexpr const char* kHugePageMallocTunables = "glibc.malloc.hugetlb=1";

// Called first thing in main: when GLIBC_TUNABLES is unset, sets it to
// kHugePageMallocTunables and executes the program again (same process id, arguments and
// environment otherwise). Returns without doing anything when GLIBC_TUNABLES is set, to any
// value: a user's own tunables are kept, and `GLIBC_TUNABLES= isocorr ...` opts out (e.g.
// under valgrind, which would not follow the exec). Returns, with the variable unset
// again, when the program cannot be executed again (no /proc).
void restart_with_huge_page_malloc(char** argv);

// GLIBC_TUNABLES as this process started with it ("" when unset), for the logs.
std::string malloc_tunables();

}  // namespace isocorr
