// IGES adapter: exact write -> read round trips, the read report, and every bad input
// throwing the right aero exception with the file named in the message.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <BRepBuilderAPI_MakeFace.hxx>
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

#include "RandomNurbs.h"
#include "cad/Iges.h"
#include "common/Error.h"
#include "geometry/HalfSphere.h"
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
    IgesReadReport report;
    const PatchSet back = readIges(path, &report);
    EXPECT_EQ(back.source, path);
    EXPECT_EQ(report.faces, set.size());
    EXPECT_EQ(report.converted, 0);
    EXPECT_EQ(report.trimmed, 0);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_EQ(back.size(), set.size());
    ASSERT_EQ(back.names.size(), set.patches.size());
    for (int k = 0; k < set.size(); ++k) {
        EXPECT_EQ(back.names[k], "face " + std::to_string(k + 1));
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

TEST(Iges, RationalWithEqualWeightsReadsBackPolynomial) {
    // OCCT drops weights that are all equal: the same surface, now stored as polynomial.
    std::mt19937 rng(11);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 2, 3, 4, 6, true));
    std::fill(set.patches[0].weights.begin(), set.patches[0].weights.end(), 1.0);
    const std::string path = outputPath("equal_weights.igs");
    writeIges(set, path);
    const PatchSet back = readIges(path);
    ASSERT_EQ(back.size(), 1);
    EXPECT_FALSE(back.patches[0].rational());
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

    IgesReadReport report;
    const PatchSet set = readIges(path, &report);
    ASSERT_EQ(set.size(), 3);
    EXPECT_EQ(report.faces, 3);
    EXPECT_EQ(report.converted, 2);
    EXPECT_EQ(report.trimmed, 1);
    std::string all;
    for (const std::string& w : report.warnings) all += w + "\n";
    EXPECT_NE(all.find("face 1: Geom_Plane converted"), std::string::npos) << all;
    EXPECT_NE(all.find("face 2: trimmed"), std::string::npos) << all;
    EXPECT_NE(all.find("face 3: Geom_CylindricalSurface converted"), std::string::npos) << all;
    EXPECT_NE(all.find("face 3: periodic"), std::string::npos) << all;

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

TEST(Iges, OverflowingCoordinateIsAGeometryErrorNamingFileAndPatch) {
    std::mt19937 rng(6);
    PatchSet set;
    set.patches.push_back(test::randomSurface(rng, 2, 2, 4, 4, false));
    const Patch& p = set.patches[0];
    const std::string path = outputPath("overflow.igs");
    writeIges(set, path);
    const int firstPole =
        10 + static_cast<int>(p.knotsU.size() + p.knotsV.size()) + p.controlCount() + 1;
    writeText(path, replaceParameter(readText(path), firstPole, "1.0E+999"));
    const std::string m = messageOf<GeometryError>([&] { readIges(path); });
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find("face 1"), std::string::npos) << m;
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
