// Geometry blocks for ParaView: trimmed sets carry an "inside_trim" point field.
#include <gtest/gtest.h>

#include "io/GeometryVtk.h"

using namespace aero;

TEST(GeometryVtk, TrimmedPatchesMarkTheirInside) {
    geometry::Patch p;
    p.degreeU = p.degreeV = 1;
    p.countU = p.countV = 2;
    p.knotsU = p.knotsV = {0, 0, 1, 1};
    p.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    geometry::PatchSet set;
    set.patches = {p, p};
    set.trims.resize(2);
    set.trims[1].outer = geometry::rectangleLoop(0.0, 0.5, 0.0, 1.0);  // the left half
    const auto groups = io::geometryBlocks(set, nullptr, {}, nullptr, 5);
    ASSERT_GE(groups.size(), 1u);
    ASSERT_EQ(groups[0].blocks.size(), 2u);
    for (int b = 0; b < 2; ++b) {
        ASSERT_EQ(groups[0].blocks[b].pointData.size(), 1u);
        EXPECT_EQ(groups[0].blocks[b].pointData[0].name, "inside_trim");
    }
    const auto& whole = groups[0].blocks[0].pointData[0].values;
    const auto& half = groups[0].blocks[1].pointData[0].values;
    ASSERT_EQ(half.size(), 25u);
    for (int j = 1; j < 4; ++j) {  // (rows on the loop's own edges may go either way)
        EXPECT_EQ(whole[static_cast<std::size_t>(1 + 5 * j)], 1.0);
        EXPECT_EQ(half[static_cast<std::size_t>(1 + 5 * j)], 1.0);  // u = 0.25: inside
        EXPECT_EQ(half[static_cast<std::size_t>(3 + 5 * j)], 0.0);  // u = 0.75: outside
    }
    // An untrimmed set has no such field.
    set.trims.clear();
    EXPECT_TRUE(io::geometryBlocks(set, nullptr, {}, nullptr, 5)[0].blocks[0].pointData.empty());
}
