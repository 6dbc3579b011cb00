// The executables' operator new (libcore/common/Allocation.cpp): a large block is marked for
// transparent huge pages before its first write.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

// The header line and the VmFlags line of the mapping of /proc/self/smaps that holds `address`
// (empty when none does).
struct Mapping {
    std::string header, flags;
};
Mapping mappingAt(const void* address) {
    const auto a = reinterpret_cast<std::uintptr_t>(address);
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    Mapping m;
    bool inside = false;
    while (std::getline(smaps, line)) {
        unsigned long long lo = 0, hi = 0;
        if (std::sscanf(line.c_str(), "%llx-%llx ", &lo, &hi) == 2 && line.find(':') > line.find(' ')) {
            inside = a >= lo && a < hi;
            if (inside) m.header = line;
        } else if (inside && line.rfind("VmFlags:", 0) == 0) {
            m.flags = line;
            return m;
        }
    }
    return {};
}

bool hasFlag(const std::string& vmFlags, const std::string& flag) {
    std::istringstream in(vmFlags);
    std::string word;
    while (in >> word)
        if (word == flag) return true;
    return false;
}

}  // namespace

namespace aero {
bool allocationPolicyHeapOnly();
}

TEST(Allocation, LargeBlocksComeFromTheHeapInTransparentHugePages) {
#ifndef AEROFORM_ALLOCATION_POLICY
    GTEST_SKIP() << "this build keeps its runtime's operator new and malloc (a sanitizer build)";
#else
    if (const char* v = std::getenv("AEROFORM_ALLOCATOR"); v && std::string(v) == "system")
        GTEST_SKIP() << "AEROFORM_ALLOCATOR=system keeps glibc's defaults";
    ASSERT_TRUE(aero::allocationPolicyHeapOnly()) << "mallopt refused the settings";
    // 48 MB, above the largest mmap threshold glibc allows (32 MB): from the heap all the same.
    {
        auto block = std::make_unique<char[]>(std::size_t{48} << 20);
        block[0] = 1;
        const Mapping m = mappingAt(block.get() + (std::size_t{24} << 20));
        EXPECT_NE(m.header.find("[heap]"), std::string::npos) << m.header;
    }
    if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"))
        GTEST_SKIP() << "the kernel has no transparent huge pages";
    // 32 MB: the inside of the block, 2 MB-aligned, is marked ("hg" in the mapping's VmFlags).
    const std::size_t n = std::size_t{4} << 20;
    auto big = std::make_unique<double[]>(n);
    for (std::size_t i = 0; i < n; i += 512) big[i] = static_cast<double>(i);
    const std::string flags = mappingAt(big.get() + n / 2).flags;
    ASSERT_FALSE(flags.empty()) << "no mapping of /proc/self/smaps holds the block";
    EXPECT_TRUE(hasFlag(flags, "hg")) << flags;
    for (std::size_t i = 0; i < n; i += 512) ASSERT_EQ(big[i], static_cast<double>(i));
    // A vector's storage goes through the same operator new.
    std::vector<float> vec(std::size_t{8} << 20, 1.0f);
    EXPECT_TRUE(hasFlag(mappingAt(vec.data() + vec.size() / 2).flags, "hg"));
#endif
}
