// End-to-end tests of aeroform-cli: exit codes, clean machine-readable stdout, clear errors.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/Trim.h"
#include "io/PatchSetJson.h"

namespace {

struct Result {
    int code = -1;
    std::string out, err;
};

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string tmp(const std::string& name) { return std::string(AEROFORM_TEST_OUTPUT_DIR) + "/cli_" + name; }

Result run(const std::string& args, const char* program = AEROFORM_CLI) {
    static int counter = 0;
    const std::string base = tmp("run" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    const std::string cmd = std::string("'") + program + "' " + args + " > '" + base + ".out' 2> '" + base + ".err' < /dev/null";
    const int status = std::system(cmd.c_str());
    Result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(base + ".out");
    r.err = slurp(base + ".err");
    return r;
}

const std::string kSamples = AEROFORM_SAMPLES_DIR;

// Starts aeroform-cli with `args` in a child process (stdout and stderr to /dev/null) and returns
// its pid, for tests that kill it.
pid_t spawnCli(const std::vector<std::string>& args) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int devnull = ::open("/dev/null", O_WRONLY);
        ::dup2(devnull, 1);
        ::dup2(devnull, 2);
        std::vector<char*> argv{const_cast<char*>(AEROFORM_CLI)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(AEROFORM_CLI, argv.data());
        ::_exit(127);
    }
    return pid;
}

}  // namespace

TEST(Cli, InfoJsonOnTheShippedSamples) {
    for (const std::string file : {"half_sphere.json", "half_sphere.igs"}) {
        const Result r = run("info '" + kSamples + "/" + file + "' --json");
        ASSERT_EQ(r.code, 0) << r.err;
        // Nothing but one JSON object on stdout (OpenCASCADE's console output included).
        nlohmann::json j;
        ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << "stdout: " << r.out;
        EXPECT_EQ(j["patches"], 20);
        EXPECT_EQ(j["control_points"], 720);
        EXPECT_EQ(j["unique_control_points"], 521);
        EXPECT_EQ(j["max_edge_gap"], 0.0);
        EXPECT_EQ(j["shared_edges"], 36);
        EXPECT_EQ(j["free_edges"], 8);
        EXPECT_NEAR(j["bbox"]["min"][1].get<double>(), 0.0, 0.0);
        EXPECT_NEAR(j["bbox"]["max"][1].get<double>(), 1.0, 0.05);
    }
}

TEST(Cli, SampleGeneratesTheShippedGeometryExactly) {
    const Result r = run("sample half-sphere -o '" + tmp("hs.json") + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_LT(j["max_radial_deviation"].get<double>(), 2e-4);
    const auto made = aero::io::readPatchSetJson(tmp("hs.json"));
    const auto shipped = aero::io::readPatchSetJson(kSamples + "/half_sphere.json");
    ASSERT_EQ(made.size(), shipped.size());
    for (int p = 0; p < made.size(); ++p) EXPECT_EQ(made.patches[p].points, shipped.patches[p].points);
}

TEST(Cli, ConvertRoundTripThroughIgesIsExact) {
    ASSERT_EQ(run("convert '" + kSamples + "/half_sphere.json' -o '" + tmp("hs.igs") + "'").code, 0);
    ASSERT_EQ(run("convert '" + tmp("hs.igs") + "' -o '" + tmp("hs_back.json") + "'").code, 0);
    const auto a = aero::io::readPatchSetJson(kSamples + "/half_sphere.json");
    const auto b = aero::io::readPatchSetJson(tmp("hs_back.json"));
    ASSERT_EQ(a.size(), b.size());
    for (int p = 0; p < a.size(); ++p) {
        EXPECT_EQ(a.patches[p].points, b.patches[p].points);
        EXPECT_EQ(a.patches[p].knotsU, b.patches[p].knotsU);
        EXPECT_EQ(a.patches[p].weights, b.patches[p].weights);
    }
}

namespace {

/// One IGES line: 72 columns of data, the section letter, a 7-digit sequence number.
std::string igesLine(const std::string& data, char section, int seq) {
    char tail[9];
    std::snprintf(tail, sizeof tail, "%c%07d", section, seq);
    return data + std::string(72 - data.size(), ' ') + tail + "\n";
}

/// A hand-written IGES file in metres: a bilinear B-spline surface (128), a point (116) and a
/// CSG block (150, which Aeroform cannot read: a warning).
std::string metreFileWithAPointAndABlock() {
    std::string f;
    f += igesLine("Aeroform CLI test", 'S', 1);
    f += igesLine("1H,,1H;,4Htest,5Hm.igs,4Htest,4Htest,32,38,6,308,15,4Htest,1.0,", 'G', 1);
    f += igesLine("6,1HM,1,1.0,15H20260101.000000,1.0E-8,10.0,2Hme,2Hme,11,0,", 'G', 2);
    f += igesLine("15H20260101.000000;", 'G', 3);
    const char* d[] = {"     128       1       0       0       0       0       0       000000000",
                       "     128       0       0       2       0                               0",
                       "     116       3       0       0       0       0       0       000000000",
                       "     116       0       0       1       0                               0",
                       "     150       4       0       0       0       0       0       000000000",
                       "     150       0       0       1       0                               0"};
    for (int k = 0; k < 6; ++k) f += igesLine(d[k], 'D', k + 1);
    auto p = [&](const std::string& data, int de, int seq) {
        char ptr[9];
        std::snprintf(ptr, sizeof ptr, "%8d", de);
        f += igesLine(data + std::string(64 - data.size(), ' ') + ptr, 'P', seq);
    };
    p("128,1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,", 1, 1);
    p("0.1,0.,0.,5.1,0.,0.,0.1,2.5,0.,5.1,2.5,0.25,0.,1.,0.,1.;", 1, 2);
    p("116,1.,2.,3.;", 3, 3);
    p("150,1.,1.,1.,0.,0.,0.,1.,0.,0.,0.,0.,1.;", 5, 4);
    f += igesLine("S0000001G0000003D0000006P0000004", 'T', 1);
    return f;
}

}  // namespace

// info: the file's unit, what was read and what was ignored (with the directory entries and the
// reasons), warnings on stderr, --strict turning them into exit code 1.
TEST(Cli, InfoReportsUnitReadAndIgnoredEntitiesAndStrictFailsOnWarnings) {
    const std::string path = tmp("m_point_block.igs");
    std::ofstream(path) << metreFileWithAPointAndABlock();
    Result r = run("info '" + path + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["format"], "IGES");
    EXPECT_EQ(j["unit"], "m");
    EXPECT_EQ(j["unit_source"], "IGES unit flag 6 ('M')");
    EXPECT_EQ(j["patches"], 1);
    EXPECT_EQ(j["trimmed_patches"], 0);
    ASSERT_EQ(j["read"].size(), 1u);
    EXPECT_EQ(j["read"][0]["type"], 128);
    EXPECT_EQ(j["read"][0]["outcome"], "kept as NURBS exactly");
    EXPECT_EQ(j["read"][0]["entities"], nlohmann::json::array({1}));
    ASSERT_EQ(j["ignored"].size(), 2u);
    EXPECT_EQ(j["ignored"][0]["de"], 3);
    EXPECT_EQ(j["ignored"][0]["type"], 116);
    EXPECT_EQ(j["ignored"][0]["reason"], "a point, not a surface");
    EXPECT_EQ(j["ignored"][1]["de"], 5);
    EXPECT_EQ(j["ignored"][1]["reason"], "a CSG solid: not supported");
    ASSERT_EQ(j["warnings"].size(), 1u);
    EXPECT_EQ(j["bbox"]["max"][0], 5.1);  // metres, as written
    EXPECT_NE(r.err.find("warning: entity 3 (type 150, directory line 5) (entity type 150) ignored: a CSG solid"), std::string::npos)
        << r.err;
    // The text form.
    r = run("info '" + path + "'");
    ASSERT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("unit             m (metre, IGES unit flag 6 ('M')); coordinates as written in the file"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("read             128 rational B-spline surface: 1 kept as NURBS exactly (DE 1)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("ignored          116 point: 1 (DE 3): a point, not a surface"), std::string::npos) << r.out;
    // --strict: the same output, exit 1.
    r = run("info '" + path + "' --strict");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--strict"), std::string::npos) << r.err;
    // convert --strict writes nothing.
    std::filesystem::remove(tmp("strict_out.json"));
    r = run("convert '" + path + "' '" + tmp("strict_out.json") + "' --strict");
    EXPECT_EQ(r.code, 1);
    EXPECT_FALSE(std::filesystem::exists(tmp("strict_out.json")));
}

// convert keeps the unit and the values unless --units asks; IN OUT and IN -o OUT both work;
// STEP out and back keeps unit, values and trims.
TEST(Cli, ConvertKeepsOrConvertsUnitsAndGoesThroughStep) {
    const std::string in = tmp("m_point_block.igs");
    std::ofstream(in) << metreFileWithAPointAndABlock();
    ASSERT_EQ(run("convert '" + in + "' '" + tmp("m.json") + "'").code, 0);
    const auto m = aero::io::readPatchSetJson(tmp("m.json"));
    EXPECT_EQ(m.unit, "m");
    EXPECT_EQ(m.patches[0].points[3], 5.1);
    Result r = run("convert '" + tmp("m.json") + "' -o '" + tmp("mm.json") + "' --units mm");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("converted coordinates from m to mm (factor 1000)"), std::string::npos) << r.err;
    const auto mm = aero::io::readPatchSetJson(tmp("mm.json"));
    EXPECT_EQ(mm.unit, "mm");
    for (std::size_t k = 0; k < m.patches[0].points.size(); ++k) EXPECT_EQ(mm.patches[0].points[k], 1000.0 * m.patches[0].points[k]);
    EXPECT_EQ(run("convert '" + tmp("m.json") + "' '" + tmp("x.json") + "' --units furlong").code, 2);
    EXPECT_EQ(run("convert '" + tmp("m.json") + "' '" + tmp("x.json") + "' extra").code, 2);

    // A trimmed patch in inches through STEP and IGES.
    aero::geometry::PatchSet t = m;
    t.unit = "in";
    t.trims.resize(1);
    t.trims[0].outer = aero::geometry::rectangleLoop(0.25, 0.75, 0.0, 0.5);
    aero::io::writePatchSetJson(t, tmp("in_trimmed.json"));
    for (const std::string ext : {"stp", "igs"}) {
        r = run("convert '" + tmp("in_trimmed.json") + "' '" + tmp("in_trimmed." + ext) + "'");
        ASSERT_EQ(r.code, 0) << r.err;
        r = run("info '" + tmp("in_trimmed." + ext) + "' --json");
        ASSERT_EQ(r.code, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["unit"], "in") << ext;
        EXPECT_EQ(j["trimmed_patches"], 1) << ext;
        EXPECT_NEAR(j["bbox"]["min"][0].get<double>(), 0.1 + 0.25 * 5.0, 1e-12) << ext;  // the trimmed surface
        EXPECT_EQ(j["control_bbox"]["max"][0], 5.1) << ext;
        ASSERT_EQ(run("convert '" + tmp("in_trimmed." + ext) + "' '" + tmp("in_back_" + ext + ".json") + "'").code, 0);
        const auto back = aero::io::readPatchSetJson(tmp("in_back_" + ext + ".json"));
        EXPECT_EQ(back.patches[0].points, t.patches[0].points) << ext;
        EXPECT_EQ(back.unit, "in") << ext;
    }
}

TEST(Cli, BadInputGivesAClearErrorAndExitCode1) {
    Result r = run("info '" + tmp("missing.igs") + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("missing.igs"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty());

    std::ofstream(tmp("garbage.igs")) << "this is not an IGES file\n";
    r = run("info '" + tmp("garbage.igs") + "' --json");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("garbage.igs"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;

    std::ofstream(tmp("bad.json")) << R"({"format": "aeroform.patchset", "version": 1, "patches": [{"degree": [1, 1], "count": [2, 2], "knots_u": [0, 0.5, 0, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}]})";
    r = run("info '" + tmp("bad.json") + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("bad.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("patch 1"), std::string::npos) << r.err;
}

TEST(Cli, UsageErrorsExitWith2AndHelpWorksEverywhere) {
    EXPECT_EQ(run("").code, 2);
    EXPECT_EQ(run("frobnicate").code, 2);
    EXPECT_EQ(run("info").code, 2);
    EXPECT_EQ(run("info a b").code, 2);
    EXPECT_EQ(run("info x.json --colour").code, 2);
    EXPECT_EQ(run("sample sphere -o x.json").code, 2);
    EXPECT_EQ(run("sample half-sphere").code, 2);
    EXPECT_EQ(run("sample half-sphere -o x.json --radius -1").code, 2);
    EXPECT_EQ(run("convert in.json").code, 2);
    EXPECT_EQ(run("info x.json --strict --bogus").code, 2);
    for (const char* cmd : {"--help", "info --help", "sample --help", "convert --help"}) {
        const Result r = run(cmd);
        EXPECT_EQ(r.code, 0) << cmd;
        EXPECT_NE(r.out.find("usage:"), std::string::npos) << cmd;
    }
}

namespace {

// Outputs of a case resolve against the case file's folder (the test output folder).
std::string outputPath(const std::string& rel) { return std::string(AEROFORM_TEST_OUTPUT_DIR) + "/" + rel; }

std::string writeCase(const std::string& name, const std::string& body) {
    const std::string path = tmp(name);
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": ")" << kSamples << "/half_sphere.igs\", " << body
                        << "}";
    return path;
}

}  // namespace

TEST(Cli, DeformTheSampleCaseWritesExactGeometryAndVtk) {
    const std::string c = writeCase("bwb.json", R"(
        "lattices": [{"name": "body", "counts": [6, 6, 2], "degrees": [3, 3, 1], "padding": [0.05, 0.0, 0.05]}],
        "design_variables": {"stations": [{"lattice": "body", "direction": 1, "bits": ["001","011","011","011","011","011"],
                                           "translation_bound": 3}]},
        "values": {"body.S5.ty": 1.5, "body.S4.ty": 0.8, "body.S5.taperx": 0.6},
        "constraints": {"station_gap": 0.05, "station_second_difference": 0.5, "min_volume": "initial"},
        "output": {"geometry": "cli_deformed/bwb.igs", "vtk": "cli_deformed/bwb.vtm"})");
    const Result r = run("deform '" + c + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["embedded_points"], 521);
    EXPECT_EQ(j["points_outside"], 0);
    EXPECT_EQ(j["design_variables"], 89);
    EXPECT_LE(j["max_embedding_error"].get<double>(), 1e-12);
    EXPECT_TRUE(j["injective"].get<bool>());
    EXPECT_GT(j["min_jacobian"].get<double>(), 0.0);
    EXPECT_GT(j["volume"].get<double>(), j["initial_volume"].get<double>());
    EXPECT_EQ(j["constraints"]["symmetry_max_offset"], 0.0);
    EXPECT_EQ(j["constraints"]["station_gap_violations"], 0);
    // Stations 2, 3, 4 move by 0, 0 and 0.8 in y: the lattice bends by 0.8 at station 3.
    EXPECT_NEAR(j["constraints"]["largest_station_second_difference"].get<double>(), 0.8, 1e-12);
    EXPECT_NE(j["constraints"]["largest_station_second_difference_at"].get<std::string>().find("[3, point 18, y]"),
              std::string::npos);
    EXPECT_FALSE(j["constraints"]["station_second_difference_ok"].get<bool>());
    // The planform: the sphere's half-disk, then the tip station moved 1.5 outboard.
    EXPECT_NEAR(j["initial_planform"]["half_span"].get<double>(), 1.0, 1e-4);
    EXPECT_NEAR(j["initial_planform"]["projected_area"].get<double>(), M_PI / 2, 1e-3);
    EXPECT_TRUE(j["planform"]["half_body"].get<bool>());
    EXPECT_GT(j["planform"]["half_span"].get<double>(), 2.0);
    EXPECT_GT(j["planform"]["aspect_ratio"].get<double>(), j["initial_planform"]["aspect_ratio"].get<double>());
    // The deformed IGES holds the same patch structure, stretched spanwise.
    const Result info = run("info '" + outputPath("cli_deformed/bwb.igs") + "' --json");
    ASSERT_EQ(info.code, 0) << info.err;
    const auto ji = nlohmann::json::parse(info.out);
    EXPECT_EQ(ji["patches"], 20);
    EXPECT_EQ(ji["max_edge_gap"], 0.0);
    EXPECT_GT(ji["bbox"]["max"][1].get<double>(), 2.0);
    EXPECT_FALSE(slurp(outputPath("cli_deformed/bwb.vtm")).empty());
}

// A trimmed geometry in inches: deform embeds and moves the whole base nets and writes the
// trimmed patches (in inches) back; the mesh refuses, naming the trimmed patch.
TEST(Cli, TrimmedGeometryDeformsButIsNotMeshed) {
    aero::geometry::PatchSet set = aero::io::readPatchSetJson(kSamples + "/half_sphere.json");
    set.unit = "in";
    set.trims.resize(static_cast<std::size_t>(set.size()));
    const auto& p = set.patches[3];
    const double u0 = p.knotsU.front(), u1 = p.knotsU.back(), v0 = p.knotsV.front(), v1 = p.knotsV.back();
    set.trims[3].outer = aero::geometry::rectangleLoop(u0, 0.5 * (u0 + u1), v0, v1);
    aero::io::writePatchSetJson(set, tmp("trimmed_sphere.json"));
    const std::string lattice = R"("lattices": [{"name": "body", "counts": [6, 6, 2], "degrees": [3, 3, 1], "padding": [0.05, 0.0, 0.05]}],
        "design_variables": {"stations": [{"lattice": "body", "direction": 1, "bits": ["001","011","011","011","011","011"],
                                           "translation_bound": 3}]},
        "values": {"body.S5.ty": 0.5})";
    const std::string c = tmp("trimmed_case.json");
    std::ofstream(c) << R"({"format": "aeroform.case", "version": 1, "geometry": ")" << tmp("trimmed_sphere.json") << "\", " << lattice
                     << R"(, "output": {"geometry": "cli_trimmed/deformed.igs"}})";
    Result r = run("deform '" + c + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["embedded_points"], 521);
    EXPECT_TRUE(j["volume"].is_null());  // not computed over trimmed patches
    EXPECT_TRUE(j["planform"].is_null());
    EXPECT_NE(r.err.find("enclosed volume not computed (1 trimmed patches)"), std::string::npos) << r.err;
    r = run("info '" + outputPath("cli_trimmed/deformed.igs") + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto ji = nlohmann::json::parse(r.out);
    EXPECT_EQ(ji["unit"], "in");
    EXPECT_EQ(ji["trimmed_patches"], 1);
    ASSERT_EQ(ji["read"].size(), 2u);
    EXPECT_EQ(ji["read"][0]["type"], 128);
    EXPECT_EQ(ji["read"][0]["count"], 19);
    EXPECT_EQ(ji["read"][1]["type"], 144);
    EXPECT_EQ(ji["read"][1]["outcome"], "kept with trimming, exactly");
    // The mesh level needs untrimmed patches.
    const std::string m = tmp("trimmed_mesh.json");
    std::ofstream(m) << R"({"format": "aeroform.case", "version": 1, "geometry": ")" << tmp("trimmed_sphere.json") << "\", " << lattice
                     << R"(, "mesh": {"level": "coarse", "refine": 0.3}})";
    r = run("mesh '" + m + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("needs untrimmed patches: patch 4 ('Y+-4') of '" + tmp("trimmed_sphere.json") + "' is trimmed"),
              std::string::npos)
        << r.err;
}

TEST(Cli, DeformRefusesAFoldedLatticeAndWritesNothing) {
    std::filesystem::remove_all(outputPath("cli_fold"));
    const std::string c = writeCase("fold.json", R"(
        "lattices": [{"name": "body", "counts": [6, 6, 2], "degrees": [3, 3, 1]}],
        "displacements": [{"index": [2, 2, 0], "delta": [1.5, 0, 0]}, {"index": [2, 2, 1], "delta": [1.5, 0, 0]},
                          {"index": [2, 3, 0], "delta": [1.5, 0, 0]}, {"index": [2, 3, 1], "delta": [1.5, 0, 0]}],
        "output": {"geometry": "cli_fold/out.igs"})");
    const Result r = run("deform '" + c + "' --json");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("not injective"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("fold.json"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty());
    EXPECT_FALSE(std::filesystem::exists(outputPath("cli_fold/out.igs")));
}

TEST(Cli, DeformReportsPointsOutsideTheLattice) {
    const std::string body = R"("lattices": [{"box": {"origin": [-1.1, -0.1, -1.1], "size": [2.2, 1.2, 1.6]}}])";
    Result r = run("deform '" + writeCase("outside.json", body) + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("outside every lattice"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("allow_outside"), std::string::npos) << r.err;
    r = run("deform '" + writeCase("outside_ok.json", body + R"(, "embedding": {"allow_outside": true})") + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["points_outside"].get<int>(), 0);
    EXPECT_EQ(j["embedded_points"].get<int>() + j["points_outside"].get<int>(), 521);
}

TEST(Cli, DeformCaseErrorsNameTheKey) {
    const Result r = run("deform '" + writeCase("badkey.json", R"("lattices": [{"counts": [6, 6, 2], "degree": [3, 3, 1]}])") + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("lattices[0].degree: unknown key"), std::string::npos) << r.err;
    EXPECT_EQ(run("deform").code, 2);
    EXPECT_EQ(run("deform --help").code, 0);
}

TEST(Cli, MeshTheBlendedWingSampleGivesAValidGrid) {
    // The shipped sample deforms the half-sphere towards a blended-wing-body; the moved grid
    // must stay valid. Outputs are redirected into the test folder.
    std::ifstream in(kSamples + "/bwb_deform.json");
    nlohmann::json c = nlohmann::json::parse(in);
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["output"] = {{"mesh_vtk", "cli_mesh/grid.vtm"}, {"plot3d", "cli_mesh/grid.xyz"}};
    const std::string path = tmp("bwb_mesh.json");
    std::ofstream(path) << c.dump();
    const Result r = run("mesh '" + path + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["blocks"], 20);
    EXPECT_EQ(j["control_nodes"], 521 * 12);
    EXPECT_EQ(j["grid_nodes"], 20 * 17 * 17 * 17);
    EXPECT_EQ(j["increments"], 6);
    EXPECT_GT(j["cg_iterations"].get<int>(), 0);
    EXPECT_GT(j["min_jacobian"].get<double>(), 0.0);
    EXPECT_GT(j["min_scaled_jacobian"].get<double>(), 0.1);
    EXPECT_EQ(j["non_positive_cells"], 0);
    EXPECT_TRUE(j["deformed"].get<bool>());
    EXPECT_TRUE(std::filesystem::exists(outputPath("cli_mesh/grid.xyz")));
    // Progress goes to stderr, one line per increment.
    EXPECT_NE(r.err.find("moving the control grid: increment 6 of 6"), std::string::npos) << r.err;
}

TEST(Cli, MeshWithoutDeformationAndBatchMode) {
    const std::string c = writeCase("plain_mesh.json", R"("mesh": {"level": "coarse", "refine": 0.5})");
    const Result r = run("mesh '" + c + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["deformed"].get<bool>());
    EXPECT_EQ(j["grid_nodes"], 20 * 9 * 9 * 9);  // half the intervals of the coarse level
    EXPECT_EQ(run("mesh '" + writeCase("bad_mesh.json", R"("mesh": {"level": "gigantic"})") + "'").code, 1);
    EXPECT_EQ(run("mesh '" + writeCase("bad_mesh2.json", R"("mesh": {"poisson": 0.5})") + "'").code, 1);
}

TEST(Cli, FitAPlot3dGridReproducesTheAnalyticGrid) {
    // Write the coarse half-sphere grid as Plot3D, then fit it with the generator's own control
    // counts: the B-spline grid is reproduced (to round-off where parameters match, and to a
    // small error with chord-length parameters).
    const std::string c = writeCase("fit_mesh.json", R"("mesh": {"level": "coarse"}, "output": {"plot3d": "cli_fit/grid.xyz"})");
    ASSERT_EQ(run("mesh '" + c + "'").code, 0);
    const Result r = run("fit '" + outputPath("cli_fit/grid.xyz") + "' --counts 6,6,12 --json --refit '" +
                         outputPath("cli_fit/refit.xyz") + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["blocks"].size(), 20u);
    EXPECT_EQ(j["grid_nodes"], 20 * 17 * 17 * 17);
    EXPECT_LT(j["max_error"].get<double>(), 2e-3);  // measured 6.9e-4 (radius-20 domain): chord-length vs the generator's parameters
    EXPECT_TRUE(std::filesystem::exists(outputPath("cli_fit/refit.xyz")));
    EXPECT_EQ(run("fit '" + outputPath("cli_fit/grid.xyz") + "' --counts 6,6").code, 2);
    EXPECT_EQ(run("fit '" + tmp("missing.xyz") + "'").code, 1);
}

// The flow command on a small grid of the sample: a run stopped by its iteration limit fails
// (exit 1) but keeps its state; --restart continues the same run (iterations and residual
// history carry on) and converges; a restart from another grid is refused naming the file.
TEST(Cli, FlowStopsKeepsItsStateAndResumesFromTheRestart) {
    const std::string mesh = R"("mesh": {"level": "coarse", "refine": 0.5, "grid_wall_spacing": 0.05, "farfield_radius": 5})";
    const std::string outputs =
        R"("output": {"flow_vtk": "cli_flow/solution.vtm", "residual_csv": "cli_flow/residual.csv", "restart": "cli_flow/state.restart"})";
    std::filesystem::remove_all(outputPath("cli_flow"));
    const std::string partial = writeCase("flow_partial.json", mesh + R"(, "flow": {"mach": 0.5, "max_iterations": 6}, )" + outputs);
    const Result a = run("flow '" + partial + "' --json");
    ASSERT_EQ(a.code, 1) << a.err;  // not converged: a failure, with the reason
    const auto ja = nlohmann::json::parse(a.out);
    EXPECT_FALSE(ja["converged"].get<bool>());
    EXPECT_EQ(ja["status"], "max-iterations");
    EXPECT_EQ(ja["newton_iterations"], 6);
    EXPECT_EQ(ja["grid_nodes"], 14580);
    for (const char* key : {"orders_reduced", "linear_iterations", "CL", "CD", "CM", "seconds", "peak_memory_mb"}) {
        EXPECT_TRUE(ja.contains(key)) << key;
    }
    EXPECT_GT(ja["peak_memory_mb"].get<double>(), 1.0);
    EXPECT_NE(a.err.find("iter    6"), std::string::npos) << a.err;  // a progress line per iteration
    EXPECT_NE(a.err.find("not converged in 6 iterations"), std::string::npos) << a.err;
    EXPECT_TRUE(std::filesystem::exists(outputPath("cli_flow/state.restart")));
    EXPECT_TRUE(std::filesystem::exists(outputPath("cli_flow/solution.vtm")));

    const std::string full = writeCase("flow_full.json", mesh + R"(, "flow": {"mach": 0.5, "max_iterations": 300}, )" + outputs);
    const Result b = run("flow '" + full + "' --restart '" + outputPath("cli_flow/state.restart") + "' --json");
    ASSERT_EQ(b.code, 0) << b.err;
    const auto jb = nlohmann::json::parse(b.out);
    EXPECT_TRUE(jb["converged"].get<bool>());
    EXPECT_EQ(jb["initial_residual"], ja["initial_residual"]);  // the same run, continued
    EXPECT_GE(jb["orders_reduced"].get<double>(), 10.0);
    EXPECT_EQ(jb["total_iterations"].get<int>(), 6 + jb["newton_iterations"].get<int>());
    EXPECT_LT(std::abs(jb["CL"].get<double>()), 1e-8);  // alpha 0: no lift by symmetry
    EXPECT_GT(jb["CD"].get<double>(), 0.0);
    // The residual history continues the iteration count of the first run.
    std::istringstream csv(slurp(outputPath("cli_flow/residual.csv")));
    std::string header, row;
    std::getline(csv, header);
    std::getline(csv, row);
    EXPECT_EQ(row.rfind("7,", 0), 0u) << row;

    // A restart written for another grid is refused, naming the file and the block.
    const std::string finer = writeCase("flow_finer.json", R"("mesh": {"level": "coarse", "refine": 0.75}, "flow": {})");
    const Result c = run("flow '" + finer + "' --restart '" + outputPath("cli_flow/state.restart") + "'");
    EXPECT_EQ(c.code, 1);
    EXPECT_NE(c.err.find("state.restart"), std::string::npos) << c.err;
    EXPECT_NE(c.err.find("nodes in the file"), std::string::npos) << c.err;
    EXPECT_NE(c.err.find("not another sampling of this grid"), std::string::npos) << c.err;
    // The same grid at another mesh.refine (here coarser, 2,500 nodes): interpolated as the start.
    const std::string coarser = writeCase("flow_coarser.json", R"("mesh": {"level": "coarse", "refine": 0.25, "grid_wall_spacing": 0.05, "farfield_radius": 5}, "flow": {"mach": 0.5, "max_iterations": 2})");
    const Result d = run("flow '" + coarser + "' --restart '" + outputPath("cli_flow/state.restart") + "' --json");
    ASSERT_FALSE(d.out.empty()) << d.err;
    const auto jd = nlohmann::json::parse(d.out);
    EXPECT_EQ(jd["restart_interpolated_from_nodes"], 14580);
    EXPECT_LT(jd["grid_nodes"].get<long>(), 14580);
    EXPECT_NE(d.err.find("interpolated onto its"), std::string::npos) << d.err;
    EXPECT_EQ(run("flow").code, 2);
    EXPECT_EQ(run("flow '" + partial + "' --restart").code, 2);
    EXPECT_EQ(a.err.find("spacing jumps"), std::string::npos) << a.err;  // this grid is fine (1.4)
    EXPECT_NEAR(ja["largest_spacing_jump"].get<double>(), 1.42, 0.01);
}

// The times of a flow are told apart: the command, the flow stage (metrics, grid sequencing's
// pre-solves, every solve of the case's grid) and its last solve, so a comparison with another
// solver times the whole flow, not only the last solve (the 75k half-sphere: 9.9 s solver, 10.9 s
// flow). Here the 14,580-node grid is sequenced through 2,500 nodes (sequencing_nodes 2000).
TEST(Cli, FlowTellsTheGridSequencingsTimeApart) {
    const std::string mesh = R"("mesh": {"level": "coarse", "refine": 0.5, "grid_wall_spacing": 0.05, "farfield_radius": 5})";
    const std::string sequenced =
        writeCase("flow_sequenced.json", mesh + R"(, "flow": {"mach": 0.5, "sequencing_nodes": 2000})");
    const Result a = run("flow '" + sequenced + "' --json");
    ASSERT_EQ(a.code, 0) << a.err;
    const auto ja = nlohmann::json::parse(a.out);
    ASSERT_TRUE(ja.contains("grid_sequencing")) << a.out;
    EXPECT_EQ(ja["grid_sequencing"]["levels"][0]["status"], "converged");
    EXPECT_TRUE(ja["grid_sequencing"]["started_from_them"].get<bool>());
    const double sequencing = ja["seconds_sequencing"], solve = ja["seconds_solve"], flowStage = ja["seconds_flow"];
    EXPECT_GT(sequencing, 0.0);
    EXPECT_GE(flowStage, sequencing + solve);
    EXPECT_GE(ja["seconds"].get<double>(), flowStage);
    EXPECT_NE(a.err.find(" s, of it grid sequencing "), std::string::npos) << a.err;

    const std::string plain = writeCase("flow_plain.json", mesh + R"(, "flow": {"mach": 0.5, "max_iterations": 2, "stall_modes": false})");
    const Result b = run("flow '" + plain + "' --json");
    ASSERT_FALSE(b.out.empty()) << b.err;
    const auto jb = nlohmann::json::parse(b.out);
    EXPECT_FALSE(jb.contains("grid_sequencing"));
    EXPECT_EQ(jb["seconds_sequencing"].get<double>(), 0.0);
    EXPECT_GE(jb["seconds_flow"].get<double>(), jb["seconds_solve"].get<double>());
    EXPECT_NE(b.err.find(" s, of it the solver "), std::string::npos) << b.err;
}

// Issue #20: `flow` killed with SIGKILL at random moments (a fixed seed) loses at most one
// checkpoint's work: the restart file on disk is always a complete one (old or new, never
// half-written), each run continues the previous one's iterations, and the end result is the
// uninterrupted run's. A converged run leaves no checkpoint file behind when it created it.
TEST(Cli, FlowKilledAtRandomMomentsContinuesFromItsCheckpoint) {
    const std::string mesh = R"("mesh": {"level": "coarse", "refine": 0.5, "grid_wall_spacing": 0.05, "farfield_radius": 5})";
    const std::string flowKeys = R"(, "flow": {"mach": 0.5, "alpha": 1.0, "checkpoint_seconds": 0})";
    std::filesystem::remove_all(outputPath("cli_flowkill"));
    std::filesystem::create_directories(outputPath("cli_flowkill"));
    const std::string whole = writeCase("flowkill_whole.json", mesh + flowKeys);
    std::filesystem::remove(tmp("flowkill_whole.restart"));
    const Result a = run("flow '" + whole + "' --json");
    ASSERT_EQ(a.code, 0) << a.err;
    const auto ja = nlohmann::json::parse(a.out);
    EXPECT_FALSE(std::filesystem::exists(tmp("flowkill_whole.restart")));  // only protection: gone
    const int wholeIterations = ja["newton_iterations"].get<int>();
    ASSERT_GT(wholeIterations, 6);

    const std::string state = outputPath("cli_flowkill/state.restart");
    const std::string killed = writeCase("flowkill.json", mesh + flowKeys + R"(, "output": {"restart": "cli_flowkill/state.restart"})");
    std::srand(20);  // the moments are random but the same on every run of the test
    int kills = 0, exitedAlone = 0;
    for (int round = 0; round < 4; ++round) {
        const bool resume = std::filesystem::exists(state);
        const pid_t pid = resume ? spawnCli({"flow", killed, "--restart", state}) : spawnCli({"flow", killed});
        ASSERT_GE(pid, 0);
        // Wait for this run's first checkpoint (a new file, or the old one replaced), then a
        // random 0-0.8 s more: the kill lands anywhere, a write in progress included.
        const auto before = resume ? std::filesystem::last_write_time(state) : std::filesystem::file_time_type::min();
        int status = 0;
        bool done = false;
        for (int wait = 0; wait < 3000 && !done; ++wait) {
            std::error_code ec;
            const auto t = std::filesystem::last_write_time(state, ec);
            if (!ec && t != before) break;
            done = ::waitpid(pid, &status, WNOHANG) == pid;
            ::usleep(10000);
        }
        const int extra = std::rand() % 800;
        for (int ms = 0; ms < extra && !done; ms += 10) {
            done = ::waitpid(pid, &status, WNOHANG) == pid;
            ::usleep(10000);
        }
        if (!done) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
            ++kills;
        } else {
            ++exitedAlone;
            ASSERT_TRUE(WIFEXITED(status)) << "round " << round;
            break;
        }
        ASSERT_TRUE(std::filesystem::exists(state)) << "round " << round;
    }
    ASSERT_GT(kills, 0);
    // Whatever the last kill interrupted, the file is a complete restart that continues the run.
    const Result b = run("flow '" + killed + "' --restart '" + state + "' --json");
    ASSERT_EQ(b.code, 0) << b.err;
    const auto jb = nlohmann::json::parse(b.out);
    EXPECT_TRUE(jb["converged"].get<bool>());
    EXPECT_EQ(jb["initial_residual"], ja["initial_residual"]);  // the same run, continued
    EXPECT_GT(jb["total_iterations"].get<int>(), jb["newton_iterations"].get<int>()) << b.err;  // work was kept
    EXPECT_NEAR(jb["CL"].get<double>(), ja["CL"].get<double>(), 1e-7);
    EXPECT_NEAR(jb["CD"].get<double>(), ja["CD"].get<double>(), 1e-7);
    for (const auto& entry : std::filesystem::directory_iterator(outputPath("cli_flowkill"))) {
        const std::string name = entry.path().filename().string();
        EXPECT_EQ(name, "state.restart");  // a write cut by a kill left a .tmp file: the next write removed it
    }
    std::printf("flow killed %d times, %d runs ended on their own; final run %d of %d iterations\n", kills, exitedAlone,
                jb["newton_iterations"].get<int>(), jb["total_iterations"].get<int>());
}

// A grid whose spacing jumps (5 radial nodes from a wall spacing of 1e-4 to the farfield at 20
// radii: the radial cells grow about 30 times from one to the next) is named in a warning before the solve, with block and node.
TEST(Cli, FlowWarnsAboutASpacingJumpBeforeTheSolve) {
    const std::string steep = writeCase(
        "flow_steep.json",
        R"("mesh": {"level": "coarse", "refine": 0.5, "radial_nodes": 9, "grid_wall_spacing": 0.0001}, "flow": {"max_iterations": 1}, "output": {"restart": "cli_flow_steep/state.restart"})");
    const Result r = run("flow '" + steep + "' --json");
    EXPECT_EQ(r.code, 1) << r.err;  // one iteration: not converged
    EXPECT_NE(r.err.find("warning: the grid spacing jumps by a factor 30.5 along k at block "), std::string::npos) << r.err;
    EXPECT_LT(r.err.find("spacing jumps"), r.err.find("iter    1")) << r.err;
    EXPECT_NEAR(nlohmann::json::parse(r.out)["largest_spacing_jump"].get<double>(), 30.46, 0.05);
}

// A solve that stalls is solved again by continuation in the dissipation, and `flow` reports
// every attempt: on stderr as it goes, in the JSON under dissipation_continuation with each
// attempt's status, iterations and relative residual. Here no attempt can converge (a tolerance
// below round-off, 3 iterations without progress count as a stall): the first attempt and the
// 4x, 8x and 16x stages stall, nothing is handed on, and the run fails with the first attempt's result.
TEST(Cli, FlowReportsEveryAttemptOfTheContinuationInTheDissipation) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/bwb_flow.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["flow"]["tolerance"] = 1e-15;
    c["flow"]["stall_iterations"] = 3;
    c["flow"]["stall_modes"] = false;
    c["output"] = nlohmann::json::object();
    const std::string path = tmp("flow_continuation.json");
    std::ofstream(path) << c.dump(1);
    const Result r = run("flow '" + path + "' --json");
    ASSERT_EQ(r.code, 1) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["status"], "stalled");
    ASSERT_TRUE(j.contains("dissipation_continuation")) << r.out;
    const auto& d = j["dissipation_continuation"];
    EXPECT_EQ(d["first_attempt"]["status"], "stalled");
    const double firstRelative = d["first_attempt"]["relative_residual"].get<double>();
    EXPECT_GT(firstRelative, 0.0);
    EXPECT_LT(firstRelative, 1e-9);  // down to round-off, then no progress
    // Nothing converges to continue from: the continuation climbs to 8 and 16 times and stops.
    ASSERT_EQ(d["stages"].size(), 3u) << d.dump();
    const double factors[] = {4.0, 8.0, 16.0};
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(d["stages"][k]["factor"], factors[k]);
        EXPECT_EQ(d["stages"][k]["status"], "stalled");
        EXPECT_GT(d["stages"][k]["iterations"].get<int>(), 3);
        EXPECT_GT(d["stages"][k]["relative_residual"].get<double>(), 0.0);
    }
    // 4 and 8 times go down to round-off first; at 16 times the start-up's slow steps already
    // count as a stall with 3 iterations allowed.
    for (int k = 0; k < 2; ++k) EXPECT_LT(d["stages"][k]["relative_residual"].get<double>(), 1e-9) << d["stages"].dump();
    // The answer is the first attempt's.
    EXPECT_EQ(j["newton_iterations"], d["first_attempt"]["iterations"]);
    EXPECT_NE(r.err.find("continuation in the dissipation from 4 times"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("continuation at 4 times the dissipation (from the free stream): stalled in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("continuation at 16 times the dissipation (from the free stream): stalled in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("solves with more dissipation did not converge either: 4 times: stalled after "), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("(relative residual "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("whether this flow is unsteady: aeroform-cli flow " + path + " --restart "), std::string::npos) << r.err;
}

// aeroform-cli flow --time-accurate on the blended-wing sample at CI size (refine 0.3): from the
// free stream the run writes a row per step and a state; from the converged steady state it
// stays there (the time term vanishes at a steady state) and says the flow settled; bad values
// are usage errors.
TEST(Cli, FlowTimeAccurateWritesTheLiftHistoryAndSaysWhetherTheFlowSettles) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/bwb_flow.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["output"] = nlohmann::json::object();
    const std::string steadyRestart = tmp("time_steady.restart");
    c["output"]["restart"] = steadyRestart;
    const std::string path = tmp("time_case.json");
    std::ofstream(path) << c.dump(1);
    const Result steady = run("flow '" + path + "' --json");
    ASSERT_EQ(steady.code, 0) << steady.err;
    const double cl = nlohmann::json::parse(steady.out)["CL"].get<double>();

    // From the free stream: 6 steps of 0.5, each a row of the history.
    const std::string restart = tmp("time_run.restart");
    c["output"]["restart"] = restart;
    std::ofstream(path) << c.dump(1);
    const std::string history = tmp("time_history.csv");
    std::filesystem::remove(history);
    const Result r = run("flow '" + path + "' --time-accurate 6 --time-step 0.5 --history '" + history + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["completed"].get<bool>());
    // (The impulsive start may halve the first step: at least 6 steps, ending at t = 3.)
    const int steps = j["steps"].get<int>();
    EXPECT_GE(steps, 6);
    EXPECT_EQ(steps > 6, j["halved_steps"].get<int>() > 0);  // more steps only after a halving
    EXPECT_NEAR(j["time"].get<double>(), 3.0, 1e-12);
    EXPECT_GT(j["steady_residual"].get<double>(), 1e-6);  // 3 time units after the start: not steady yet
    EXPECT_NE(r.err.find("time-accurate: 6 steps of 0.5"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("t    3.000  CL"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("verdict: "), std::string::npos) << r.err;
    std::ifstream in(history);
    std::string line;
    int rows = 0;
    std::getline(in, line);
    EXPECT_EQ(line.rfind("step,time,CL,CD,CM,CY,steady_residual,", 0), 0u) << line;
    while (std::getline(in, line)) ++rows;
    EXPECT_EQ(rows, steps);
    EXPECT_TRUE(std::filesystem::exists(restart));
    const std::string plot = slurp(tmp("time_history.svg"));
    EXPECT_NE(plot.find(">CL</text>"), std::string::npos);
    EXPECT_NE(plot.find(">CD</text>"), std::string::npos);

    // From the converged steady state: it stays (CL to 1e-7) and the verdict says so.
    const Result settled = run("flow '" + path + "' --restart '" + steadyRestart + "' --time-accurate 3 --time-step 1 --json");
    ASSERT_EQ(settled.code, 0) << settled.err;
    const auto s = nlohmann::json::parse(settled.out);
    EXPECT_NEAR(s["CL"].get<double>(), cl, 1e-7);
    EXPECT_LT(s["steady_residual"].get<double>(), 1e-9);
    EXPECT_EQ(s["verdict"].get<std::string>().rfind("the flow settled into a steady state", 0), 0u) << s["verdict"];

    EXPECT_EQ(run("flow '" + path + "' --time-accurate 5 --time-step 0").code, 2);
    EXPECT_EQ(run("flow '" + path + "' --time-accurate 2.5").code, 2);
    const Result alone = run("flow '" + path + "' --time-step 0.1");
    EXPECT_EQ(alone.code, 2);
    EXPECT_NE(alone.err.find("--time-step needs --time-accurate"), std::string::npos) << alone.err;
}

// SIGTERM (as Ctrl+C's SIGINT) stops a time-accurate run between steps: it exits 1, not killed,
// with the rows so far in its history and the state reached in its restart file.
TEST(Cli, ATimeAccurateRunStopsOnSigtermAndKeepsItsState) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/bwb_flow.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["output"] = nlohmann::json::object();
    const std::string restart = tmp("time_stop.restart");
    c["output"]["restart"] = restart;
    const std::string path = tmp("time_stop.json");
    std::ofstream(path) << c.dump(1);
    const std::string history = tmp("time_stop.csv");
    std::filesystem::remove(history);
    std::filesystem::remove(restart);
    const pid_t pid = spawnCli({"flow", path, "--time-accurate", "100000", "--time-step", "0.5", "--history", history});
    ASSERT_GE(pid, 0);
    int rows = 0, status = 0;
    bool done = false;
    for (int wait = 0; wait < 6000 && rows < 4 && !done; ++wait) {
        std::ifstream in(history);
        std::string line;
        rows = -1;  // the header
        while (std::getline(in, line)) ++rows;
        done = ::waitpid(pid, &status, WNOHANG) == pid;
        ::usleep(10000);
    }
    ASSERT_FALSE(done) << "the run ended by itself";
    ASSERT_GE(rows, 4);
    ::kill(pid, SIGTERM);
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by the signal instead of stopping";
    EXPECT_EQ(WEXITSTATUS(status), 1);
    EXPECT_TRUE(std::filesystem::exists(restart));
    // The state reached starts the next run.
    const Result next = run("flow '" + path + "' --restart '" + restart + "' --time-accurate 1 --time-step 0.5 --json");
    ASSERT_EQ(next.code, 0) << next.err;
    EXPECT_NE(next.err.find("restart from " + restart + ": a flow state"), std::string::npos) << next.err;
}

// aeroform-cli sweep on the blended-wing sample at CI size (refine 0.3, 4,320 nodes): the case's
// design and one random design converge, the CSV has a row per design with the counts; --no-flow
// checks shapes and grids only; bad options are usage errors.
TEST(Cli, SweepSolvesScaledAndRandomDesignsAndWritesOneRowEach) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/bwb_flow.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["output"] = nlohmann::json::object();
    const std::string path = tmp("sweep_case.json");
    std::ofstream(path) << c.dump(1);
    const std::string csv = outputPath("cli_sweep.csv");
    std::filesystem::remove(csv);
    const Result r = run("sweep '" + path + "' --fractions 1 --random 1 --spread 0.1 --seed 3 --csv '" + csv + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["designs"], 2);
    EXPECT_EQ(j["converged"], 2);
    ASSERT_EQ(j["rows"].size(), 2u);
    EXPECT_EQ(j["rows"][0]["design"], "fraction 1");
    EXPECT_GE(j["rows"][0]["orders"].get<double>(), 10.0);
    EXPECT_EQ(j["rows"][0]["grid_nodes"], 4320);
    EXPECT_LT(j["rows"][0]["max_mach"].get<double>(), 1.0);
    // The sample's thin wing tip turns by about 20 degrees per grid node on this grid.
    EXPECT_GT(j["rows"][0]["sharpest_wall_bend"].get<double>(), 10.0);
    EXPECT_LT(j["rows"][0]["sharpest_wall_bend"].get<double>(), 25.0);
    EXPECT_EQ(j["rows"][1]["design"], "random 1");
    EXPECT_GE(j["rows"][1]["redraws"].get<int>(), 0);
    std::istringstream rows(slurp(csv));
    std::string line;
    int n = 0;
    while (std::getline(rows, line)) ++n;
    EXPECT_EQ(n, 3);  // header + 2 designs
    EXPECT_NE(slurp(csv).find(",max_mach_at,sharpest_wall_bend,growing_mode_rate,redraws,"), std::string::npos);
    EXPECT_TRUE(j["rows"][0]["growing_mode_rate"].is_null());  // converged: not looked for
    EXPECT_NE(r.err.find("2 of 2 designs converged"), std::string::npos) << r.err;

    const std::string cases = outputPath("cli_sweep_cases");
    std::filesystem::remove_all(cases);
    const Result shapes = run("sweep '" + path + "' --fractions \"\" --random 2 --spread 0.1 --feasible --no-flow --json --cases '" + cases + "'");
    ASSERT_EQ(shapes.code, 0) << shapes.err;
    const auto js = nlohmann::json::parse(shapes.out);
    EXPECT_EQ(js["converged"], 2);
    EXPECT_TRUE(js.contains("redrawn_linear_constraint"));
    EXPECT_NE(shapes.err.find("2 of 2 designs valid"), std::string::npos) << shapes.err;
    // Each design as a case of its own, which the other commands take.
    ASSERT_TRUE(std::filesystem::exists(cases + "/random_2.json"));
    const Result again = run("deform '" + cases + "/random_2.json' --json");
    EXPECT_EQ(again.code, 0) << again.err;

    // A design that does not converge carries the mode analysis's verdict (flow.stall_modes): the
    // fastest growing mode's rate, 0 when none grows; in the CSV too.
    c["flow"]["max_iterations"] = 3;
    std::ofstream(path) << c.dump(1);
    const Result stopped = run("sweep '" + path + "' --fractions 1 --csv '" + csv + "' --json");
    EXPECT_EQ(stopped.code, 1) << stopped.err;
    const auto jst = nlohmann::json::parse(stopped.out);
    ASSERT_TRUE(jst["rows"][0]["growing_mode_rate"].is_number()) << stopped.out;
    EXPECT_GE(jst["rows"][0]["growing_mode_rate"].get<double>(), 0.0);
    EXPECT_NE(stopped.err.find("grows"), std::string::npos) << stopped.err;
    EXPECT_EQ(slurp(csv).find(",\"block"), slurp(csv).rfind(",\"block"));  // one design row

    EXPECT_EQ(run("sweep '" + path + "' --spread -1").code, 2);
    EXPECT_EQ(run("sweep '" + path + "' --random x").code, 2);
    EXPECT_EQ(run("sweep").code, 2);
    EXPECT_EQ(run("sweep '" + outputPath("no_such_case.json") + "'").code, 1);
}

#ifdef AEROFORM_GUI_BIN
// `aeroform --batch` on a bad case: exit 1 with the key named, like `aeroform-cli` (it aborted
// with 134, an uncaught CaseError); a good case runs headless to exit 0.
TEST(Cli, BatchModeReportsABadCaseLikeTheCli) {
    const std::string bad = writeCase("batch_bad.json", R"("mesh": {"level": "coarse", "refine": 0.5, "refinement": 2})");
    const Result r = run("--batch '" + bad + "'", AEROFORM_GUI_BIN);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("mesh.refinement: unknown key"), std::string::npos) << r.err;
    const Result cli = run("mesh '" + bad + "'");
    EXPECT_EQ(cli.code, 1);
    const Result good = run("--batch '" + writeCase("batch_good.json", R"("mesh": {"level": "coarse", "refine": 0.3})") + "'",
                            AEROFORM_GUI_BIN);
    EXPECT_EQ(good.code, 0) << good.err;
    EXPECT_EQ(run("--batch", AEROFORM_GUI_BIN).code, 2);
}
#endif

// aeroform-cli flow --adjoint: the adjoints of the converged state and dJ/dalpha, in the JSON
// summary (their accuracy against converged flows is tests/adjoint's).
TEST(Cli, FlowAdjointReportsConvergedAdjointsAndAlphaDerivatives) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/bwb_flow.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["output"] = nlohmann::json::object();
    const std::string path = tmp("adjoint_case.json");
    std::ofstream(path) << c.dump(1);
    const Result r = run("flow '" + path + "' --adjoint CL,CD --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["adjoint"].size(), 2u);
    EXPECT_EQ(j["adjoint"][0]["functional"], "CL");
    EXPECT_TRUE(j["adjoint"][0]["converged"].get<bool>());
    EXPECT_LT(j["adjoint"][0]["relative_residual"].get<double>(), 1e-9);
    EXPECT_EQ(j["adjoint"][0]["value"].get<double>(), j["CL"].get<double>());
    EXPECT_EQ(j["adjoint"][1]["value"].get<double>(), j["CD"].get<double>());
    EXPECT_TRUE(std::isfinite(j["adjoint"][1]["d_dalpha_per_degree"].get<double>()));
    EXPECT_NE(r.err.find("adjoint of CD: converged"), std::string::npos) << r.err;
    const Result bad = run("flow '" + path + "' --adjoint LD");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("unknown functional 'LD'"), std::string::npos) << bad.err;
}

// A directory or a device where a file belongs is named as such (it was "not valid JSON", or read
// until memory ran out for /dev/zero; issue #20).
TEST(Cli, DirectoriesAndDevicesAreRefusedAsInputFiles) {
    const std::string dir = outputPath("");
    Result r = run("flow '" + dir + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("is a directory, not a case file"), std::string::npos) << r.err;
    r = run("info /dev/zero");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("'/dev/zero' is not a regular file"), std::string::npos) << r.err;
    const std::string c = writeCase("dir_restart.json", R"("mesh": {"level": "coarse", "refine": 0.3}, "flow": {})");
    r = run("flow '" + c + "' --restart '" + dir + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("is a directory, not a restart file"), std::string::npos) << r.err;
}

// aeroform-cli gradient: J and dJ/dv of every variable by name, the quotient rule for CL/CD, the
// stage times; gradient-check: the directional-derivative table with exit code 0 within the
// tolerance and 1 outside it (at eps 0.1 the centred difference is far off), CSV and SVG written.
// (The gradient's accuracy itself is tests/adjoint's.)
TEST(Cli, GradientAndGradientCheck) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/bwb_flow.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["output"] = nlohmann::json::object();
    const std::string path = tmp("gradient_case.json");
    std::ofstream(path) << c.dump(1);
    Result r = run("gradient '" + path + "' --json --csv '" + tmp("gradient.csv") + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["functionals"].size(), 3u);
    EXPECT_EQ(j["functionals"][2]["name"], "CL/CD");
    const auto& L = j["functionals"][0], &D = j["functionals"][1], &R = j["functionals"][2];
    EXPECT_EQ(L["gradient"].size(), j["variables"].get<std::size_t>());
    EXPECT_GT(j["variables"].get<int>(), 80);
    const double cl = L["value"], cd = D["value"];
    // CL/CD's gradient comes from one adjoint of its own linearization, not from the quotient
    // rule on the other two: they agree to the adjoint solves' tolerance, relative to the
    // gradient's size.
    double scale = 0;
    for (auto it = R["gradient"].begin(); it != R["gradient"].end(); ++it)
        scale = std::max(scale, std::abs(it.value().get<double>()));
    ASSERT_GT(scale, 0);
    for (auto it = L["gradient"].begin(); it != L["gradient"].end(); ++it) {
        const double dl = it.value(), dd = D["gradient"][it.key()], dr = R["gradient"][it.key()];
        EXPECT_NEAR(dr, (dl * cd - cl * dd) / (cd * cd), 1e-8 * scale) << it.key();
    }
    EXPECT_GT(j["seconds"]["mesh_adjoint"].get<double>(), 0);
    EXPECT_NE(r.err.find("flow adjoint of CD"), std::string::npos) << r.err;
    EXPECT_NE(slurp(tmp("gradient.csv")).find("body.S1.tx,"), std::string::npos);
    EXPECT_EQ(run("gradient '" + path + "' --functionals LD").code, 2);

    const std::string csv = tmp("check.csv"), svg = tmp("check.svg");
    // Several steps: the response's kinks (the dissipation's switches) spoil some of them.
    r = run("gradient-check '" + path + "' --functional CL --eps-range 1e-4:1e-8 --tolerance 1e-5 --csv '" + csv +
            "' --plot '" + svg + "'");
    EXPECT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("all variables: best relative error"), std::string::npos) << r.out;
    EXPECT_NE(slurp(csv).find("\"all variables\",1.0000000000000001e-05"), std::string::npos) << slurp(csv);
    EXPECT_NE(slurp(svg).find("<polyline"), std::string::npos);
    r = run("gradient-check '" + path + "' --functional CL --eps-range 1e-1:1e-1");
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("NOT within the tolerance"), std::string::npos) << r.out;
    EXPECT_EQ(run("gradient-check '" + path + "' --eps-range 1e-8:1e-2").code, 2);
}

namespace {

// The history's records without their wall-clock times (everything else must match bit for bit:
// JSON numbers round-trip doubles exactly).
std::vector<nlohmann::json> historyRecords(const std::string& path) {
    std::vector<nlohmann::json> records;
    std::istringstream in(slurp(path));
    std::string line;
    while (std::getline(in, line)) {
        if (in.eof()) break;  // no newline yet: a line being written
        nlohmann::json j = nlohmann::json::parse(line);
        j.erase("seconds");
        records.push_back(j);
    }
    return records;
}

}  // namespace

// Issue #17: a run killed at any moment (kill -9, mid-evaluation) and resumed replays what its
// history holds without solving it again and reaches the same iterates, bit for bit, as an
// uninterrupted run; an existing history is never overwritten without --fresh.
TEST(Cli, OptimizeKilledAndResumedReachesTheSameIterates) {
    nlohmann::json c = nlohmann::json::parse(slurp(kSamples + "/sphere_to_bwb.json"));
    c["geometry"] = kSamples + "/half_sphere.igs";
    c["mesh"]["refine"] = 0.3;
    c["mesh"]["increments"] = 2;  // folds on some steps: failed evaluations are part of the path
    // Ipopt, not the sample's SLSQP: its replay is the harder one (the barrier's state and the
    // quasi-Newton memory are rebuilt from the records). SLSQP's resume is checked on the same
    // sample in OptimizationWorkspaceTest::pauseStopsAtAnEvaluationAndResumeReachesTheSameRecords.
    c["optimization"]["optimizer"] = "ipopt";
    c["optimization"]["max_iterations"] = 3;
    c["output"] = nlohmann::json::object();
    auto caseFor = [&](const std::string& name) {
        c["optimization"]["history"] = tmp(name + "/history.csv");
        c["optimization"]["iterations"] = tmp(name + "/iterations");
        std::filesystem::remove_all(tmp(name));
        const std::string path = tmp(name + ".json");
        std::ofstream(path) << c.dump(1);
        return path;
    };
    const std::string whole = caseFor("opt_whole"), killed = caseFor("opt_killed");
    Result r = run("optimize '" + whole + "' --json --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json a = nlohmann::json::parse(r.out);
    EXPECT_EQ(a["status"], "iteration limit");
    // From 0.0016 at the sphere. The best feasible design: the sample's bound on the wall Mach
    // number (1) makes the third and fourth evaluations (J 0.34 and 1.02 at wall Mach 1.07 and
    // 1.14) infeasible, so the best is the second's 0.017.
    EXPECT_GT(a["J"].get<double>(), 0.01);
    EXPECT_GE(a["volume"].get<double>(), a["start_volume"].get<double>() * (1 - 1e-6));
    EXPECT_TRUE(std::filesystem::exists(tmp("opt_whole/history_best.igs")));
    EXPECT_TRUE(std::filesystem::exists(tmp("opt_whole/iterations/iteration_003.igs")));
    EXPECT_NE(slurp(tmp("opt_whole/history_optimality.svg")).find("<polyline"), std::string::npos);
    EXPECT_NE(slurp(tmp("opt_whole/history_objective.svg")).find("<polyline"), std::string::npos);
    EXPECT_NE(slurp(tmp("opt_whole/history.csv")).find("values,1,ok,"), std::string::npos);
    EXPECT_NE(slurp(tmp("opt_whole/history.csv")).find(",smallest_corner_ratio,sharpest_wall_bend,max_mach,max_entropy,"), std::string::npos);
    // The planform the paper reports (half-span, projected area, aspect ratio), per evaluation
    // and for the start and the best shape: the half-sphere's is 1, pi/2 and 4/pi.
    EXPECT_NE(slurp(tmp("opt_whole/history.csv")).find(",volume,half_span,projected_area,aspect_ratio,"), std::string::npos);
    EXPECT_NEAR(a["start_half_span"].get<double>(), 1.0, 1e-4);
    EXPECT_NEAR(a["start_projected_area"].get<double>(), M_PI / 2, 1e-3);
    EXPECT_NEAR(a["start_aspect_ratio"].get<double>(), 4 / M_PI, 1e-3);
    EXPECT_GT(a["half_span"].get<double>(), 0.5);
    EXPECT_NEAR(a["aspect_ratio"].get<double>(),
                2 * std::pow(a["half_span"].get<double>(), 2) / a["projected_area"].get<double>(), 1e-12);
    EXPECT_NE(slurp(tmp("opt_whole/history_iterations.csv")).find("iteration,evaluations,gradients,objective,optimality"),
              std::string::npos);
    const auto wholeRecords = historyRecords(tmp("opt_whole/history.jsonl"));
    for (const nlohmann::json& rec : wholeRecords) {
        if (rec["kind"] == "values" && rec["evaluation"] == 1) {
            EXPECT_NEAR(rec["half_span"].get<double>(), 1.0, 1e-4);  // the sphere
            EXPECT_NEAR(rec["projected_area"].get<double>(), M_PI / 2, 1e-3);
        }
    }

    // Killed (SIGKILL) three times at random moments (a fixed seed: after a random number of
    // records, then a random 0-0.4 s into whatever runs next, a history write included), each
    // time resumed, killed again further on, and finally resumed to the end.
    const std::string jsonl = tmp("opt_killed/history.jsonl");
    std::srand(17);
    std::size_t before = 0;
    for (int round = 0; round < 3; ++round) {
        const std::size_t have = historyRecords(jsonl).size();
        const std::size_t left = wholeRecords.size() - have;
        ASSERT_GT(left, 2u) << "round " << round;
        const std::size_t cut = have + 1 + static_cast<std::size_t>(std::rand()) % (left / 2);
        const pid_t pid = round == 0 ? spawnCli({"optimize", killed, "--quiet"}) : spawnCli({"optimize", killed, "--resume", "--quiet"});
        ASSERT_GE(pid, 0);
        for (int wait = 0; wait < 6000 && historyRecords(jsonl).size() < cut; ++wait) ::usleep(20000);
        ::usleep(static_cast<useconds_t>(std::rand() % 400000));
        ::kill(pid, SIGKILL);
        int status = 0;
        ::waitpid(pid, &status, 0);
        const auto records = historyRecords(jsonl);  // every complete line parses
        before = records.size();
        ASSERT_GE(before, cut) << "round " << round;
        ASSERT_LT(before, wholeRecords.size()) << "the run finished before it was killed (round " << round << ")";
        for (std::size_t i = 0; i < before; ++i) {
            nlohmann::json w = wholeRecords[i], k = records[i];
            w.erase("replayed");
            k.erase("replayed");
            EXPECT_EQ(k, w) << "round " << round << ", record " << i;
        }
    }

    // While another run owns the history (here: this test holds its lock, as a running optimize
    // does), a second run, resumed or fresh, is refused, names the owner and touches nothing: it
    // would interleave its records with the owner's, or delete the warm states the owner reads.
    // (The SIGKILLed runs above left the lock free: the kernel drops it with the process.)
    {
        const std::string states = tmp("opt_killed/history.states");
        auto stateFiles = [&] {
            std::size_t k = 0;
            for (const auto& e : std::filesystem::directory_iterator(states)) k += e.is_regular_file() ? 1 : 0;
            return k;
        };
        const std::size_t statesBefore = stateFiles();
        ASSERT_GT(statesBefore, 0u);
        const int fd = ::open((jsonl + ".lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        ASSERT_GE(fd, 0);
        ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
        ASSERT_EQ(::ftruncate(fd, 0), 0);
        ASSERT_EQ(::pwrite(fd, "4242", 4, 0), 4);
        for (const char* flag : {"--resume", "--fresh"}) {
            const Result second = run("optimize '" + killed + "' " + flag + " --quiet");
            EXPECT_EQ(second.code, 1) << flag;
            EXPECT_NE(second.err.find("is in use by another run (process 4242)"), std::string::npos) << second.err;
            EXPECT_EQ(historyRecords(jsonl).size(), before) << flag;
            EXPECT_EQ(stateFiles(), statesBefore) << flag;
        }
        ::close(fd);
    }

    r = run("optimize '" + killed + "' --json --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;  // nothing overwritten
    EXPECT_EQ(historyRecords(jsonl).size(), before);

    // A history written before the planform was recorded (its fields removed): the resume computes
    // it from each recorded design, to the same bits as the uninterrupted run recorded it.
    {
        std::string text;
        std::istringstream in(slurp(jsonl));
        for (std::string line; std::getline(in, line);) {
            nlohmann::ordered_json j = nlohmann::ordered_json::parse(line);
            for (const char* key : {"half_span", "projected_area", "aspect_ratio"}) j.erase(key);
            text += j.dump() + "\n";
        }
        std::ofstream(jsonl, std::ios::trunc) << text;
    }
    r = run("optimize '" + killed + "' --resume --json --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json b = nlohmann::json::parse(r.out);
    EXPECT_GT(b["replayed_evaluations"].get<int>(), 0);
    EXPECT_EQ(b["x"], a["x"]);
    EXPECT_EQ(b["J"], a["J"]);
    const auto resumedRecords = historyRecords(jsonl);
    ASSERT_EQ(resumedRecords.size(), wholeRecords.size());
    for (std::size_t i = 0; i < wholeRecords.size(); ++i) EXPECT_EQ(resumedRecords[i], wholeRecords[i]) << "record " << i;

    r = run("optimize '" + killed + "' --fresh --resume");
    EXPECT_EQ(r.code, 2);

    // An evaluation of the history as a case of its own (--design): the recorded design, without
    // outputs or optimization section, which the other commands run.
    const std::string design = tmp("opt_whole_evaluation2.json");
    r = run("optimize '" + whole + "' --design 2 '" + design + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json d = nlohmann::json::parse(slurp(design));
    EXPECT_FALSE(d.contains("optimization"));
    EXPECT_FALSE(d.contains("output"));
    EXPECT_NE(d["description"].get<std::string>().find("evaluation 2 of the optimization of"), std::string::npos) << d.dump();
    EXPECT_FALSE(d["values"].empty());
    r = run("deform '" + design + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const nlohmann::json& rec : wholeRecords) {
        if (rec["kind"] == "values" && rec["evaluation"] == 2) {
            EXPECT_NEAR(nlohmann::json::parse(r.out)["volume"].get<double>(), rec["volume"].get<double>(), 1e-12);
        }
    }
    r = run("optimize '" + whole + "' --design 99 '" + design + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("has no evaluation 99 (it has "), std::string::npos) << r.err;
    r = run("optimize '" + whole + "' --design 1 '" + whole + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("is the case itself"), std::string::npos) << r.err;
    EXPECT_EQ(run("optimize '" + whole + "' --design x '" + design + "'").code, 2);
    EXPECT_EQ(run("optimize '" + whole + "' --design 2").code, 2);

    // An evaluation whose flow the run kept: written as a restart beside the case, from which
    // its flow is back at once on its grid and starts a finer mesh.refine (4,320 -> 6,860 nodes).
    int keptEvaluation = 0;
    for (const auto& entry : std::filesystem::directory_iterator(tmp("opt_whole/history.states"))) {
        keptEvaluation = std::max(keptEvaluation, std::atoi(entry.path().stem().string().c_str()));
    }
    ASSERT_GT(keptEvaluation, 0);
    const std::string keptCase = tmp("opt_whole_kept.json"), keptRestart = tmp("opt_whole_kept.restart");
    std::filesystem::remove(keptRestart);
    r = run("optimize '" + whole + "' --design " + std::to_string(keptEvaluation) + " '" + keptCase + "'");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(std::filesystem::exists(keptRestart)) << r.err;
    EXPECT_NE(r.err.find("--restart"), std::string::npos) << r.err;
    r = run("flow '" + keptCase + "' --restart '" + keptRestart + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json again = nlohmann::json::parse(r.out);
    EXPECT_LE(again["newton_iterations"].get<int>(), 2) << r.err;  // converged where the run left it
    EXPECT_NE(r.err.find("it is only the initial guess"), std::string::npos) << r.err;
    for (const nlohmann::json& rec : wholeRecords) {
        if (rec["kind"] == "values" && rec["evaluation"] == keptEvaluation) {
            EXPECT_NEAR(again["CL"].get<double>(), rec["CL"].get<double>(), 1e-8);
            EXPECT_NEAR(again["CD"].get<double>(), rec["CD"].get<double>(), 1e-8);
        }
    }
    nlohmann::json finer = nlohmann::json::parse(slurp(keptCase));
    finer["mesh"]["refine"] = 0.4;
    const std::string finerCase = tmp("opt_whole_kept_finer.json");
    std::ofstream(finerCase) << finer.dump(1);
    r = run("flow '" + finerCase + "' --restart '" + keptRestart + "' --json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["restart_interpolated_from_nodes"], again["grid_nodes"]);
}
