#include "geometry/PatchSet.h"

#include <gtest/gtest.h>

#include "RandomNurbs.h"
#include "common/Error.h"

using namespace aero;
using namespace aero::geometry;

TEST(PatchSet, CountsDescribeAndBoundingBox) {
    std::mt19937 rng(1);
    PatchSet set;
    set.source = "wing.igs";
    set.patches = {test::randomSurface(rng, 3, 3, 6, 5, false), test::randomSurface(rng, 2, 1, 3, 2, true)};
    set.names = {"upper", ""};
    EXPECT_EQ(set.controlPointCount(), 36);
    EXPECT_EQ(set.describe(0), "patch 1 ('upper') of 'wing.igs'");
    EXPECT_EQ(set.describe(1), "patch 2 of 'wing.igs'");
    const BoundingBox b = controlBoundingBox(set);
    for (const auto& p : set.patches) {
        for (std::size_t a = 0; a < p.points.size(); ++a) {
            EXPECT_GE(p.points[a], b.min[a % 3]);
            EXPECT_LE(p.points[a], b.max[a % 3]);
        }
    }
    EXPECT_NO_THROW(validate(set));
}

TEST(PatchSet, ValidationNamesTheSourceAndPatch) {
    std::mt19937 rng(2);
    PatchSet set;
    set.source = "bad.json";
    EXPECT_THROW(validate(set), GeometryError);
    set.patches = {test::randomSurface(rng, 3, 3, 4, 4, false), test::randomSurface(rng, 3, 3, 4, 4, false)};
    set.names = {"a", "b"};
    set.patches[1].points[7] = std::nan("");
    try {
        validate(set);
        FAIL();
    } catch (const GeometryError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("patch 2 ('b') of 'bad.json'"), std::string::npos) << m;
        EXPECT_NE(m.find("non-finite"), std::string::npos) << m;
    }
}
