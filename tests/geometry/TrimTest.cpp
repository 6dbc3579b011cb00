// Trimming loops in parameter space (geometry/Trim.h), length units (geometry/Units.h) and the
// watertightness of trimmed sets (geometry/Topology.h boundaryGaps).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/Error.h"
#include "geometry/EnclosedVolume.h"
#include "geometry/PatchSet.h"
#include "geometry/Topology.h"
#include "geometry/Trim.h"
#include "geometry/Units.h"

using namespace aero;
using namespace aero::geometry;

namespace {

/// A bilinear patch: the plane z = 0 over [x0, x1] x [0, 1], parameters (u, v) in [0, 1]^2.
Patch plane(double x0, double x1) {
    Patch p;
    p.degreeU = p.degreeV = 1;
    p.countU = p.countV = 2;
    p.knotsU = p.knotsV = {0, 0, 1, 1};
    p.points = {x0, 0, 0, x1, 0, 0, x0, 1, 0, x1, 1, 0};
    return p;
}

/// A circle of radius r about c in parameter space as one rational quadratic curve (4 quarters).
TrimCurve circle(Point2 c, double r) {
    TrimCurve t;
    t.curve.degree = 2;
    t.curve.knots = {0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4};
    const double w = std::sqrt(0.5);
    const double px[] = {1, 1, 0, -1, -1, -1, 0, 1, 1}, py[] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    for (int k = 0; k < 9; ++k) {
        t.curve.points.insert(t.curve.points.end(), {c[0] + r * px[k], c[1] + r * py[k], 0.0});
        t.curve.weights.push_back(k % 2 ? w : 1.0);
    }
    t.first = 0;
    t.last = 4;
    return t;
}

}  // namespace

TEST(Trim, ReversingIsExactAndTraversesTheOtherWay) {
    TrimCurve c = circle({0.4, 0.6}, 0.25);
    c.first = 0.5;
    c.last = 3.25;
    const TrimCurve r = reversed(c);
    EXPECT_EQ(r.first, -3.25);
    EXPECT_EQ(r.last, -0.5);
    for (const auto& [a, b] :
         {std::pair{startPoint(r), endPoint(c)}, std::pair{endPoint(r), startPoint(c)}}) {
        EXPECT_NEAR(a[0], b[0], 1e-15);
        EXPECT_NEAR(a[1], b[1], 1e-15);
    }
    EXPECT_EQ(reversed(r).curve.points, c.curve.points);  // twice: bit for bit the original
    EXPECT_EQ(reversed(r).curve.knots, c.curve.knots);
    EXPECT_EQ(reversed(r).curve.weights, c.curve.weights);
    for (double t : {0.7, 1.5, 2.9}) {
        const Point2 a = evaluate(c, t), b = evaluate(r, -t);
        EXPECT_NEAR(a[0], b[0], 1e-15);
        EXPECT_NEAR(a[1], b[1], 1e-15);
    }
}

TEST(Trim, AreasOrientationAndContainment) {
    const Patch p = plane(0, 1);
    PatchTrim trim;
    trim.outer = rectangleLoop(0.1, 0.9, 0.2, 0.8);
    trim.holes.push_back({{reversed(circle({0.5, 0.5}, 0.2))}});
    EXPECT_NO_THROW(validate(trim, p, "patch 1"));
    EXPECT_DOUBLE_EQ(signedArea(trim.outer), 0.8 * 0.6);                      // counter-clockwise
    EXPECT_NEAR(signedArea(trim.holes[0]), -std::numbers::pi * 0.04, 1e-15);  // clockwise
    const TrimPolygons poly = polygonize(trim, p);
    EXPECT_GT(signedArea(poly.loops[0]), 0);
    EXPECT_TRUE(contains(poly, 0.15, 0.5));
    EXPECT_FALSE(contains(poly, 0.5, 0.5));   // in the hole
    EXPECT_FALSE(contains(poly, 0.05, 0.5));  // outside the outer loop
    EXPECT_TRUE(contains(poly, 0.8, 0.75));
    // Holes without an outer loop cut the whole rectangle.
    PatchTrim holeOnly;
    holeOnly.holes = trim.holes;
    const TrimPolygons h = polygonize(holeOnly, p);
    EXPECT_TRUE(contains(h, 0.02, 0.02));
    EXPECT_FALSE(contains(h, 0.5, 0.5));
}

TEST(Trim, ValidationNamesThePatchAndTheLoop) {
    const Patch p = plane(0, 1);
    auto message = [&](const PatchTrim& t) {
        try {
            validate(t, p, "patch 3 of 'f.igs'");
        } catch (const GeometryError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    PatchTrim open;
    open.outer = rectangleLoop(0.1, 0.9, 0.2, 0.8);
    open.outer.curves.pop_back();
    EXPECT_NE(message(open).find("patch 3 of 'f.igs', outer trim loop: not closed"),
              std::string::npos)
        << message(open);
    PatchTrim outside;
    outside.holes.push_back(rectangleLoop(0.5, 1.2, 0.2, 0.8));
    EXPECT_NE(message(outside).find("trim hole 1: leaves the patch's parameter rectangle"),
              std::string::npos)
        << message(outside);
    PatchTrim lifted;
    lifted.outer = rectangleLoop(0.1, 0.9, 0.2, 0.8);
    lifted.outer.curves[2].curve.points[2] = 0.5;
    EXPECT_NE(
        message(lifted).find("outer trim loop curve 3: control point 0 has a third coordinate"),
        std::string::npos)
        << message(lifted);
    PatchTrim range;
    range.outer = rectangleLoop(0.1, 0.9, 0.2, 0.8);
    range.outer.curves[0].last = 2.0;
    EXPECT_NE(message(range).find("curve 1: range [0, 2] is empty or outside the curve's knots"),
              std::string::npos)
        << message(range);
    // In a set: the set names the patch; the mesh and the volume refuse trimmed patches by name.
    PatchSet set;
    set.source = "f.igs";
    set.patches = {plane(0, 1), plane(1, 2)};
    set.names = {"left", "right"};
    set.trims.resize(2);
    set.trims[1].outer = rectangleLoop(0.1, 0.9, 0.2, 0.8);
    EXPECT_NO_THROW(validate(set));
    EXPECT_EQ(set.trimmedCount(), 1);
    try {
        enclosedVolume(set);
        FAIL();
    } catch (const GeometryError& e) {
        EXPECT_STREQ(
            e.what(),
            "the enclosed volume needs untrimmed patches: patch 2 ('right') of 'f.igs' is trimmed");
    }
    set.trims.pop_back();
    EXPECT_THROW(validate(set), GeometryError);  // one trim for two patches
}

TEST(Trim, TrimmedBoundingBoxAndBoundaryGaps) {
    // A disc (plane trimmed to a circle) and the plane next to it with the same circle as a hole:
    // their untrimmed edges overlap everywhere, their trimmed boundaries coincide.
    PatchSet set;
    set.patches = {plane(0, 1), plane(0, 1)};
    set.trims.resize(2);
    set.trims[0].outer.curves = {circle({0.5, 0.5}, 0.3)};
    set.trims[1].holes.push_back({{reversed(circle({0.5, 0.5}, 0.3))}});
    validate(set);
    const BoundingBox disc =
        surfaceBoundingBox(PatchSet{{set.patches[0]}, {}, {}, {set.trims[0]}, {}});
    EXPECT_NEAR(disc.min[0], 0.2, 1e-12);
    EXPECT_NEAR(disc.max[0], 0.8, 1e-12);
    const BoundaryGaps gaps = boundaryGaps(set);
    EXPECT_EQ(gaps.pieces, 6);   // the disc's circle, the hole's circle, the plane's 4 edges
    EXPECT_EQ(gaps.matched, 2);  // the two circles
    EXPECT_EQ(gaps.free, 4);
    EXPECT_LT(gaps.maxGap, 1e-14);
    // Shrink the disc: the gap is measured.
    set.trims[0].outer.curves = {circle({0.5, 0.5}, 0.299)};
    EXPECT_NEAR(boundaryGaps(set).maxGap, 0.001, 1e-12);
}

TEST(Units, FactorsAreExactAndConversionIsExplicit) {
    const LengthUnit* in = findLengthUnit("INCH");
    const LengthUnit* mm = findLengthUnit("millimetre");
    const LengthUnit* m = findLengthUnit("M");
    ASSERT_TRUE(in && mm && m);
    EXPECT_EQ(in->name, "in");
    EXPECT_EQ(lengthUnitForIgesFlag(6), m);
    EXPECT_EQ(lengthUnitForIgesFlag(3), nullptr);
    EXPECT_EQ(findLengthUnit("furlong"), nullptr);
    EXPECT_EQ(lengthFactor(*in, *mm), 25.4);
    EXPECT_EQ(lengthFactor(*m, *mm), 1000.0);
    EXPECT_EQ(lengthFactor(*findLengthUnit("ft"), *in), 12.0);
    EXPECT_EQ(lengthFactor(*findLengthUnit("mi"), *findLengthUnit("ft")), 5280.0);
    PatchSet set;
    set.source = "wing.igs";
    set.patches = {plane(0, 5)};
    set.trims.resize(1);
    set.trims[0].outer = rectangleLoop(0.1, 0.9, 0.2, 0.8);
    try {
        convertUnits(set, "mm");
        FAIL();
    } catch (const GeometryError& e) {
        EXPECT_STREQ(e.what(), "'wing.igs' states no length unit, so it cannot be converted to mm");
    }
    set.unit = "m";
    convertUnits(set, "millimetres");
    EXPECT_EQ(set.unit, "mm");
    EXPECT_EQ(set.patches[0].points[3], 5000.0);
    EXPECT_EQ(set.trims[0].outer.curves[0].curve.points[0], 0.1);  // parameter space: unchanged
    EXPECT_THROW(convertUnits(set, "cubit"), GeometryError);
    set.unit = "parsec";
    EXPECT_THROW(validate(set), GeometryError);
}
