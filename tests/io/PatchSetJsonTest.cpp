#include "io/PatchSetJson.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "RandomNurbs.h"
#include "common/Error.h"
#include "geometry/HalfSphere.h"

using namespace aero;

namespace {

void expectIdentical(const geometry::PatchSet& a, const geometry::PatchSet& b) {
    ASSERT_EQ(a.size(), b.size());
    for (int p = 0; p < a.size(); ++p) {
        const auto &x = a.patches[p], &y = b.patches[p];
        EXPECT_EQ(x.degreeU, y.degreeU);
        EXPECT_EQ(x.degreeV, y.degreeV);
        EXPECT_EQ(x.countU, y.countU);
        EXPECT_EQ(x.countV, y.countV);
        EXPECT_EQ(x.knotsU, y.knotsU);  // bit for bit
        EXPECT_EQ(x.knotsV, y.knotsV);
        EXPECT_EQ(x.points, y.points);
        EXPECT_EQ(x.weights, y.weights);
    }
    EXPECT_EQ(a.names, b.names);
}

std::string tempPath(const std::string& name) { return std::string(AEROFORM_TEST_OUTPUT_DIR) + "/" + name; }

void expectInputError(const std::string& text, const std::string& fragment) {
    try {
        io::parsePatchSetJson(text, "case.json");
        ADD_FAILURE() << "no error, expected: " << fragment;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("case.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(PatchSetJson, RoundTripIsExact) {
    std::mt19937 rng(61);
    geometry::PatchSet set;
    for (int p = 0; p < 6; ++p) {
        set.patches.push_back(test::randomSurface(rng, 1 + p % 4, 1 + p % 3, 5 + p, 4 + p, p % 2 == 0));
        set.names.push_back("patch" + std::to_string(p));
    }
    const std::string path = tempPath("roundtrip.json");
    io::writePatchSetJson(set, path);
    expectIdentical(set, io::readPatchSetJson(path));
    expectIdentical(geometry::makeHalfSphere(), io::parsePatchSetJson(io::formatPatchSetJson(geometry::makeHalfSphere()), "x"));
}

// The unit and the trims (loops of parameter-space curves) go out and come back bit for bit.
TEST(PatchSetJson, UnitAndTrimsRoundTripExactly) {
    geometry::PatchSet set = geometry::makeHalfSphere();
    set.unit = "in";
    set.trims.resize(static_cast<std::size_t>(set.size()));
    const geometry::Patch& p = set.patches[3];
    const double u0 = p.knotsU.front(), u1 = p.knotsU.back(), v0 = p.knotsV.front(), v1 = p.knotsV.back();
    set.trims[3].outer = geometry::rectangleLoop(u0 + 0.1 * (u1 - u0), u1, v0, v1 - 1.0 / 3.0 * (v1 - v0));
    geometry::TrimCurve arc = geometry::lineCurve({u0 + 0.4 * (u1 - u0), v0 + 0.3 * (v1 - v0)}, {u0 + 0.6 * (u1 - u0), v0 + 0.3 * (v1 - v0)});
    arc.curve.degree = 2;
    arc.curve.knots = {0, 0, 0, 1, 1, 1};
    arc.curve.points = {arc.curve.points[0], arc.curve.points[1], 0, u0 + 0.5 * (u1 - u0), v0 + 0.5 * (v1 - v0), 0,
                        arc.curve.points[3], arc.curve.points[4], 0};
    arc.curve.weights = {1, std::sqrt(0.5), 1};
    set.trims[7].holes.push_back({{arc, geometry::lineCurve(geometry::endPoint(arc), geometry::startPoint(arc))}});
    geometry::validate(set);
    const geometry::PatchSet back = io::parsePatchSetJson(io::formatPatchSetJson(set), "trims.json");
    expectIdentical(set, back);
    EXPECT_EQ(back.unit, "in");
    ASSERT_EQ(back.trims.size(), set.trims.size());
    EXPECT_EQ(back.trimmedCount(), 2);
    for (int k : {3, 7}) {
        const auto& a = set.trims[static_cast<std::size_t>(k)];
        const auto& b = back.trims[static_cast<std::size_t>(k)];
        ASSERT_EQ(a.outer.curves.size(), b.outer.curves.size());
        ASSERT_EQ(a.holes.size(), b.holes.size());
        std::vector<const geometry::TrimLoop*> la{&a.outer}, lb{&b.outer};
        for (std::size_t h = 0; h < a.holes.size(); ++h) {
            la.push_back(&a.holes[h]);
            lb.push_back(&b.holes[h]);
        }
        for (std::size_t l = 0; l < la.size(); ++l)
            for (std::size_t c = 0; c < la[l]->curves.size(); ++c) {
                const auto &x = la[l]->curves[c], &y = lb[l]->curves[c];
                EXPECT_EQ(x.curve.points, y.curve.points);
                EXPECT_EQ(x.curve.knots, y.curve.knots);
                EXPECT_EQ(x.curve.weights, y.curve.weights);
                EXPECT_EQ(x.first, y.first);
                EXPECT_EQ(x.last, y.last);
            }
    }
    // A set without trims or unit writes neither key (files of earlier versions stay the same).
    const std::string plain = io::formatPatchSetJson(geometry::makeHalfSphere());
    EXPECT_EQ(plain.find("\"trim\""), std::string::npos);
    EXPECT_EQ(plain.find("\"unit\""), std::string::npos);
}

TEST(PatchSetJson, BadTrimsAndUnitsNameFileAndKey) {
    const std::string good = io::formatPatchSetJson(geometry::makeHalfSphere());
    auto with = [&](const std::string& patchKey) {
        std::string t = good;
        t.insert(t.find("\"name\""), patchKey + ", ");
        return t;
    };
    expectInputError(with(R"("trim": {"outer": [{"degree": 1, "knots": [0, 0, 1, 1], "points": [[0, 0], [1, 1]], "range": [0, 1]}]})"),
                     "outer trim loop: not closed");
    expectInputError(with(R"("trim": {"inner": []})"), "patches[0].trim: unknown key 'inner'");
    expectInputError(with(R"("trim": {"holes": [[{"degree": 1, "knots": [0, 0, 1, 1], "points": [[0, 0, 0], [1, 1]], "range": [0, 1]}]]})"),
                     "patches[0].trim.holes[0][0].points[0]: expected [u, v]");
    std::string unit = good;
    unit.insert(unit.find("\"patches\""), "\"unit\": \"furlong\", ");
    expectInputError(unit, "unknown length unit 'furlong'");
}

TEST(PatchSetJson, BadInputNamesFileAndKey) {
    const std::string good = io::formatPatchSetJson(geometry::makeHalfSphere());
    expectInputError("{ not json", "not valid JSON");
    // Found by fuzz_patchset_json (tests/fuzz): a number out of double's range escaped as
    // nlohmann::json's out_of_range instead of an InputError.
    expectInputError(R"({"format": "aeroform.patchset", "version": 1, "patches": [1E400]})",
                     "not valid JSON");
    expectInputError("[1, 2]", "expected a JSON object");
    expectInputError(R"({"format": "aeroform.patchset", "version": 1})", "missing key 'patches'");
    expectInputError(R"({"format": "something", "version": 1, "patches": []})", "format");
    expectInputError(R"({"format": "aeroform.patchset", "version": 7, "patches": []})", "unsupported version");
    expectInputError(R"({"format": "aeroform.patchset", "version": 1, "patches": [], "extra": 1})", "unknown key 'extra'");
    expectInputError(R"({"format": "aeroform.patchset", "version": 1, "patches": []})", "no patches");
    const std::string patchHead = R"({"format": "aeroform.patchset", "version": 1, "patches": [{"name": "w", "degree": [1, 1], "count": [2, 2], )";
    expectInputError(patchHead + R"("knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[1,0,0],[0,1,0],["a",1,0]]}]})",
                     "patches[0].points[3][0]");
    expectInputError(patchHead + R"("knots_u": [0, 1, 0, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}]})",
                     "decreases");
    expectInputError(patchHead + R"("knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,null]]}]})",
                     "expected a number");
    expectInputError(patchHead + R"("knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[1,0,0],[0,1,0]]}]})",
                     "expected 12");
    expectInputError(patchHead + R"("knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "colour": 3, "points": []}]})",
                     "unknown key 'colour'");
    // Counts of 2^32 + k were read as k; a huge product overflowed an int (issue #20).
    const std::string head = R"({"format": "aeroform.patchset", "version": 1, "patches": [{"degree": [3, 3], )";
    expectInputError(head + R"("count": [4294967300, 4], "knots_u": [0,0,0,0,1,1,1,1], "knots_v": [0,0,0,0,1,1,1,1], "points": []}]})",
                     "patches[0].count: value 4294967300 out of range");
    expectInputError(head + R"("count": [65536, 65536], "knots_u": [0,0,0,0,1,1,1,1], "knots_v": [0,0,0,0,1,1,1,1], "points": []}]})",
                     "more than the 10 million a patch may have");
    try {
        io::readPatchSetJson(tempPath("does-not-exist.json"));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("does-not-exist.json"), std::string::npos);
    }
}

TEST(PatchSetJson, FailedWriteLeavesTheExistingFileIntact) {
    const std::string path = tempPath("keep.json");
    io::writePatchSetJson(geometry::makeHalfSphere(), path);
    EXPECT_THROW(io::writePatchSetJson(geometry::makeHalfSphere(), tempPath("no-such-dir/x.json")), InputError);
    EXPECT_EQ(io::readPatchSetJson(path).size(), 20);
}
