// STEP through OpenCASCADE's translator: our writer and OCCT's own writer as fixtures, in
// metres, inches and millimetres; poles, weights and knots exactly; trimmed faces kept as
// parameter-space loops; the report; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>

#include "CadFixtures.h"
#include "RandomNurbs.h"
#include "cad/Iges.h"
#include "cad/Step.h"
#include "common/Error.h"
#include "geometry/Units.h"

namespace aero::cad {
namespace {

using fixtures::outputPath;
using geometry::Patch;
using geometry::PatchSet;

std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "no exception thrown";
    return {};
}

void expectSamePatch(const Patch& a, const Patch& b, const std::string& what) {
    EXPECT_EQ(a.degreeU, b.degreeU) << what;
    EXPECT_EQ(a.degreeV, b.degreeV) << what;
    EXPECT_EQ(a.knotsU, b.knotsU) << what;
    EXPECT_EQ(a.knotsV, b.knotsV) << what;
    EXPECT_EQ(a.points, b.points) << what;
    EXPECT_EQ(a.weights, b.weights) << what;
}

PatchSet randomSet(unsigned seed, const std::string& unit) {
    std::mt19937 rng(seed);
    PatchSet set;
    set.unit = unit;
    for (int k = 0; k < 6; ++k) {
        const int pu = 1 + k % 4, pv = 1 + (k + 2) % 4;
        Patch p = test::randomSurface(rng, pu, pv, pu + 2 + k % 3, pv + 1 + k % 2, k % 2 == 1);
        p.knotsU = test::randomKnots(rng, pu, p.countU, -1.5, 2.25);
        set.patches.push_back(std::move(p));
    }
    return set;
}

TEST(Step, RoundTripKeepsUnitPolesWeightsAndKnotsExactly) {
    for (const std::string unit : {"m", "in", "mm"}) {
        for (const std::string schema : {"AP214", "AP242"}) {
            SCOPED_TRACE(unit + " " + schema);
            const PatchSet set = randomSet(3, unit);
            const std::string path = outputPath("random_" + unit + "_" + schema + ".stp");
            writeStep(set, path, schema);
            ReadReport report;
            const PatchSet back = readStep(path, &report);
            EXPECT_EQ(report.format, "STEP");
            EXPECT_EQ(back.unit, unit);
            EXPECT_EQ(report.unit, unit);
            EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
            ASSERT_EQ(back.size(), set.size());
            EXPECT_TRUE(back.trims.empty());
            ASSERT_EQ(report.items.size(), static_cast<std::size_t>(set.size()));
            for (int k = 0; k < set.size(); ++k) {
                EXPECT_EQ(report.items[k].surface, SurfaceOutcome::Kept);
                EXPECT_EQ(report.items[k].trim, TrimOutcome::None);
                EXPECT_GT(report.items[k].entity, 0);  // the face's #id
                expectSamePatch(set.patches[k], back.patches[k], "patch " + std::to_string(k));
            }
        }
    }
}

// STEP written by OpenCASCADE's own writer (a B-spline face in inches, 17 digits): the unit
// and the values are the file's.
TEST(Step, OcctWrittenInchFileKeepsItsUnitAndValues) {
    const Handle(Geom_BSplineSurface) surface = fixtures::wavySurface(3.0);
    const std::string path = outputPath("occt_inch.stp");
    fixtures::writeStepWithOcct(BRepBuilderAPI_MakeFace(surface, 1e-7), "INCH", path);
    ReadReport report;
    const PatchSet set = readStep(path, &report);
    EXPECT_EQ(set.unit, "in");
    EXPECT_NE(report.unitSource.find("INCH"), std::string::npos) << report.unitSource;
    ASSERT_EQ(set.size(), 1);
    fixtures::expectSameSurface(*surface, set.patches[0], "OCCT's STEP face");
    EXPECT_FALSE(set.trimmed(0));
}

// A trimmed face with a hole (OCCT's STEP writer): kept as parameter-space loops, the same
// region as the face's own p-curves.
TEST(Step, TrimmedFacesKeepTheirLoops) {
    const Handle(Geom_BSplineSurface) surface = fixtures::wavySurface();
    const std::string path = outputPath("occt_trimmed.stp");
    fixtures::writeStepWithOcct(fixtures::trimmedFace(surface, true), "MM", path);
    ReadReport report;
    const PatchSet set = readStep(path, &report);
    EXPECT_EQ(set.unit, "mm");
    ASSERT_EQ(set.size(), 1);
    fixtures::expectSameSurface(*surface, set.patches[0], "the base surface");
    ASSERT_TRUE(set.trimmed(0));
    ASSERT_EQ(report.items.size(), 1u);
    EXPECT_EQ(report.items[0].surface, SurfaceOutcome::Kept);
    EXPECT_EQ(report.items[0].trim, TrimOutcome::Computed);
    EXPECT_NE(report.items[0].note.find("largest distance"), std::string::npos)
        << report.items[0].note;
    const geometry::PatchTrim& t = set.trims[0];
    ASSERT_EQ(t.holes.size(), 1u);
    // The hole is the circle of radius 0.15: area pi r^2 in parameter space.
    EXPECT_NEAR(std::abs(geometry::signedArea(t.holes[0])), std::numbers::pi * 0.15 * 0.15, 1e-12);
    const PatchSet iges = readIges([&] {
        const std::string p = outputPath("occt_trimmed_for_step.igs");
        fixtures::writeIgesWithOcct(fixtures::trimmedFace(surface, true), "MM", 0, p);
        return p;
    }());
    EXPECT_NEAR(std::abs(geometry::signedArea(t.outer)),
                std::abs(geometry::signedArea(iges.trims[0].outer)), 1e-12);
}

// Our trimmed patches out to STEP and back: the surface exactly, the loops bounding the same
// region, the unit kept.
TEST(Step, OurTrimmedPatchesRoundTrip) {
    const PatchSet set = readIges([&] {
        const std::string p = outputPath("occt_trimmed_for_step2.igs");
        fixtures::writeIgesWithOcct(fixtures::trimmedFace(fixtures::wavySurface(), true), "M", 0,
                                    p);
        return p;
    }());
    ASSERT_TRUE(set.trimmed(0));
    EXPECT_EQ(set.unit, "m");
    const std::string path = outputPath("trimmed_back.step");
    writeStep(set, path);
    ReadReport report;
    const PatchSet back = readStep(path, &report);
    EXPECT_EQ(back.unit, "m");
    ASSERT_EQ(back.size(), 1);
    expectSamePatch(set.patches[0], back.patches[0], "the base surface");
    ASSERT_TRUE(back.trimmed(0));
    ASSERT_EQ(back.trims[0].holes.size(), 1u);
    EXPECT_NEAR(std::abs(geometry::signedArea(back.trims[0].outer)),
                std::abs(geometry::signedArea(set.trims[0].outer)), 1e-12);
    EXPECT_NEAR(std::abs(geometry::signedArea(back.trims[0].holes[0])),
                std::abs(geometry::signedArea(set.trims[0].holes[0])), 1e-12);
}

// Found by fuzz_step (tests/fuzz): an entity OpenCASCADE cannot read (here every CARTESIAN_POINT
// misspelt; the fuzzer broke a control point of a p-curve, a placement's location, a direction)
// was a null handle inside its translator, which crashed (SEGV in
// StepGeom_CartesianPoint::NbCoordinates). The file is refused naming it and the first entity.
TEST(Step, AnUnreadableControlPointIsRefusedNotACrash) {
    const std::string path = outputPath("broken_points.stp");
    fixtures::writeStepWithOcct(fixtures::trimmedFace(fixtures::wavySurface(), true), "MM", path);
    std::string text = fixtures::slurp(path);
    for (std::size_t at = 0; (at = text.find("= CARTESIAN_POINT(", at)) != std::string::npos;)
        text.replace(at, 18, "= CARTESIAN_POIE(");
    fixtures::writeText(path, text);
    const std::string m = messageOf([&] { readStep(path); });
    EXPECT_NE(m.find("STEP file '" + path + "'"), std::string::npos) << m;
    EXPECT_NE(m.find("is malformed"), std::string::npos) << m;
}

// Found by fuzz_step, 2026-12-05: a p-curve whose definitional representation holds a point
// instead of a 2D curve crashed OpenCASCADE's translator (SEGV in StepToGeom::MakeCurve2d).
// Refused, naming the p-curve, its representation and the item.
TEST(Step, APcurveWhoseRepresentationHoldsNoCurveIsRefusedNotACrash) {
    const std::string path = outputPath("pcurve_point.stp");
    fixtures::writeStepWithOcct(fixtures::trimmedFace(fixtures::wavySurface(), true), "MM", path);
    std::string text = fixtures::slurp(path);
    // The first DEFINITIONAL_REPRESENTATION('',(#c),#ctx): its item becomes a CARTESIAN_POINT.
    const std::size_t rep = text.find("DEFINITIONAL_REPRESENTATION('',(#");
    ASSERT_NE(rep, std::string::npos);
    const std::size_t point = text.find("= CARTESIAN_POINT(");
    ASSERT_NE(point, std::string::npos);
    const std::size_t hash = text.rfind('#', point);
    const std::string pointId = text.substr(hash + 1, text.find_first_of(" =", hash) - hash - 1);
    const std::size_t item = rep + std::string("DEFINITIONAL_REPRESENTATION('',(#").size();
    text.replace(item, text.find(')', item) - item, pointId);
    fixtures::writeText(path, text);
    const std::string m = messageOf([&] { readStep(path); });
    EXPECT_NE(m.find("STEP file '" + path + "': p-curve #"), std::string::npos) << m;
    EXPECT_NE(m.find("holds #" + pointId + " (StepGeom_CartesianPoint), not a curve"), std::string::npos) << m;
}

TEST(Step, BadInputIsAnInputErrorNamingTheFile) {
    const std::string missing = outputPath("missing.stp");
    std::filesystem::remove(missing);
    std::string m = messageOf([&] { readStep(missing); });
    EXPECT_NE(m.find("cannot open STEP file '" + missing + "'"), std::string::npos) << m;
    const std::string text = outputPath("text.stp");
    fixtures::writeText(text, "this is not STEP\n");
    m = messageOf([&] { readStep(text); });
    EXPECT_NE(m.find("'" + text + "' is not a STEP file"), std::string::npos) << m;
    // The right header but nothing after it.
    const std::string empty = outputPath("header_only.stp");
    fixtures::writeText(empty,
                        "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n");
    m = messageOf([&] { readStep(empty); });
    EXPECT_NE(m.find(empty), std::string::npos) << m;
    // An unknown schema is refused before anything is written.
    PatchSet set = randomSet(1, "mm");
    m = messageOf([&] { writeStep(set, outputPath("x.stp"), "AP999"); });
    EXPECT_NE(m.find("AP999"), std::string::npos) << m;
}

}  // namespace
}  // namespace aero::cad
