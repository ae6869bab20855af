#pragma once
/// @file huge_pages.h
/// @brief Start-up step of the sphfx programs: glibc's malloc on transparent huge pages.
///
/// A 1M-particle frame touches about 220 MiB of fresh memory (OpenVDB leaves and their filter buffers,
/// the particle arrays, the mesh); on 4 KiB pages that is ~60,000 page faults, about a sixth of the
/// surfacing stage's CPU time on the reference machine (docs/performance.md, "Surfacing"). Where the
/// kernel gives huge pages only on request (THP mode "madvise", the Debian default), glibc >= 2.35 asks
/// for them when started with GLIBC_TUNABLES=glibc.malloc.hugetlb=1, a setting read only at process
/// start, so the program runs itself again once with it.

namespace sphfx {

/// If this is glibc, the kernel's THP mode is "madvise", GLIBC_TUNABLES does not mention
/// glibc.malloc.hugetlb yet (a user's own choice, 0 included, is kept) and SPHFX_HUGE_PAGES is not 0,
/// replaces the process by `/proc/self/exe argv` with the tunable added. Returns (and the program goes
/// on as it is) when any of these does not hold or the exec fails. Call first thing in main().
void reexecWithHugePageMalloc(char** argv);

}  // namespace sphfx
