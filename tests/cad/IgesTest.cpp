// IGES adapter: exact write -> read round trips, the read report, and every bad input
// throwing the right aero exception with the file named in the message.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_SurfaceOfLinearExtrusion.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Plane.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "CadFixtures.h"
#include "RandomNurbs.h"
#include "cad/Iges.h"
#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "geometry/Topology.h"
#include "nurbs/Surface.h"

// OpenCASCADE's one-time initialisation of its IGES settings (IGESControl_Controller::Init,
// in MoniTool_TypedValue::AddEnum) leaks a few hundred bytes. With fast unwinding the
// reported stack ends in OCCT's allocator, so that is what is suppressed: this keeps
// LeakSanitizer builds (AEROFORM_SANITIZE) green; our own allocations are still checked.
extern "C" const char* __lsan_default_suppressions() {
    return "leak:Standard_MMgrRaw\n";
}

namespace aero::cad {
namespace {

namespace fs = std::filesystem;
using geometry::Patch;
using geometry::PatchSet;

std::string outputPath(const std::string& name) {
    const fs::path dir = fs::path(AEROFORM_TEST_OUTPUT_DIR) / "cad";
    fs::create_directories(dir);
    return (dir / name).string();
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Runs f and returns the message of the exception of type E it must throw.
template <class E>
std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "no exception thrown";
    return {};
}

/// Index of the first differing entry (or -1), compared with ==, so equal means bit for bit
/// up to the sign of zero.
int firstMismatch(const std::vector<double>& a, const std::vector<double>& b) {
    if (a.size() != b.size()) return 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!(a[i] == b[i])) return static_cast<int>(i);
    return -1;
}

void expectSamePatch(const Patch& a, const Patch& b, const std::string& what) {
    EXPECT_EQ(a.degreeU, b.degreeU) << what;
    EXPECT_EQ(a.degreeV, b.degreeV) << what;
    EXPECT_EQ(a.countU, b.countU) << what;
    EXPECT_EQ(a.countV, b.countV) << what;
    EXPECT_EQ(firstMismatch(a.knotsU, b.knotsU), -1) << what << ": knotsU";
    EXPECT_EQ(firstMismatch(a.knotsV, b.knotsV), -1) << what << ": knotsV";
    EXPECT_EQ(firstMismatch(a.points, b.points), -1) << what << ": points";
    EXPECT_EQ(a.rational(), b.rational()) << what;
    EXPECT_EQ(firstMismatch(a.weights, b.weights), -1) << what << ": weights";
}

void expectExactRoundTrip(const PatchSet& set, const std::string& file) {
    const std::string path = outputPath(file);
    writeIges(set, path);
    ReadReport report;
    const PatchSet back = readIges(path, &report);
    EXPECT_EQ(back.source, path);
    EXPECT_EQ(report.format, "IGES");
    EXPECT_EQ(report.unit, set.unit.empty() ? "mm" : set.unit);
    EXPECT_EQ(back.unit, report.unit);
    ASSERT_EQ(report.items.size(), static_cast<std::size_t>(set.size()));
    EXPECT_EQ(report.count(SurfaceOutcome::Kept), set.size());
    EXPECT_EQ(report.count(TrimOutcome::None), set.size());
    for (const ReadItem& item : report.items) EXPECT_EQ(item.type, 128);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_EQ(back.size(), set.size());
    ASSERT_EQ(back.names.size(), set.patches.size());
    EXPECT_TRUE(back.trims.empty());
    for (int k = 0; k < set.size(); ++k) {
        // Names come back (labels, or a name property when longer than 8 characters); a set
        // without names gets the entity numbers.
        EXPECT_EQ(back.names[k], set.names.empty() ? "entity " + std::to_string(k + 1) : set.names[k]);
        expectSamePatch(set.patches[k], back.patches[k], set.describe(k));
    }
}

/// Random patches: degrees 1..5, non-uniform knots on an arbitrary interval with interior
/// multiplicities, every second one rational; coordinates over many magnitudes.
PatchSet randomPatches(unsigned seed, int n) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> degree(1, 5), extra(0, 6);
    std::uniform_real_distribution<double> start(-10.0, 10.0), length(0.01, 50.0), exponent(-6, 6);
    PatchSet set;
    set.source = "random";
    for (int k = 0; k < n; ++k) {
        const int pu = degree(rng), pv = degree(rng);
        Patch p =
            test::randomSurface(rng, pu, pv, pu + 1 + extra(rng), pv + 1 + extra(rng), k % 2 == 1);
        const double a = start(rng), c = start(rng);
        p.knotsU = test::randomKnots(rng, pu, p.countU, a, a + length(rng));
        p.knotsV = test::randomKnots(rng, pv, p.countV, c, c + length(rng));
        const double scale = std::pow(10.0, exponent(rng));
        for (double& x : p.points) x *= scale;
        set.patches.push_back(std::move(p));
        set.names.push_back("random " + std::to_string(k));
    }
    return set;
}

/// Whether some interior knot is repeated.
bool hasInteriorMultiplicity(const std::vector<double>& knots, int degree) {
    for (std::size_t i = degree + 1; i + degree + 2 < knots.size(); ++i)
        if (knots[i] == knots[i + 1]) return true;
    return false;
}

TEST(Iges, RoundTripOfRandomPatchesIsExact) {
    int repeated = 0, rational = 0;
    for (unsigned seed : {1u, 2u, 3u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const PatchSet set = randomPatches(seed, 12);
        geometry::validate(set);
        for (const Patch& p : set.patches) {
            repeated += hasInteriorMultiplicity(p.knotsU, p.degreeU) ||
                        hasInteriorMultiplicity(p.knotsV, p.degreeV);
            rational += p.rational();
        }
        expectExactRoundTrip(set, "random_" + std::to_string(seed) + ".igs");
    }
    EXPECT_GT(repeated, 3);  // the cases that matter are really there
    EXPECT_EQ(rational, 18);
}

TEST(Iges, RoundTripOfAClosedPatchIsExact) {
    // First and last rows of the net coincide: OCCT would re-knot it as periodic if the file
    // flagged it closed.
    std::mt19937 rng(7);
    PatchSet set;
    set.source = "closed";
    for (bool rational : {false, true}) {
        Patch p = test::randomSurface(rng, 3, 2, 8, 5, rational);
        for (int j = 0; j < p.countV; ++j) {
            const int first = p.index(0, j), last = p.index(p.countU - 1, j);
            for (int d = 0; d < 3; ++d) p.points[3 * last + d] = p.points[3 * first + d];
            if (rational) p.weights[last] = p.weights[first];
        }
        set.patches.push_back(p);
    }
    expectExactRoundTrip(set, "closed.igs");
}

TEST(Iges, RoundTripOfHalfSphereIsExact) {
    const PatchSet sphere = geometry::makeHalfSphere();
    ASSERT_EQ(sphere.size(), 20);
    expectExactRoundTrip(sphere, "half_sphere.igs");
}

TEST(Iges, RationalWithEqualWeightsStaysRational) {
    // The file flags it rational (PROP3 = 0): its weights are kept as written (OpenCASCADE's
    // reader made it polynomial).
    std::mt19937 rng(11);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 2, 3, 4, 6, true));
    std::fill(set.patches[0].weights.begin(), set.patches[0].weights.end(), 1.0);
    const std::string path = outputPath("equal_weights.igs");
    writeIges(set, path);
    const PatchSet back = readIges(path);
    ASSERT_EQ(back.size(), 1);
    EXPECT_TRUE(back.patches[0].rational());
    EXPECT_EQ(back.patches[0].weights, set.patches[0].weights);
    EXPECT_EQ(firstMismatch(set.patches[0].points, back.patches[0].points), -1);
}

TEST(Iges, ReportsConvertedTrimmedAndPeriodicFaces) {
    // Three faces written by OCCT as BRep entities: a bounded plane (converted), a B-spline
    // face trimmed to part of its surface, a full cylinder (converted, periodic).
    TColgp_Array2OfPnt poles(1, 3, 1, 3);
    for (int i = 1; i <= 3; ++i)
        for (int j = 1; j <= 3; ++j) poles(i, j) = gp_Pnt(i, j, 0.1 * i * j);
    TColStd_Array1OfReal knots(1, 2);
    knots(1) = 0.0;
    knots(2) = 1.0;
    TColStd_Array1OfInteger mults(1, 2);
    mults.Init(3);
    Handle(Geom_BSplineSurface) bspline =
        new Geom_BSplineSurface(poles, knots, knots, mults, mults, 2, 2);

    TopoDS_Compound shape;
    BRep_Builder builder;
    builder.MakeCompound(shape);
    const Handle(Geom_Surface) plane = new Geom_Plane(gp::XOY());
    const Handle(Geom_Surface) cylinder = new Geom_CylindricalSurface(gp::XOY(), 2.0);
    builder.Add(shape, BRepBuilderAPI_MakeFace(plane, 0.0, 2.0, 0.0, 1.0, 1e-7));
    builder.Add(shape, BRepBuilderAPI_MakeFace(bspline, 0.25, 0.75, 0.0, 1.0, 1e-7));
    builder.Add(shape,
                BRepBuilderAPI_MakeFace(cylinder, 0.0, 2 * std::numbers::pi, 0.0, 3.0, 1e-7));
    const std::string path = outputPath("faces.igs");
    IGESControl_Controller::Init();
    IGESControl_Writer writer("MM", 1);
    ASSERT_TRUE(writer.AddShape(shape));
    ASSERT_TRUE(writer.Write(path.c_str()));

    ReadReport report;
    const PatchSet set = readIges(path, &report);
    ASSERT_EQ(set.size(), 3);
    // Written as B-rep: a group (402) of three faces (510); each face one patch.
    ASSERT_EQ(report.items.size(), 4u);
    EXPECT_EQ(report.items[0].type, 402);
    EXPECT_EQ(report.items[0].surface, SurfaceOutcome::Ignored);
    EXPECT_EQ(report.items[0].note, "an associativity (a group): its members are read on their own");
    for (int k = 1; k <= 3; ++k) EXPECT_EQ(report.items[k].type, 510);
    // The plane: converted exactly; the B-spline face: its surface as written, trimmed to
    // [0.25, 0.75] x [0, 1] (a B-rep face: OCCT's p-curves, reported as computed); the full
    // cylinder converted and made non-periodic, untrimmed.
    EXPECT_EQ(report.items[1].surface, SurfaceOutcome::Converted);
    EXPECT_EQ(report.items[1].trim, TrimOutcome::None);
    EXPECT_NE(report.items[1].note.find("Geom_Plane converted to an exact NURBS surface"), std::string::npos) << report.items[1].note;
    EXPECT_EQ(report.items[2].surface, SurfaceOutcome::Kept);
    EXPECT_EQ(report.items[2].trim, TrimOutcome::Computed);
    EXPECT_EQ(report.items[3].surface, SurfaceOutcome::Converted);
    EXPECT_EQ(report.items[3].trim, TrimOutcome::None);
    EXPECT_NE(report.items[3].note.find("Geom_CylindricalSurface converted"), std::string::npos) << report.items[3].note;
    EXPECT_NE(report.items[3].note.find("periodic knots made non-periodic"), std::string::npos) << report.items[3].note;
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    EXPECT_FALSE(set.trimmed(0));
    EXPECT_FALSE(set.trimmed(2));
    ASSERT_TRUE(set.trimmed(1));
    // Bit for bit what the file says (OCCT's own reader of the same text, in the file's unit).
    const auto occt = fixtures::occtSurfaces(path, "MM");
    ASSERT_EQ(occt.size(), 3u);
    ASSERT_FALSE(occt[1].IsNull());
    fixtures::expectSameSurface(*occt[1], set.patches[1], "the B-spline face");
    const geometry::TrimPolygons poly = geometry::polygonize(set.trims[1], set.patches[1]);
    EXPECT_NEAR(std::abs(geometry::signedArea(poly.loops[0])), 0.5, 1e-15);
    EXPECT_TRUE(geometry::contains(poly, 0.5, 0.5));
    EXPECT_FALSE(geometry::contains(poly, 0.2, 0.5));
    EXPECT_FALSE(geometry::contains(poly, 0.8, 0.5));

    // The converted cylinder is the same surface: every point at radius 2.
    const Patch& round = set.patches[2];
    for (double u : {0.0, 0.3, 0.5, 0.9, 1.0})
        for (double v : {0.0, 0.5, 1.0}) {
            const double s =
                round.knotsU.front() + u * (round.knotsU.back() - round.knotsU.front());
            const double t =
                round.knotsV.front() + v * (round.knotsV.back() - round.knotsV.front());
            const auto p = nurbs::evaluate(round, s, t);
            EXPECT_NEAR(std::hypot(p.x(), p.y()), 2.0, 1e-6) << "u " << s << " v " << t;
        }
}

// Files in metres and inches written by OpenCASCADE's IGES writer: the unit is the file's and
// the values are the file's, bit for bit (compared with OCCT's own reader told to use the file's
// unit; its default, millimetres, multiplies them). Both 17-digit and OCCT's default ~10-digit
// output.
TEST(Iges, MetreAndInchFilesKeepTheirUnitAndValuesBitForBit) {
    const TopoDS_Face face = BRepBuilderAPI_MakeFace(fixtures::wavySurface(2500.0), 1e-7);  // 5 m chord, in mm
    struct Case {
        const char *occtUnit, *unit;
        double mmPerUnit;
        bool exact;
    };
    for (const Case& c : {Case{"M", "m", 1000.0, true}, Case{"M", "m", 1000.0, false}, Case{"INCH", "in", 25.4, true},
                          Case{"INCH", "in", 25.4, false}, Case{"MM", "mm", 1.0, true}}) {
        SCOPED_TRACE(std::string(c.unit) + (c.exact ? " 17 digits" : " OCCT default digits"));
        const std::string path = outputPath(std::string("occt_") + c.unit + (c.exact ? "_exact" : "_default") + ".igs");
        fixtures::writeIgesWithOcct(face, c.occtUnit, 0, path, c.exact);
        ReadReport report;
        const PatchSet set = readIges(path, &report);
        EXPECT_EQ(set.unit, c.unit);
        EXPECT_EQ(report.unit, c.unit);
        EXPECT_NE(report.unitSource.find("IGES unit flag"), std::string::npos);
        EXPECT_TRUE(report.warnings.empty());
        ASSERT_EQ(set.size(), 1);
        ASSERT_EQ(report.items.size(), 1u);
        EXPECT_EQ(report.items[0].surface, SurfaceOutcome::Kept);
        const auto occt = fixtures::occtSurfaces(path, c.occtUnit);
        ASSERT_EQ(occt.size(), 1u);
        ASSERT_FALSE(occt[0].IsNull());
        fixtures::expectSameSurface(*occt[0], set.patches[0], "OCCT in the file's unit");
        // The chord is 5 m: 5 in metres, 196.85... in inches (not the 5000 millimetres OCCT reads).
        const geometry::BoundingBox box = geometry::controlBoundingBox(set);
        EXPECT_NEAR(box.max[0] - box.min[0], 5000.0 / c.mmPerUnit, 1e-8 * 5000.0 / c.mmPerUnit);
        if (c.mmPerUnit != 1.0) {
            const auto mm = fixtures::occtSurfaces(path, "MM");
            ASSERT_EQ(mm.size(), 1u);
            EXPECT_NEAR(mm[0]->Pole(4, 3).X(), c.mmPerUnit * set.patches[0].points[3 * set.patches[0].index(3, 2)], 1e-9);
        }
        // Written back: the same unit, the same values.
        const std::string back = outputPath(std::string("occt_") + c.unit + "_back.igs");
        writeIges(set, back);
        const PatchSet again = readIges(back);
        EXPECT_EQ(again.unit, c.unit);
        expectSamePatch(set.patches[0], again.patches[0], "written back");
    }
}

/// Our loop's curve equals an OCCT p-curve we made (same poles, knots, range), bit for bit.
void expectSameCurve(const geometry::TrimCurve& c, const Geom2d_BSplineCurve& b, const std::string& what) {
    ASSERT_EQ(c.curve.count(), b.NbPoles()) << what;
    EXPECT_EQ(c.curve.degree, b.Degree()) << what;
    for (int i = 0; i < b.NbPoles(); ++i) {
        EXPECT_EQ(c.curve.points[3 * i], b.Pole(i + 1).X()) << what << " pole " << i;
        EXPECT_EQ(c.curve.points[3 * i + 1], b.Pole(i + 1).Y()) << what << " pole " << i;
    }
    TColStd_Array1OfReal k(1, b.NbPoles() + b.Degree() + 1);
    b.KnotSequence(k);
    EXPECT_EQ(c.curve.knots, std::vector<double>(k.begin(), k.end())) << what;
    EXPECT_EQ(c.first, b.FirstParameter()) << what;
    EXPECT_EQ(c.last, b.LastParameter()) << what;
}

// A trimmed face (outer loop of two B-spline p-curves, a circular hole) written by OCCT as
// 144/142 in millimetres with 17 digits: read by our parser exactly, written back exactly, and
// our output read by OCCT as one face with a hole.
TEST(Iges, TrimmedFacesWrittenByOcctAreKeptExactly) {
    const Handle(Geom_BSplineSurface) surface = fixtures::wavySurface();
    const TopoDS_Face face = fixtures::trimmedFace(surface, true);
    const std::string path = outputPath("occt_trimmed.igs");
    fixtures::writeIgesWithOcct(face, "MM", 0, path);
    ReadReport report;
    const PatchSet set = readIges(path, &report);
    ASSERT_EQ(set.size(), 1);
    ASSERT_EQ(report.items.size(), 1u);
    const ReadItem& item = report.items[0];
    EXPECT_EQ(item.type, 144);
    EXPECT_EQ(item.surface, SurfaceOutcome::Kept) << item.note;
    // The circle is written by OCCT as a circular arc (100) with a transformation matrix (124):
    // the same curve as a rational B-spline, its control points computed.
    EXPECT_EQ(item.trim, TrimOutcome::Converted) << item.note;
    EXPECT_EQ(item.note, "trim curves: circular arcs made rational B-splines, transformation matrices applied");
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    fixtures::expectSameSurface(*surface, set.patches[0], "the base surface");
    ASSERT_TRUE(set.trimmed(0));
    const geometry::PatchTrim& trim = set.trims[0];
    ASSERT_EQ(trim.outer.curves.size(), 2u);
    ASSERT_EQ(trim.holes.size(), 1u);
    expectSameCurve(trim.outer.curves[0],
                    *fixtures::curve2d({gp_Pnt2d(0.1, 0.1), gp_Pnt2d(0.7, 0.05), gp_Pnt2d(1.3, 0.3), gp_Pnt2d(1.9, 0.15)}, 3), "lower");
    expectSameCurve(trim.outer.curves[1],
                    *fixtures::curve2d({gp_Pnt2d(1.9, 0.15), gp_Pnt2d(1.5, 0.9), gp_Pnt2d(0.4, 0.95), gp_Pnt2d(0.1, 0.1)}, 2), "upper");
    // The circle (OCCT writes it as a rational 126): every point at radius 0.15 from (0.9, 0.45).
    double worst = 0;
    for (const geometry::TrimCurve& c : trim.holes[0].curves)
        for (int k = 0; k <= 50; ++k) {
            const geometry::Point2 uv = geometry::evaluate(c, c.first + (c.last - c.first) * k / 50);
            worst = std::max(worst, std::abs(std::hypot(uv[0] - 0.9, uv[1] - 0.45) - 0.15));
        }
    EXPECT_LT(worst, 1e-15);

    // Written back and read again: identical.
    const std::string out = outputPath("occt_trimmed_back.igs");
    writeIges(set, out);
    const PatchSet back = readIges(out);
    ASSERT_TRUE(back.trimmed(0));
    ASSERT_EQ(back.trims[0].holes.size(), 1u);
    for (std::size_t k = 0; k < 2; ++k) {
        EXPECT_EQ(back.trims[0].outer.curves[k].curve.points, trim.outer.curves[k].curve.points);
        EXPECT_EQ(back.trims[0].outer.curves[k].curve.knots, trim.outer.curves[k].curve.knots);
    }
    EXPECT_EQ(back.trims[0].holes[0].curves[0].curve.weights, trim.holes[0].curves[0].curve.weights);
    // OCCT reads our output: one face, two wires, and its area (OCCT's integration) equals the
    // original face's.
    IGESControl_Controller::Init();
    IGESControl_Reader reader;
    ASSERT_EQ(reader.ReadFile(out.c_str()), IFSelect_RetDone);
    reader.TransferRoots();
    int faces = 0, wires = 0;
    double area = 0;
    for (TopExp_Explorer f(reader.OneShape(), TopAbs_FACE); f.More(); f.Next()) {
        ++faces;
        for (TopExp_Explorer w(f.Current(), TopAbs_WIRE); w.More(); w.Next()) ++wires;
        GProp_GProps props;
        BRepGProp::SurfaceProperties(f.Current(), props, 1e-10);
        area += props.Mass();
    }
    GProp_GProps original;
    BRepGProp::SurfaceProperties(face, original, 1e-10);
    EXPECT_EQ(faces, 1);
    EXPECT_EQ(wires, 2);
    // (Adaptive integration to 1e-10; a lost or inverted hole would be 7 % off.)
    EXPECT_NEAR(area, original.Mass(), 1e-7 * original.Mass());
}

// Without parameter-space curves in the file (OCCT's write.surfacecurve.mode 0), the trims are
// defined in model space only: OpenCASCADE computes the loops, the report and a warning say so.
TEST(Iges, ModelSpaceOnlyTrimsAreComputedWithAWarning) {
    const Handle(Geom_BSplineSurface) surface = fixtures::wavySurface();
    const TopoDS_Face face = fixtures::trimmedFace(surface, true);
    const std::string path = outputPath("occt_model_space_trims.igs");
    fixtures::writeIgesWithOcct(face, "MM", 0, path, true, false);
    ReadReport report;
    const PatchSet set = readIges(path, &report);
    ASSERT_EQ(set.size(), 1);
    ASSERT_EQ(report.items.size(), 1u);
    EXPECT_EQ(report.items[0].surface, SurfaceOutcome::Kept);
    EXPECT_EQ(report.items[0].trim, TrimOutcome::Computed);
    EXPECT_NE(report.items[0].note.find("model space only"), std::string::npos) << report.items[0].note;
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("trim loops defined in model space only"), std::string::npos) << report.warnings[0];
    fixtures::expectSameSurface(*surface, set.patches[0], "the base surface");
    // The computed loops bound the same region as the exact ones (the fixture's parameter-space
    // curves): areas in parameter space agree to the model-space curves' accuracy.
    ASSERT_TRUE(set.trimmed(0));
    const PatchSet exact = readIges(outputPath("occt_trimmed.igs"));
    const geometry::PatchTrim &ours = set.trims[0], &reference = exact.trims[0];
    ASSERT_EQ(ours.holes.size(), 1u);
    EXPECT_NEAR(std::abs(geometry::signedArea(ours.outer)), std::abs(geometry::signedArea(reference.outer)), 1e-7);
    EXPECT_NEAR(std::abs(geometry::signedArea(ours.holes[0])), std::abs(geometry::signedArea(reference.holes[0])), 1e-7);
    EXPECT_NEAR(std::abs(geometry::signedArea(reference.holes[0])), std::numbers::pi * 0.15 * 0.15, 1e-15);
}

// Surfaces of revolution and extrusions (OCCT writes them as 144 over 120 and 122) in metres:
// converted to NURBS by OpenCASCADE exactly (the points lie on the original surfaces), unit kept.
TEST(Iges, SurfacesOfRevolutionAndExtrusionsAreConvertedExactly) {
    const Handle(Geom_BSplineCurve) profile = [] {
        TColgp_Array1OfPnt p(1, 4);
        p(1) = gp_Pnt(100, 0, 0);
        p(2) = gp_Pnt(150, 0, 100);
        p(3) = gp_Pnt(120, 0, 200);
        p(4) = gp_Pnt(60, 0, 300);
        TColStd_Array1OfReal k(1, 2);
        k(1) = 0;
        k(2) = 1;
        TColStd_Array1OfInteger m(1, 2);
        m.Init(4);
        return Handle(Geom_BSplineCurve)(new Geom_BSplineCurve(p, k, m, 3));
    }();
    const Handle(Geom_Surface) revolution = new Geom_SurfaceOfRevolution(profile, gp::OZ());
    const Handle(Geom_Surface) extrusion = new Geom_SurfaceOfLinearExtrusion(profile, gp_Dir(0, 1, 0));
    TopoDS_Compound shape;
    BRep_Builder builder;
    builder.MakeCompound(shape);
    builder.Add(shape, BRepBuilderAPI_MakeFace(revolution, 0.0, 1.5 * std::numbers::pi, 0.0, 1.0, 1e-7));
    builder.Add(shape, BRepBuilderAPI_MakeFace(extrusion, 0.0, 1.0, 0.0, 80.0, 1e-7));
    const std::string path = outputPath("occt_revolution_m.igs");
    fixtures::writeIgesWithOcct(shape, "M", 0, path);
    ReadReport report;
    const PatchSet set = readIges(path, &report);
    EXPECT_EQ(set.unit, "m");
    ASSERT_EQ(set.size(), 2);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    int converted = 0;
    std::string kinds;
    for (const ReadItem& i : report.items) {
        converted += i.surface == SurfaceOutcome::Converted;
        kinds += i.kind + "; ";
    }
    EXPECT_EQ(converted, 2) << kinds;
    EXPECT_NE(kinds.find("surface of revolution"), std::string::npos) << kinds;
    EXPECT_NE(kinds.find("tabulated cylinder"), std::string::npos) << kinds;
    // Every sampled point (metres) lies on its original surface (millimetres).
    for (int p = 0; p < 2; ++p) {
        const Handle(Geom_Surface) original = p == 0 ? revolution : extrusion;
        const geometry::Patch& s = set.patches[static_cast<std::size_t>(p)];
        double worst = 0;
        for (int i = 0; i <= 6; ++i)
            for (int j = 0; j <= 6; ++j) {
                const auto x = nurbs::evaluate(s, s.knotsU.front() + (s.knotsU.back() - s.knotsU.front()) * i / 6,
                                               s.knotsV.front() + (s.knotsV.back() - s.knotsV.front()) * j / 6);
                GeomAPI_ProjectPointOnSurf proj(gp_Pnt(1000 * x.x(), 1000 * x.y(), 1000 * x.z()), original);
                ASSERT_GT(proj.NbPoints(), 0);
                worst = std::max(worst, proj.LowerDistance());
            }
        EXPECT_LT(worst, 1e-7) << "patch " << p;  // millimetres, on a body of 300 mm
    }
}

TEST(Iges, MissingFileIsAnInputErrorNamingIt) {
    const std::string path = outputPath("does_not_exist.igs");
    fs::remove(path);
    const std::string m = messageOf<InputError>([&] { readIges(path); });
    EXPECT_NE(m.find("cannot open IGES file '" + path + "'"), std::string::npos) << m;
}

TEST(Iges, TextAndJsonFilesAreNotIges) {
    const std::vector<std::pair<std::string, std::string>> files = {
        {"notes.txt", "This is a plain text file.\nIt is not IGES.\n"},
        {"patches.json", "{\"patches\": [{\"degreeU\": 3, \"degreeV\": 3}]}\n"},
        {"empty.igs", ""}};
    for (const auto& [name, text] : files) {
        const std::string path = outputPath(name);
        writeText(path, text);
        const std::string m = messageOf<InputError>([&] { readIges(path); });
        EXPECT_NE(m.find(path), std::string::npos) << m;
        EXPECT_NE(m.find("not an IGES file"), std::string::npos) << m;
    }
}

/// One IGES line: 72 columns of data, the section letter, a 7-digit sequence number.
std::string igesLine(const std::string& data, char section, int seq) {
    char tail[9];
    std::snprintf(tail, sizeof tail, "%c%07d", section, seq);
    return (data + std::string(72 - data.size(), ' ')) + tail + "\n";
}

/// A valid IGES file holding a single point (entity 116) and no surface, written by hand.
std::string pointOnlyIges() {
    std::string f;
    f += igesLine("Aeroform test: one point, no surface", 'S', 1);
    f += igesLine(",,4Htest,9Hpoint.igs,4Htest,4Htest,32,308,15,308,15,4Htest,1.,2,2HMM,", 'G', 1);
    f += igesLine("1,0.01,15H20240101.000000,1.E-06,10.,2Hme,2Hme,11,0,", 'G', 2);
    f += igesLine("15H20240101.000000;", 'G', 3);
    f += igesLine("     116       1       0       0       0       0       0       000000000", 'D',
                  1);
    f += igesLine("     116       0       0       1       0", 'D', 2);
    f += igesLine(std::string("116,1.,2.,3.;").append(51, ' ') + "       1", 'P', 1);
    f += igesLine("S0000001G0000003D0000002P0000001", 'T', 1);
    return f;
}

TEST(Iges, FileWithoutSurfacesIsAnInputError) {
    const std::string path = outputPath("point_only.igs");
    writeText(path, pointOnlyIges());
    const std::string m = messageOf<InputError>([&] { readIges(path); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("no surfaces"), std::string::npos) << m;
    // ... and what it has instead (a point, type 116, directory entry 1), with the reason.
    EXPECT_NE(m.find("its top-level entities are 1 point (116, DE 1)"), std::string::npos) << m;
}

/// Replaces parameter `index` (1-based) of the parameter section, keeping the columns.
std::string replaceParameter(const std::string& text, int index, const std::string& value) {
    std::istringstream in(text);
    std::string out;
    int count = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.size() >= 73 && line[72] == 'P') {
            for (std::size_t pos = 0; pos < 64;) {
                const std::size_t end = line.find_first_of(",;", pos);
                if (end == std::string::npos || end >= 64) break;
                if (++count == index) {
                    EXPECT_LE(value.size(), end - pos);
                    line.replace(pos, end - pos,
                                 std::string(end - pos - value.size(), ' ') + value);
                }
                pos = end + 1;
            }
        }
        out += line + "\n";
    }
    return out;
}

TEST(Iges, NonNumericCoordinateIsAnInputErrorNamingFileAndEntity) {
    std::mt19937 rng(5);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 3, 2, 5, 4, true));
    const Patch& p = set.patches[0];
    const std::string path = outputPath("valid.igs");
    writeIges(set, path);
    const std::string valid = readText(path);
    // Entity 128: type, 9 integers, both knot vectors, the weights, then the poles.
    const int firstPole =
        10 + static_cast<int>(p.knotsU.size() + p.knotsV.size()) + p.controlCount() + 1;
    for (const std::string bad : {"NaN", "nan", "1.2X3E+00", "inf", "--1.0"}) {
        const std::string corrupt = outputPath("corrupt.igs");
        writeText(corrupt, replaceParameter(valid, firstPole + 4, bad));
        const std::string m = messageOf<InputError>([&] { readIges(corrupt); });
        EXPECT_NE(m.find(corrupt), std::string::npos) << m;
        EXPECT_NE(m.find("entity 1 (type 128"), std::string::npos) << m;
        EXPECT_NE(m.find("not a number: '" + bad + "'"), std::string::npos) << m;
    }
}

TEST(Iges, OverflowingCoordinateIsAnInputErrorNamingFileAndEntity) {
    std::mt19937 rng(6);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 2, 2, 4, 4, false));
    const Patch& p = set.patches[0];
    const std::string path = outputPath("overflow.igs");
    writeIges(set, path);
    const int firstPole =
        10 + static_cast<int>(p.knotsU.size() + p.knotsV.size()) + p.controlCount() + 1;
    // The fields are 23 columns wide ("%.16E"): the value keeps its column.
    writeText(path, replaceParameter(readText(path), firstPole, "1.0E+999"));
    const std::string m = messageOf<InputError>([&] { readIges(path); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("entity 1 (type 128"), std::string::npos) << m;
    EXPECT_NE(m.find("1.0E+999: not a finite number"), std::string::npos) << m;
}

TEST(Iges, InvalidKnotsAreAGeometryErrorNamingFileAndEntity) {
    // OCCT skips an entity 128 it cannot build; with a second, valid surface in the file that
    // must not go unnoticed.
    std::mt19937 rng(9);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 3, 2, 6, 4, false));
    set.patches.push_back(test::randomSurface(rng, 2, 2, 4, 4, true));
    const std::string path = outputPath("bad_knots.igs");
    writeIges(set, path);
    // Parameter 11 is the first u knot of entity 1; the one after the clamped start becomes
    // larger than the last knot.
    const int knot = 11 + set.patches[0].degreeU + 1;
    writeText(path, replaceParameter(readText(path), knot, "1.0E+03"));
    const std::string m = messageOf<GeometryError>([&] { readIges(path); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("entity 1 (type 128"), std::string::npos) << m;
    EXPECT_NE(m.find("not a valid B-spline surface"), std::string::npos) << m;
}

TEST(Iges, UnwritableOutputIsAnInputErrorNamingIt) {
    std::mt19937 rng(8);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 3, 3, 4, 4, false));
    for (const std::string& path : {outputPath("no_such_dir/out.igs"), outputPath("")}) {
        const std::string m = messageOf<InputError>([&] { writeIges(set, path); });
        EXPECT_NE(m.find("cannot write IGES file '" + path + "'"), std::string::npos) << m;
    }
}

// A failed write leaves the existing file as it was and no temporary file behind (it deleted the
// file), and writing through a symlink replaces its target and keeps the link (issue #20).
TEST(Iges, FailedWriteKeepsTheExistingFileAndSymlinksStayLinks) {
    const PatchSet sphere = geometry::makeHalfSphere();
    // A name of 254 characters exists; its temporary sibling's name is too long to create.
    const std::string dir = outputPath("atomic");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string longName = dir + "/" + std::string(250, 'a') + ".igs";  // 254 of the 255 allowed
    writeText(longName, "the user's file\n");
    const std::string before = readText(longName);
    PatchSet other = sphere;
    other.patches.resize(3);
    other.names.resize(3);
    const std::string m = messageOf<InputError>([&] { writeIges(other, longName); });
    EXPECT_NE(m.find("File name too long"), std::string::npos) << m;  // the reason, named
    EXPECT_EQ(readText(longName), before);
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
    EXPECT_EQ(files, 1);  // no temporary left
    // Through a symlink.
    const std::string target = dir + "/target.igs", link = dir + "/link.igs";
    writeIges(sphere, target);
    fs::create_symlink("target.igs", link);
    writeIges(other, link);
    EXPECT_TRUE(fs::is_symlink(link));
    EXPECT_EQ(readIges(target).size(), 3);
}

TEST(Iges, InvalidPatchIsNotWritten) {
    PatchSet set;
    set.source = "broken set";
    set.patches.push_back(Patch{});
    const std::string m =
        messageOf<GeometryError>([&] { writeIges(set, outputPath("broken.igs")); });
    EXPECT_NE(m.find("broken set"), std::string::npos) << m;
}

/// Everything written to file descriptor 1 while f runs (whose exceptions pass through).
std::string captureStdout(const std::function<void()>& f) {
    const std::string path = outputPath("stdout.txt");
    std::fflush(stdout);
    const int saved = ::dup(STDOUT_FILENO);
    const int file = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(file, STDOUT_FILENO);
    ::close(file);
    std::exception_ptr error;
    try {
        f();
    } catch (...) {
        error = std::current_exception();
    }
    std::fflush(stdout);
    ::dup2(saved, STDOUT_FILENO);
    ::close(saved);
    if (error) std::rethrow_exception(error);
    return readText(path);
}

TEST(Iges, ReadingAndWritingPrintNothingOnStdout) {
    const PatchSet set = randomPatches(4, 3);
    const std::string path = outputPath("quiet.igs");
    EXPECT_EQ(captureStdout([&] { writeIges(set, path); }), "");
    EXPECT_EQ(captureStdout([&] { readIges(path); }), "");
    // A read that fails inside OpenCASCADE's part restores stdout too.
    const std::string empty = outputPath("quiet_point_only.igs");
    writeText(empty, pointOnlyIges());
    bool threw = false;
    const std::string printed = captureStdout([&] {
        try {
            readIges(empty);
        } catch (const InputError&) {
            threw = true;
        }
        std::printf("after");
    });
    EXPECT_TRUE(threw);
    EXPECT_EQ(printed, "after");
}

}  // namespace

namespace {

// The sample's IGES text with parameter `index` (0-based; 0 is the type) of its first entity
// replaced by `value` (the entity's lines keep their 64 data columns). Unlike replaceParameter
// above, which keeps the field's width, this repacks the line: the values here are wider than
// the sample's one-digit counts and degrees.
std::string withFirstEntityParameter(int index, const std::string& value) {
    std::ifstream in(std::string(AEROFORM_SAMPLES_DIR) + "/half_sphere.igs");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    int seen = 0;
    for (std::string& l : lines) {
        if (l.size() < 73 || l[72] != 'P' || std::stoi(l.substr(64, 8)) != 1) continue;
        std::string data = l.substr(0, 64);
        std::vector<std::string> parts;
        std::stringstream ss(data);
        for (std::string t; std::getline(ss, t, ',');) parts.push_back(t);
        const bool trailingComma = data.find_last_not_of(' ') != std::string::npos && data[data.find_last_not_of(' ')] == ',';
        int real = static_cast<int>(parts.size());
        while (real > 0 && parts[real - 1].find_first_not_of(' ') == std::string::npos) --real;
        if (index < seen + real) {
            parts[index - seen] = value;
            std::string joined;
            for (int k = 0; k < real; ++k) joined += parts[k] + (k + 1 < real || trailingComma ? "," : "");
            if (joined.size() > 64) throw std::runtime_error("value too long for the line");
            l = joined + std::string(64 - joined.size(), ' ') + l.substr(64);
            break;
        }
        seen += real;
    }
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

void expectRefused(const std::string& text, const std::string& name, const std::string& fragment) {
    const std::string path = outputPath(name);
    std::ofstream(path) << text;
    try {
        (void)cad::readIges(path);
        ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("entity 1 (type 128"), std::string::npos) << e.what();
    }
}

}  // namespace

// Entity 128 is checked against its own counts before OCCT reads it (its reader crashed on a
// degree of 999999999 or K1 = 1000 with data for 6 x 6), and a weight of 0, -1 or 1e-300 is
// refused (it became a polynomial surface without a word; issue #20).
TEST(Iges, BSplineSurfacesWithCountsOrWeightsTheirDataCannotHaveAreRefused) {
    EXPECT_NO_THROW((void)cad::readIges(std::string(AEROFORM_SAMPLES_DIR) + "/half_sphere.igs"));
    expectRefused(withFirstEntityParameter(3, "999999999"), "deg.igs", "degrees 999999999, 3 outside [1, 25]");
    expectRefused(withFirstEntityParameter(1, "1000"), "k1.igs", "need 25053 parameters");
    expectRefused(withFirstEntityParameter(2, "2.5"), "kfrac.igs", "must be non-negative integers");
    // Parameters 10.. are the 10 + 10 knots, then the 36 weights (parameter 30 is the first).
    for (const char* w : {"0.0", "-1.0", "1.0D-300"}) expectRefused(withFirstEntityParameter(30, w), "w.igs", std::string("weight 1 is ") + w);
}

}  // namespace aero::cad
