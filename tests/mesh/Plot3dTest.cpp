#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>

#include "common/Error.h"
#include "mesh/Plot3d.h"

using namespace aero;
using namespace aero::mesh;

namespace {

std::string outPath(const std::string& name) {
    return std::string(AEROFORM_TEST_OUTPUT_DIR) + "/" + name;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void spit(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Two blocks of random coordinates over many magnitudes, plus awkward values.
std::vector<StructuredGrid> sampleBlocks() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    std::uniform_int_distribution<int> E(-30, 30);
    std::vector<StructuredGrid> blocks(2);
    blocks[0].dims = {4, 3, 2};
    blocks[1].dims = {2, 5, 3};
    for (int b = 0; b < 2; ++b) {
        blocks[b].name = "block" + std::to_string(b);
        blocks[b].xyz.resize(3 * static_cast<std::size_t>(blocks[b].nodeCount()));
        for (double& x : blocks[b].xyz) x = std::ldexp(U(rng), E(rng));
    }
    blocks[0].xyz[0] = -0.0;
    blocks[0].xyz[1] = 0.1;
    blocks[0].xyz[2] = 5e-324;  // smallest subnormal
    blocks[1].xyz[0] = 1.7976931348623157e308;
    return blocks;
}

void expectBitwiseEqual(const std::vector<StructuredGrid>& a,
                        const std::vector<StructuredGrid>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].dims, b[k].dims);
        EXPECT_EQ(a[k].name, b[k].name);
        ASSERT_EQ(a[k].xyz.size(), b[k].xyz.size());
        EXPECT_EQ(std::memcmp(a[k].xyz.data(), b[k].xyz.data(), a[k].xyz.size() * sizeof(double)),
                  0)
            << "block " << k;
    }
}

std::string le32(std::uint32_t v) {
    std::string s(4, '\0');
    for (int b = 0; b < 4; ++b) s[b] = static_cast<char>(v >> (8 * b));
    return s;
}

template <class T>
std::string raw(const std::vector<T>& v) {
    std::string s(v.size() * sizeof(T), '\0');
    std::memcpy(s.data(), v.data(), s.size());  // the test host is little-endian
    return s;
}

// Expects readPlot3d(path) to throw InputError whose message contains every fragment.
void expectInputError(const std::string& path, std::initializer_list<std::string> fragments) {
    try {
        readPlot3d(path);
        ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(path), std::string::npos) << m;
        for (const std::string& f : fragments) {
            EXPECT_NE(m.find(f), std::string::npos) << "'" << f << "' in: " << m;
        }
    }
}

}  // namespace

TEST(Plot3d, BinaryRoundTripIsBitwiseAndHasTheStandardLayout) {
    const auto blocks = sampleBlocks();
    const std::string path = outPath("roundtrip.xyz");
    writePlot3d(path, blocks, true);
    const std::string bytes = slurp(path);
    // [4][nb][4] [24][dims x 6][24] [24 N][x y z][24 N] per block.
    const std::size_t expected = 12 + 32 + (8 + 24 * 24) + (8 + 24 * 30);
    ASSERT_EQ(bytes.size(), expected);
    EXPECT_EQ(bytes.substr(0, 12), le32(4) + le32(2) + le32(4));
    EXPECT_EQ(bytes.substr(12, 32),
              le32(24) + le32(4) + le32(3) + le32(2) + le32(2) + le32(5) + le32(3) + le32(24));
    EXPECT_EQ(bytes.substr(44, 4), le32(24 * 24));
    double x1 = 0;  // x of node 1 of block 0 follows x of node 0
    std::memcpy(&x1, bytes.data() + 48 + 8, 8);
    EXPECT_EQ(x1, blocks[0].xyz[3]);

    const auto back = readPlot3d(path);
    expectBitwiseEqual(blocks, back);
    writePlot3d(path, back, true);
    EXPECT_EQ(slurp(path), bytes);
}

TEST(Plot3d, AsciiRoundTripIsExact) {
    const auto blocks = sampleBlocks();
    const std::string path = outPath("roundtrip.p3d");
    writePlot3d(path, blocks, false);
    const std::string text = slurp(path);
    EXPECT_EQ(text.substr(0, 14), "2\n4 3 2\n2 5 3\n");
    expectBitwiseEqual(blocks, readPlot3d(path));
}

TEST(Plot3d, AsciiReaderAcceptsFortranStyles) {
    // Commas, tabs, CRLF, a leading '+', and 'D' exponents; x then y then z, i fastest.
    const std::string path = outPath("fortran.p3d");
    spit(path, " 1\r\n 2,1,1\r\n\t0.0D0, +1.5d+00\r\n 2.5E-1 -3\n 7 8 \n");
    const auto g = readPlot3d(path);
    ASSERT_EQ(g.size(), 1u);
    EXPECT_EQ(g[0].dims, (std::array<int, 3>{2, 1, 1}));
    EXPECT_EQ(g[0].xyz, (std::vector<double>{0.0, 0.25, 7, 1.5, -3, 8}));
}

TEST(Plot3d, BinaryReaderAcceptsFloat32AndIblank) {
    const std::string dims =
        le32(4) + le32(1) + le32(4) + le32(12) + le32(2) + le32(1) + le32(1) + le32(12);
    const std::vector<float> f32{1.5f, 2.5f, -1.0f, 0.25f, 3.0f, 4.0f};
    std::string path = outPath("float32.xyz");
    spit(path, dims + le32(24) + raw(f32) + le32(24));
    auto g = readPlot3d(path);
    ASSERT_EQ(g.size(), 1u);
    EXPECT_EQ(g[0].xyz, (std::vector<double>{1.5, -1.0, 3.0, 2.5, 0.25, 4.0}));

    const std::vector<double> f64{1.5, 2.5, -1.0, 0.25, 3.0, 4.0};
    path = outPath("iblank.xyz");
    spit(path, dims + le32(56) + raw(f64) + le32(1) + le32(0) + le32(56));
    g = readPlot3d(path);
    EXPECT_EQ(g[0].xyz, (std::vector<double>{1.5, -1.0, 3.0, 2.5, 0.25, 4.0}));
}

TEST(Plot3d, MissingAndEmptyFiles) {
    const std::string missing = outPath("no-such-file.xyz");
    std::remove(missing.c_str());
    expectInputError(missing, {"cannot open"});
    const std::string empty = outPath("empty.xyz");
    spit(empty, "");
    expectInputError(empty, {"empty"});
}

TEST(Plot3d, TruncatedFilesNameTheBlockAndTheCounts) {
    const auto blocks = sampleBlocks();
    const std::string good = outPath("good.xyz");
    writePlot3d(good, blocks, true);
    const std::string bytes = slurp(good);
    const std::string path = outPath("truncated.xyz");
    // Cut inside block 1's coordinate record (its payload is 720 bytes).
    spit(path, bytes.substr(0, bytes.size() - 100));
    expectInputError(path, {"truncated", "block 1", "720 bytes", "only 624 bytes remain"});
    // Cut inside the dimensions record.
    spit(path, bytes.substr(0, 20));
    expectInputError(path, {"truncated", "dimensions"});
    // Cut right after block 0.
    spit(path, bytes.substr(0, 12 + 32 + 8 + 24 * 24));
    expectInputError(path, {"truncated", "block 1"});

    const std::string goodText = outPath("good.p3d");
    writePlot3d(goodText, blocks, false);
    std::string text = slurp(goodText);
    // Drop the last 5 values of block 1 (90 coordinates).
    for (int v = 0; v < 5; ++v) {
        while (text.back() == ' ' || text.back() == '\n') text.pop_back();
        text.erase(text.find_last_of(" \n") + 1);
    }
    const std::string pathText = outPath("truncated.p3d");
    spit(pathText, text);
    expectInputError(pathText, {"truncated", "block 1", "expected 3 * 30 = 90", "found 85"});
}

TEST(Plot3d, BadDims) {
    const std::string path = outPath("baddims.p3d");
    spit(path, "2\n2 2 2\n3 0 2\n");
    expectInputError(path, {"block 1", "bad dimension 1 = 0"});
    spit(path, "1\n2 -2 2\n");
    expectInputError(path, {"block 0", "bad dimension 1 = -2"});
    spit(path, "0\n");
    expectInputError(path, {"bad block count 0"});
    spit(path, "1\n1000 1000 1000\n1 2 3\n");
    expectInputError(path, {"block 0", "1000 x 1000 x 1000", "3000000000 coordinates"});
    spit(path, "1\n2 2.5 2\n");
    expectInputError(path, {"block 0 dimension 1", "'2.5' is not an integer"});

    const std::string bin = outPath("baddims.xyz");
    spit(bin, le32(4) + le32(1) + le32(4) + le32(12) + le32(2) + le32(0) + le32(2) + le32(12));
    expectInputError(bin, {"block 0", "bad dims 2 x 0 x 2"});
    spit(bin, le32(4) + le32(0) + le32(4));
    expectInputError(bin, {"bad block count 0"});
    // 2D file: two dims per block.
    spit(bin, le32(4) + le32(1) + le32(4) + le32(8) + le32(2) + le32(2) + le32(8));
    expectInputError(bin, {"dimensions record has 8 bytes", "expected 12 * 1 = 12", "2D"});
    // Coordinate record that does not match the dims.
    spit(bin, le32(4) + le32(1) + le32(4) + le32(12) + le32(2) + le32(1) + le32(1) + le32(12) +
                  le32(40) + std::string(40, '\0') + le32(40));
    expectInputError(bin, {"block 0", "record has 40 bytes", "expected 24 * 2 = 48"});
    // Dims whose product wraps a 64-bit count (16 x 2^30 x 2^30 = 2^64 read as 0 nodes, then a
    // crash in fit; issue #20) and an ASCII dimension beyond an int.
    spit(bin, le32(4) + le32(1) + le32(4) + le32(12) + le32(16) + le32(1u << 30) + le32(1u << 30) + le32(12) + le32(0) + le32(0));
    expectInputError(bin, {"block 0", "16 x 1073741824 x 1073741824", "more than the 10^9 a block may have"});
    spit(path, "1\n16 2000000000 2\n1 2 3\n");
    expectInputError(path, {"block 0", "bad dimension 1 = 2000000000", "[1, 10^9]"});
}

TEST(Plot3d, NonNumericAndNonFiniteData) {
    const std::string path = outPath("nonnumeric.p3d");
    spit(path, "1\n2 1 1\n0 1\n0 abc\n0 0\n");
    expectInputError(path, {"block 0, y coordinate 1", "line 4", "'abc' is not a number"});
    spit(path, "1\n2 1 1\n0 1\n0 1\n0 nan\n");
    expectInputError(path, {"block 0, z coordinate 1", "line 5", "not finite"});
    spit(path, "1\n2 1 1\n0 1\n0 1\n0 1\n2\n");
    expectInputError(path, {"unexpected data after the last block", "line 6"});
    spit(path, "one\n2 1 1\n");
    expectInputError(path, {"block count", "'one' is not an integer"});

    const std::string bin = outPath("nonfinite.xyz");
    const std::vector<double> xyz{0, 1, 0, 1, 0, std::numeric_limits<double>::infinity()};
    spit(bin, le32(4) + le32(1) + le32(4) + le32(12) + le32(2) + le32(1) + le32(1) + le32(12) +
                  le32(48) + raw(xyz) + le32(48));
    expectInputError(bin, {"block 0", "z of node 1", "not finite"});
}

TEST(Plot3d, MismatchedRecordMarkersAndForeignLayouts) {
    const auto blocks = sampleBlocks();
    const std::string good = outPath("good2.xyz");
    writePlot3d(good, blocks, true);
    const std::string bytes = slurp(good);
    const std::string path = outPath("corrupt.xyz");

    std::string b = bytes;
    b.replace(b.size() - 4, 4, le32(719));  // trailing marker of block 1
    spit(path, b);
    expectInputError(path, {"mismatched record markers", "block 1", "leading 720", "trailing 719"});

    b = bytes;
    b.replace(8, 4, le32(5));  // trailing marker of the block count
    spit(path, b);
    expectInputError(path, {"mismatched record markers", "block count", "leading 4", "trailing 5"});

    b = bytes + std::string(3, '\0');
    spit(path, b);
    expectInputError(path, {"3 bytes of trailing data"});

    b = bytes;
    b.replace(0, 4, std::string("\0\0\0\4", 4));  // big-endian marker
    spit(path, b);
    expectInputError(path, {"big-endian"});

    spit(path, le32(12) + le32(2) + le32(2) + le32(2) + le32(12));
    expectInputError(path, {"single-block"});

    spit(path, le32(7) + std::string(20, '\1'));
    expectInputError(path, {"first record marker is 7, expected 4"});
}

TEST(Plot3d, WriterRejectsBadBlocksAndUnwritablePaths) {
    auto blocks = sampleBlocks();
    blocks[1].xyz.pop_back();
    EXPECT_THROW(writePlot3d(outPath("bad.xyz"), blocks, true), GeometryError);
    blocks = sampleBlocks();
    blocks[0].xyz[5] = std::nan("");
    EXPECT_THROW(writePlot3d(outPath("bad.xyz"), blocks, false), GeometryError);
    EXPECT_THROW(writePlot3d(outPath("bad.xyz"), {}, false), GeometryError);
    EXPECT_THROW(writePlot3d(outPath("no-such-dir/grid.xyz"), sampleBlocks(), true), InputError);
}
