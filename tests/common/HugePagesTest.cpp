// The executables' operator new (libcore/common/HugePages.cpp): a large block is marked for
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

// The VmFlags of the mapping of /proc/self/smaps that holds `address` ("" when none does).
std::string vmFlagsAt(const void* address) {
    const auto a = reinterpret_cast<std::uintptr_t>(address);
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        unsigned long long lo = 0, hi = 0;
        if (std::sscanf(line.c_str(), "%llx-%llx ", &lo, &hi) == 2 && line.find(':') > line.find(' ')) {
            inside = a >= lo && a < hi;
        } else if (inside && line.rfind("VmFlags:", 0) == 0) {
            return line;
        }
    }
    return "";
}

bool hasFlag(const std::string& vmFlags, const std::string& flag) {
    std::istringstream in(vmFlags);
    std::string word;
    while (in >> word)
        if (word == flag) return true;
    return false;
}

}  // namespace

TEST(HugePages, LargeBlocksAreMarkedForTransparentHugePagesBeforeTheirFirstWrite) {
#ifndef AEROFORM_HUGE_PAGES_NEW
    GTEST_SKIP() << "this build keeps its runtime's operator new (a sanitizer build)";
#else
    if (const char* v = std::getenv("AEROFORM_HUGE_PAGES"); v && std::string(v) == "0")
        GTEST_SKIP() << "AEROFORM_HUGE_PAGES=0 turns the advice off";
    if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"))
        GTEST_SKIP() << "the kernel has no transparent huge pages";
    // 32 MB: the inside of the block, 2 MB-aligned, is marked ("hg" in the mapping's VmFlags).
    const std::size_t n = std::size_t{4} << 20;
    auto big = std::make_unique<double[]>(n);
    for (std::size_t i = 0; i < n; i += 512) big[i] = static_cast<double>(i);
    const std::string flags = vmFlagsAt(big.get() + n / 2);
    ASSERT_FALSE(flags.empty()) << "no mapping of /proc/self/smaps holds the block";
    EXPECT_TRUE(hasFlag(flags, "hg")) << flags;
    for (std::size_t i = 0; i < n; i += 512) ASSERT_EQ(big[i], static_cast<double>(i));
    // A vector's storage goes through the same operator new.
    std::vector<float> vec(std::size_t{8} << 20, 1.0f);
    EXPECT_TRUE(hasFlag(vmFlagsAt(vec.data() + vec.size() / 2), "hg"));
#endif
}
