// The program's global operator new, with transparent huge pages for large blocks.
//
// Linked into the executables only (the `aeroform_huge_pages` object library), never into a
// sanitizer or fuzzing build, whose runtimes replace operator new themselves.
//
// Why: the solvers' large arrays (Krylov bases, ILU factors, Jacobians, stiffness matrices; tens
// to thousands of MB) are written once after they are allocated, and on a virtual machine every
// first write to a fresh 4 KB page is a fault the hypervisor has to serve. Where the kernel's
// transparent huge pages are in `madvise` mode (Debian's default), a block the program marks
// with madvise(MADV_HUGEPAGE) is served in 2 MB pages instead: 512 times fewer faults and TLB
// entries. glibc can do this for every allocation (GLIBC_TUNABLES=glibc.malloc.hugetlb=1), but
// only when the variable is set before the program starts; this does it for large blocks
// whatever the environment. docs/performance.md has the measurements.
//
// The memory still comes from malloc and is returned by free (the default operator delete), so
// nothing else changes: the advice is a hint the kernel may ignore (THP `never`, or no free huge
// page), and only the 2 MB-aligned inside of a block of at least kAdviseBytes is marked.
// AEROFORM_HUGE_PAGES=0 in the environment turns the advice off.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#include <sys/mman.h>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kAdviseBytes = 4 * kHugePage;

bool adviceWanted() {
    static const bool wanted = [] {
        const char* v = std::getenv("AEROFORM_HUGE_PAGES");
        return !(v && std::strcmp(v, "0") == 0);
    }();
    return wanted;
}

void adviseHugePages(void* p, std::size_t bytes) {
    if (bytes < kAdviseBytes || !adviceWanted()) return;
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + kHugePage - 1) & ~(kHugePage - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHugePage - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint: failure is harmless
}

}  // namespace

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
