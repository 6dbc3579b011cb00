// Restart files, residual history and flow VTK output: exact round trips and clear errors.
#include "io/FlowFiles.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/Error.h"
#include "flow/Outputs.h"

using namespace aero;

namespace {

std::string outPath(const std::string& name) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/flow_files";
    std::filesystem::create_directories(dir);
    return dir + "/" + name;
}

flow::FlowMesh twoBlocks(int n) {
    std::vector<flow::FlowBlock> blocks(2);
    blocks[0].name = "a";
    blocks[0].dims = {n, n + 1, 3};
    blocks[1].name = "b";
    blocks[1].dims = {4, n, 2};
    blocks[1].faces[4].kind = mesh::BoundaryKind::Wall;
    return flow::makeFlowMesh(blocks, {});
}

std::vector<double> someState(const flow::FlowMesh& fm) {
    std::vector<double> q(flow::kVars * fm.nodeCount);
    for (std::size_t i = 0; i < q.size(); ++i) q[i] = 1.0 + 1.0 / (3.0 + static_cast<double>(i % 97));
    return q;
}

void expectInputError(const std::string& path, const flow::FlowMesh& fm, const std::string& fragment) {
    try {
        io::readRestart(path, fm);
        ADD_FAILURE() << "no error, expected: " << fragment;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST(FlowFiles, RestartRoundTripsBitExactly) {
    const flow::FlowMesh fm = twoBlocks(5);
    const std::vector<double> q = someState(fm);
    io::RestartInfo info;
    info.freeStream.mach = 0.3333333333333333;
    info.freeStream.alphaDeg = -1.25;
    info.iterations = 42;
    info.residual = 1.5e-7;
    info.initialResidual = 0.1;
    info.cflBase = 1e5 / 3;
    info.lumping = 6;
    const std::string path = outPath("a.restart");
    io::writeRestart(path, fm, q, info);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    io::RestartInfo back;
    const std::vector<double> r = io::readRestart(path, fm, &back);
    EXPECT_EQ(r, q);
    EXPECT_EQ(back.freeStream.mach, info.freeStream.mach);
    EXPECT_EQ(back.freeStream.alphaDeg, info.freeStream.alphaDeg);
    EXPECT_EQ(back.iterations, 42);
    EXPECT_EQ(back.residual, info.residual);
    EXPECT_EQ(back.initialResidual, info.initialResidual);
    EXPECT_EQ(back.cflBase, info.cflBase);
    EXPECT_EQ(back.lumping, 6.0);
}

TEST(FlowFiles, RestartForAnotherGridOrDamagedIsRejectedWithTheReason) {
    const flow::FlowMesh fm = twoBlocks(5);
    const std::string path = outPath("b.restart");
    io::writeRestart(path, fm, someState(fm), {});
    expectInputError(path, twoBlocks(6), "block 0 ('a') has 5x6x3 nodes in the file, 6x7x3 in this grid");

    const std::string bytes = slurp(path);
    const std::string cut = outPath("cut.restart");
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    expectInputError(cut, fm, "truncated");

    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x10;
    const std::string bad = outPath("flipped.restart");
    std::ofstream(bad, std::ios::binary) << flipped;
    expectInputError(bad, fm, "checksum mismatch");

    const std::string twice = outPath("twice.restart");  // garbage after the checksum was ignored
    std::ofstream(twice, std::ios::binary) << bytes << "extra";
    expectInputError(twice, fm, "data after the checksum");

    const std::string other = outPath("other.restart");
    std::ofstream(other, std::ios::binary) << "{\"format\": \"aeroform.case\"}";
    expectInputError(other, fm, "not an Aeroform restart file");
    expectInputError(outPath("missing.restart"), fm, "cannot open");
}

// Version 2 records every block's grid parameters (what lets another mesh.refine of the same
// analytic grid start from the state); files of version 1 (the fuzz corpus's seed, written by
// the first version of the test above) still read, without them.
TEST(FlowFiles, RestartRecordsTheGridParametersAndVersionOneStillReads) {
    const flow::FlowMesh fm = twoBlocks(5);
    io::RestartInfo info;
    info.iterations = 7;
    for (const flow::FlowBlock& b : fm.blocks) {
        std::array<std::vector<double>, 3> s;
        for (int d = 0; d < 3; ++d) {
            for (int i = 0; i < b.dims[d]; ++i) s[d].push_back(std::pow(static_cast<double>(i) / (b.dims[d] - 1), 1.5));
        }
        info.samples.push_back(s);
        std::array<double, 24> corners{};
        for (int i = 0; i < 24; ++i) corners[i] = 0.5 * i + static_cast<double>(b.offset);
        info.corners.push_back(corners);
    }
    const std::string path = outPath("samples.restart");
    io::writeRestart(path, fm, someState(fm), info);
    const io::RestartContents c = io::readRestartContents(path);
    ASSERT_EQ(c.dims.size(), 2u);
    EXPECT_EQ(c.dims[1], (std::array<int, 3>{4, 5, 2}));
    EXPECT_EQ(c.info.samples, info.samples);
    EXPECT_EQ(c.info.corners, info.corners);
    EXPECT_EQ(c.q, someState(fm));
    EXPECT_EQ(c.info.iterations, 7);
    io::RestartInfo back;
    EXPECT_EQ(io::readRestart(path, fm, &back), someState(fm));
    EXPECT_EQ(back.samples, info.samples);
    // Another grid: the layout check names the block, as for a file without parameters.
    EXPECT_THROW(io::checkRestartLayout(path, c, twoBlocks(6)), InputError);

    // Parameters that do not match the blocks are a caller's error; ones that do not increase
    // (a damaged or forged file whose checksum still holds) are the file's.
    io::RestartInfo wrong = info;
    wrong.samples[1][2].pop_back();
    EXPECT_THROW(io::writeRestart(outPath("wrong.restart"), fm, someState(fm), wrong), Error);
    io::RestartInfo cornerless = info;
    cornerless.corners.clear();
    EXPECT_THROW(io::writeRestart(outPath("wrong.restart"), fm, someState(fm), cornerless), Error);
    io::RestartInfo flat = info;
    flat.samples[0][1][2] = flat.samples[0][1][1];
    const std::string flatPath = outPath("flat.restart");
    io::writeRestart(flatPath, fm, someState(fm), flat);
    try {
        io::readRestartContents(flatPath);
        ADD_FAILURE() << "no error for parameters that do not increase";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("grid parameters of block 0 do not increase along direction 1"), std::string::npos)
            << e.what();
    }

    const std::string v1 = std::string(AEROFORM_TEST_DATA_DIR) + "/../fuzz/corpus/restart/a.restart";
    io::RestartInfo old;
    const std::vector<double> q = io::readRestart(v1, fm, &old);
    EXPECT_EQ(q, someState(fm));
    EXPECT_EQ(old.iterations, 42);
    EXPECT_EQ(old.lumping, 6.0);
    EXPECT_TRUE(old.samples.empty());
    EXPECT_TRUE(old.corners.empty());

    // The corners are those of the nodes at the ends of every block's i, j, k.
    std::vector<double> x(3 * fm.nodeCount);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i);
    const auto corners = io::blockCorners(fm, x);
    ASSERT_EQ(corners.size(), 2u);
    const long last0 = 5 * 6 * 3 - 1, first1 = fm.blocks[1].offset, far1 = first1 + 3;  // block 1: 4x5x2
    EXPECT_EQ(corners[0][0], 0.0);
    EXPECT_EQ(corners[0][21], 3.0 * last0);
    EXPECT_EQ(corners[1][0], 3.0 * first1);
    EXPECT_EQ(corners[1][3], 3.0 * far1);
}

TEST(FlowFiles, ResidualCsvHasOneRowPerIterationContinuingTheCount) {
    std::vector<flow::FlowIteration> h;
    for (int i = 1; i <= 3; ++i) h.push_back({i, 1.0 / i, 0.1 / i, 10.0 * i, 5 * i, 0.01, 0.05, 1.0, false, 0.5 * i, {}});
    const std::string path = outPath("residual.csv");
    io::writeResidualCsv(path, h, 10);
    std::istringstream in(slurp(path));
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(in, line)) lines.push_back(line);
    ASSERT_EQ(lines.size(), 4u);
    EXPECT_EQ(lines[0].rfind("iteration,residual,relative_residual,cfl,", 0), 0u);
    EXPECT_EQ(lines[1].rfind("11,1.0000000000e+00,1.0000000000e-01,", 0), 0u) << lines[1];
    EXPECT_EQ(lines[3].rfind("13,", 0), 0u);
}

TEST(FlowFiles, FlowVtmHasTheFieldsAndTheWallFaces) {
    const flow::FlowMesh fm = twoBlocks(4);
    std::vector<double> x(3 * fm.nodeCount);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.01 * static_cast<double>(i);
    flow::FreeStream fs;
    std::vector<double> q(flow::kVars * fm.nodeCount);
    for (long n = 0; n < fm.nodeCount; ++n) {
        const auto s = fs.state();
        std::copy(s.begin(), s.end(), q.begin() + flow::kVars * n);
    }
    const std::string path = outPath("flow/solution.vtm");
    std::filesystem::remove_all(outPath("flow"));
    io::writeFlowVtm(path, fm, x, q, fs);
    const std::string vtm = slurp(path);
    EXPECT_NE(vtm.find("flow"), std::string::npos);
    EXPECT_NE(vtm.find("wall"), std::string::npos);
    int pieces = 0;
    for (const auto& e : std::filesystem::directory_iterator(outPath("flow/solution"))) {
        ++pieces;
        const std::string vts = slurp(e.path().string());
        for (const char* field : {"\"Cp\"", "\"Mach\"", "\"entropy\""}) {
            EXPECT_NE(vts.find(field), std::string::npos) << e.path() << " lacks " << field;
        }
    }
    EXPECT_EQ(pieces, 3);  // two volume blocks, one wall face
}

// The inverse design's target: one row per wall node, the pressure bit for bit, and a file for
// another grid (or damaged) refused naming the line.
TEST(FlowFiles, WallPressureRoundTripsAndBelongsToItsGrid) {
    const flow::FlowMesh fm = twoBlocks(5);
    std::vector<double> q(flow::kVars * fm.nodeCount);  // physical: positive pressure
    for (long n = 0; n < fm.nodeCount; ++n) {
        const double v[flow::kVars] = {1.0 + 0.001 * static_cast<double>(n % 7), 0.3, 0.01, -0.02, 2.5 + 1.0 / (3.0 + static_cast<double>(n))};
        std::copy(v, v + flow::kVars, q.begin() + flow::kVars * n);
    }
    std::vector<double> x(3 * fm.nodeCount);
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = 0.01 * static_cast<double>(i);
    flow::FreeStream fs;
    const std::string path = outPath("wall_pressure.csv");
    io::writeWallPressureCsv(path, fm, x, q, fs);
    const std::vector<double> p = io::readWallPressureCsv(path, fm);
    const std::vector<flow::WallNode> wall = flow::wallNodes(fm);
    ASSERT_EQ(p.size(), wall.size());
    for (std::size_t k = 0; k < wall.size(); ++k) EXPECT_EQ(p[k], flow::pressure(&q[flow::kVars * wall[k].node], fs.gamma));
    auto refused = [&](const flow::FlowMesh& other, const std::string& file, const std::string& fragment) {
        try {
            (void)io::readWallPressureCsv(file, other);
            ADD_FAILURE() << "accepted: " << fragment;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    refused(twoBlocks(6), path, "another grid");
    std::string text = slurp(path);
    text.replace(text.find('\n', text.find('\n') + 1) + 1, 1, "x");  // damage the second data row
    std::ofstream(outPath("damaged.csv")) << text;
    refused(fm, outPath("damaged.csv"), "line 3");
    refused(fm, outPath("missing.csv"), "cannot read");
}

// Issue #20: an optimization's warm-start state round-trips bit for bit, and a damaged one (its
// count not backed by the file's size, truncated, missing) reads as no state, allocating nothing
// from the count (a count of 2^40 used to be allocated before reading).
TEST(FlowFiles, WarmStateRoundTripsAndADamagedOneIsNoState) {
    const std::vector<double> q = {1.0, -2.5, 3.25e-300, 0.1, 7.0};
    const std::string path = outPath("warm.state");
    io::writeWarmState(path, q);
    EXPECT_EQ(io::readWarmState(path), q);

    const std::string bytes = slurp(path);
    std::string huge = bytes;
    const std::uint64_t n = std::uint64_t(1) << 40;
    std::memcpy(huge.data(), &n, sizeof n);
    std::ofstream(outPath("huge.state"), std::ios::binary) << huge;
    EXPECT_TRUE(io::readWarmState(outPath("huge.state")).empty());
    std::ofstream(outPath("cut.state"), std::ios::binary) << bytes.substr(0, bytes.size() - 3);
    EXPECT_TRUE(io::readWarmState(outPath("cut.state")).empty());
    std::ofstream(outPath("tiny.state"), std::ios::binary) << "abc";
    EXPECT_TRUE(io::readWarmState(outPath("tiny.state")).empty());
    EXPECT_TRUE(io::readWarmState(outPath("missing.state")).empty());
    io::writeWarmState(outPath("empty.state"), {});
    EXPECT_TRUE(io::readWarmState(outPath("empty.state")).empty());
}
