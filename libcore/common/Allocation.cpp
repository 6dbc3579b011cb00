// The executables' allocation policy: large blocks in transparent huge pages, and freed memory
// kept for reuse instead of being handed back to the kernel and faulted in again.
//
// Linked into the executables only (the `aeroform_allocation` object library), never into a
// sanitizer or fuzzing build, whose runtimes replace operator new and malloc themselves.
//
// Why: on a virtual machine every first write to a fresh 4 KB page is a fault the hypervisor has
// to serve (about 4 ms per MB on this project's VMs). Two things made the solvers pay it again
// and again:
//   - glibc serves a block above its mmap threshold (at most 32 MB) with a mapping of its own and
//     unmaps it on free, so a state-sized temporary of a 903k-node flow (36 MB) is faulted in anew
//     every time it is allocated: 13.7 million page faults for a 4.2 GB run. At start-up this file
//     turns malloc's mappings off (M_MMAP_MAX 0) and keeps up to kKeepFreeBytes of freed memory at
//     the top of the heap (M_TRIM_THRESHOLD), so such blocks are reused from the heap.
//   - where the kernel's transparent huge pages are in `madvise` mode (Debian's default), a block
//     the program marks with madvise(MADV_HUGEPAGE) is served in 2 MB pages: 512 times fewer
//     faults. The global operator new marks the 2 MB-aligned inside of every block of at least
//     kAdviseBytes before its first write. (glibc can do this itself with
//     GLIBC_TUNABLES=glibc.malloc.hugetlb=1, but only when set before the program starts.)
// The memory still comes from malloc and is returned by free (the default operator delete), so
// nothing else changes; the advice is a hint the kernel may ignore. The cost: memory freed by the
// solvers stays with the process (up to its peak) until it exits, as in most numerical codes.
// AEROFORM_ALLOCATOR=system in the environment keeps glibc's defaults and gives no advice.
// docs/performance.md has the measurements.
#include <malloc.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#include <sys/mman.h>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kAdviseBytes = 4 * kHugePage;
constexpr int kKeepFreeBytes = 1 << 30;

bool policyWanted() {
    static const bool wanted = [] {
        const char* v = std::getenv("AEROFORM_ALLOCATOR");
        return !(v && std::strcmp(v, "system") == 0);
    }();
    return wanted;
}

// Before main (and before any thread): malloc's own settings.
const bool heapOnly = [] {
    if (!policyWanted()) return false;
    return mallopt(M_MMAP_MAX, 0) == 1 && mallopt(M_TRIM_THRESHOLD, kKeepFreeBytes) == 1;
}();

void adviseHugePages(void* p, std::size_t bytes) {
    if (bytes < kAdviseBytes || !policyWanted()) return;
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + kHugePage - 1) & ~(kHugePage - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHugePage - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint: failure is harmless
}

}  // namespace

namespace aero {
/// Whether the start-up settings above took effect (for the tests).
bool allocationPolicyHeapOnly() { return heapOnly; }
}  // namespace aero

void* operator new(std::size_t bytes) {
    if (bytes == 0) bytes = 1;
    for (;;) {
        if (void* p = std::malloc(bytes)) {
            adviseHugePages(p, bytes);
            return p;
        }
        std::new_handler handler = std::get_new_handler();
        if (!handler) throw std::bad_alloc();
        handler();
    }
}

void* operator new[](std::size_t bytes) { return ::operator new(bytes); }

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
