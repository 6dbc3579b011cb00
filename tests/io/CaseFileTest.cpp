#include "io/CaseFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "io/CaseWriter.h"
#include "io/Options.h"

using namespace aero;

namespace {

const std::string kHead = R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", )";

void expectCaseError(const std::string& body, const std::string& fragment) {
    try {
        io::parseCase(kHead + body + "}", "/cases/c.json");
        ADD_FAILURE() << "no error, expected: " << fragment;
    } catch (const CaseError& e) {
        EXPECT_NE(std::string(e.what()).find("/cases/c.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(CaseFile, SampleCaseParsesAndBuildsThePapersModel) {
    const io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/half_sphere_ffd.json");
    EXPECT_EQ(c.geometry, std::string(AEROFORM_SAMPLES_DIR) + "/half_sphere.igs");
    ASSERT_EQ(c.lattices.size(), 1u);
    EXPECT_EQ(c.lattices[0].counts, (std::array<int, 3>{6, 6, 2}));
    EXPECT_EQ(c.lattices[0].degrees, (std::array<int, 3>{3, 3, 1}));
    ASSERT_TRUE(c.minVolume.has_value());
    EXPECT_TRUE(std::isnan(*c.minVolume));  // "initial"
    const ffd::FfdModel m = io::buildModel(c, geometry::makeHalfSphere());
    EXPECT_EQ(m.design().size(), 89);
    EXPECT_EQ(m.summary().embedded, 521);
    EXPECT_EQ(io::designValues(c, m), m.design().baselineValues());
}

TEST(CaseFile, ValuesAndDisplacementsMoveTheLattice) {
    const io::CaseFile c = io::parseCase(kHead + R"(
        "lattices": [{"name": "box", "counts": [4, 4, 3], "degrees": [2, 2, 2]}],
        "design_variables": {"points": [{"lattice": "box", "index": [1, 2, 1], "axes": "z", "bounds": [-1, 1]}]},
        "values": {"box.P25.z": 0.25},
        "displacements": [{"lattice": "box", "index": [3, 3, 2], "delta": [0.1, 0, 0]}]})",
                                         "/cases/c.json");
    const ffd::FfdModel m = io::buildModel(c, geometry::makeHalfSphere());
    ASSERT_EQ(m.design().size(), 1);
    EXPECT_EQ(m.design().variables()[0].name, "box.P25.z");  // index (1,2,1) of a 4x4x3 lattice
    const auto v = io::designValues(c, m);
    const auto moved = io::movedLattices(c, m, v);
    const auto& B0 = m.lattices()[0].lattice.points;
    for (std::size_t i = 0; i < B0.size(); ++i) {
        double expect = B0[i];
        if (i == 3 * 25 + 2) expect += 0.25;
        if (i == 3 * (3 + 4 * (3 + 4 * 2))) expect += 0.1;
        EXPECT_DOUBLE_EQ(moved[0].points[i], expect);
    }
}

TEST(CaseFile, BadKeysTypesAndValuesNameTheKey) {
    expectCaseError(R"("colour": 1)", "colour: unknown key");
    expectCaseError(R"("lattices": [{"counts": [6, 6]}])", "lattices[0].counts: expected 3 integers");
    expectCaseError(R"("lattices": [{"counts": [6, 6, 2], "degrees": [3, 3, 2]}])", "lattices[0].counts[2]");
    expectCaseError(R"("lattices": [{"padding": [0.1, -1, 0]}])", "lattices[0].padding[1]: must be >= 0");
    expectCaseError(R"("constraints": {"station_second_difference": 0})", "constraints.station_second_difference: must be > 0");
    expectCaseError(R"("lattices": [{"name": "a"}, {"name": "a"}])", "duplicate lattice name");
    expectCaseError(R"("lattices": [{"axes": [[1, 0, 0], [1, 0, 0], [0, 0, 1]]}])", "lattices[0].axes: must be orthonormal");
    expectCaseError(R"("lattices": [{"name": "a"}], "design_variables": {"stations": [{"lattice": "b"}]})",
                    "design_variables.stations[0].lattice: no lattice named 'b'");
    expectCaseError(R"("lattices": [{}], "design_variables": {"stations": [{"bits": ["001", "012"]}]})",
                    "design_variables.stations[0].bits[1]");
    expectCaseError(R"("lattices": [{}], "design_variables": {"stations": [{"bits": ["001"]}]})", "1 bit strings for 6 stations");
    expectCaseError(R"("lattices": [{}], "design_variables": {"stations": [{"vertical": "w"}]})",
                    "design_variables.stations[0].vertical");
    expectCaseError(R"("lattices": [{}], "displacements": [{"index": [9, 0, 0], "delta": [0, 0, 0]}])", "displacements[0].index[0]");
    expectCaseError(R"("embedding": {"tolerance": "tight"})", "embedding.tolerance: expected a number");
    expectCaseError(R"("constraints": {"min_volume": "big"})", "constraints.min_volume");
    expectCaseError(R"("constraints": {"thickness": {"stations": [0.5]}})", "constraints.thickness: stations and chord_fractions go together");
    expectCaseError(R"("constraints": {"thickness": {"stations": [0.5], "chord_fractions": [1.2]}})",
                    "constraints.thickness.chord_fractions[0]: must lie in (0, 1)");
    expectCaseError(R"("constraints": {"thickness": {"points": [[0.5]]}})", "constraints.thickness.points[0]: expected 2 numbers");
    expectCaseError(R"("constraints": {"thickness": {"min_ratio": 0.5}})", "constraints.thickness: expected stations with chord_fractions, or points");
    expectCaseError(R"("constraints": {"thickness": {"points": [[0, 0.5]], "min_ratio": -1}})", "constraints.thickness.min_ratio");
    expectCaseError(R"("constraints": {"min_lattice_jacobian": 1.5})", "constraints.min_lattice_jacobian: must lie in [0, 1)");
    expectCaseError(R"("output": {"vtk": "x.vtk"})", "output.vtk: must end in .vtm");
    expectCaseError(R"("values": {"a": "b"})", "values.a: expected a number");
    expectCaseError(R"("flow": {"mach": -0.5})", "flow.mach: value -0.500000 outside (0, 10)");
    expectCaseError(R"("flow": {"alpha": 95})", "flow.alpha");
    expectCaseError(R"("flow": {"max_iterations": 0})", "flow.max_iterations");
    expectCaseError(R"("flow": {"reynolds": 1e6})", "flow.reynolds: unknown key");
    expectCaseError(R"("output": {"flow_vtk": "flow.vts"})", "output.flow_vtk: must end in .vtm");
    EXPECT_THROW(io::parseCase(R"({"format": "aeroform.case", "version": 2, "geometry": "g"})", "c.json"), CaseError);
    EXPECT_THROW(io::parseCase("{", "c.json"), InputError);
    EXPECT_THROW(io::readCase("/no/such/case.json"), InputError);
}

// Found by fuzz_patchset_json (tests/fuzz), the same JSON parsing here: a number out of double's
// range escaped as nlohmann::json's out_of_range instead of an InputError naming the file.
TEST(CaseFile, ANumberOutOfRangeIsInvalidJsonNamingTheFile) {
    try {
        io::parseCase(kHead + R"("flow": {"mach": -0.45E6745}})", "/cases/c.json");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("'/cases/c.json': not valid JSON"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("number overflow"), std::string::npos) << e.what();
    }
}

TEST(CaseFile, UnknownVariablesAndOutOfBoundsValuesAreRejected) {
    const std::string body = R"("lattices": [{}], "design_variables": {"stations": [{"bits": ["001","011","011","011","011","011"]}]}, )";
    const auto set = geometry::makeHalfSphere();
    {
        const io::CaseFile c = io::parseCase(kHead + body + R"("values": {"L0.S9.tx": 1}})", "/cases/c.json");
        const ffd::FfdModel m = io::buildModel(c, set);
        try {
            io::designValues(c, m);
            FAIL();
        } catch (const CaseError& e) {
            EXPECT_NE(std::string(e.what()).find("values.L0.S9.tx: no design variable"), std::string::npos) << e.what();
        }
    }
    {
        const io::CaseFile c = io::parseCase(kHead + body + R"("values": {"L0.S1.ty": 7}})", "/cases/c.json");
        const ffd::FfdModel m = io::buildModel(c, set);
        try {
            io::designValues(c, m);
            FAIL();
        } catch (const CaseError& e) {
            EXPECT_NE(std::string(e.what()).find("values.L0.S1.ty: 7 is outside the bounds [-1, 1]"), std::string::npos) << e.what();
        }
    }
    {
        const io::CaseFile c = io::parseCase(kHead + R"("lattices": [{"patches": [21]}]})", "/cases/c.json");
        EXPECT_THROW(io::buildModel(c, set), CaseError);
    }
}

TEST(CaseFile, DisplacementIndicesReferToTheRefinedLattice) {
    // 6 points per direction, refined by 2 knots in xi and creased (multiplicity 3) at 0.5 in eta:
    // 8 x 9 x 2 points. Indices are checked against those counts, not the unrefined ones.
    const std::string lattice = R"("lattices": [{"counts": [6, 6, 2], "degrees": [3, 3, 1],
        "refine": [{"direction": 0, "knots": [0.1, 0.9]}], "crease": [{"direction": 1, "at": 0.5}]}], )";
    const io::CaseFile c = io::parseCase(kHead + lattice + R"("description": "refined",
        "displacements": [{"index": [7, 8, 1], "delta": [0, 0, 0.1]}]})", "/cases/c.json");
    EXPECT_EQ(c.description, "refined");
    const ffd::FfdModel m = io::buildModel(c, geometry::makeHalfSphere());
    EXPECT_EQ(m.lattices()[0].lattice.count, (std::array<int, 3>{8, 9, 2}));
    const auto moved = io::movedLattices(c, m, m.design().baselineValues());
    const int a = moved[0].index(7, 8, 1);
    EXPECT_NEAR(moved[0].points[3 * a + 2] - m.lattices()[0].lattice.points[3 * a + 2], 0.1, 1e-15);
    expectCaseError(lattice + R"("displacements": [{"index": [8, 0, 0], "delta": [0, 0, 0]}])", "displacements[0].index[0]");
}

// The flow section's options are one table (io/Options.h): the parser accepts exactly its keys
// and checks their ranges, the writer writes them all back, and docs/case-file.md shows every
// option with its default and range as the table generates it.
TEST(Options, FlowTableDrivesParserWriterAndDocumentation) {
    const auto& options = io::flowOptions();
    ASSERT_GE(options.size(), 19u);
    const io::FlowCase defaults;
    for (const auto& o : options) {
        EXPECT_TRUE(o.spec.check(o.get(defaults)).empty()) << o.spec.key << ": the default is outside its own range";
        EXPECT_FALSE(o.spec.description.empty()) << o.spec.key;
    }
    // Every key parses and writes back (a value other than the default where possible).
    std::string body = R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {)";
    body += R"("mach": 0.7, "ilu_parts": 3, "scheme": "central", "grid_sequencing": false, "reference_point": [0.25, 0, 0]}})";
    const std::string path = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/options_case.json";
    std::ofstream(path) << body;
    const io::CaseFile c = io::readCase(path);
    EXPECT_EQ(c.flow.freeStream.mach, 0.7);
    EXPECT_EQ(c.flow.newton.preconditionerParts, 3);
    EXPECT_EQ(c.flow.scheme, flow::InviscidScheme::Central);
    EXPECT_FALSE(c.flow.gridSequencing);
    EXPECT_EQ(c.flow.reference.point[0], 0.25);
    EXPECT_NEAR(c.flow.reference.area, 3.14159265358979323846 / 2, 1e-15);  // one default
    const std::string written = io::formatCase(c);
    for (const auto& o : options) EXPECT_NE(written.find("\"" + o.spec.key + "\""), std::string::npos) << o.spec.key;
    // Ranges come from the table, with its message.
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {"ilu_fill": 7}})";
    try {
        (void)io::readCase(path);
        ADD_FAILURE() << "ilu_fill 7 accepted";
    } catch (const CaseError& e) {
        EXPECT_NE(std::string(e.what()).find("flow.ilu_fill: value 7 outside [0, 4]"), std::string::npos) << e.what();
    }
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {"scheme": "upwind"}})";
    EXPECT_THROW((void)io::readCase(path), CaseError);
    // Keys that depend on each other: the deflated vectors must leave room in the cycle.
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {"gmres_restart": 20, "gmres_deflation": 19}})";
    try {
        (void)io::readCase(path);
        ADD_FAILURE() << "gmres_deflation 19 with gmres_restart 20 accepted";
    } catch (const CaseError& e) {
        EXPECT_NE(std::string(e.what()).find("flow.gmres_deflation: must be below gmres_restart - 1 (19)"), std::string::npos)
            << e.what();
    }
    // The documentation's rows are the generated ones.
    std::ifstream in(std::string(AEROFORM_SAMPLES_DIR) + "/../docs/case-file.md");
    std::stringstream doc;
    doc << in.rdbuf();
    for (const std::string& row : io::optionTableRows(options)) {
        EXPECT_NE(doc.str().find(row), std::string::npos) << "docs/case-file.md lacks (or has an old version of) the row\n" << row;
    }
    for (const std::string& row : io::optionTableRows(io::meshOptions())) {
        EXPECT_NE(doc.str().find(row), std::string::npos) << "docs/case-file.md lacks (or has an old version of) the row\n" << row;
    }
}

// The optimization section: defaults inside their ranges, every key parsed and written back, the
// history resolved beside the case, the checks that need other sections, the documented rows.
TEST(Options, OptimizationTableDrivesParserWriterAndDocumentation) {
    const auto& options = io::optimizationOptions();
    const io::OptimizationCase defaults;
    for (const auto& o : options) {
        EXPECT_TRUE(o.spec.check(o.get(defaults)).empty()) << o.spec.key << ": the default is outside its own range";
        EXPECT_FALSE(o.spec.description.empty()) << o.spec.key;
    }
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR);
    const std::string path = dir + "/options_optimization.json";
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {"alpha": 2},
        "optimization": {"objective": "CD", "sense": "minimize", "optimizer": "slsqp", "max_evaluations": 7,
                         "alpha_variable": true, "lift_constraint": true, "target_cl": 0.3,
                         "history": "runs/h.csv", "iterations": "runs/shapes", "start_design": "runs/e63.json"}})";
    const io::CaseFile c = io::readCase(path);
    const io::OptimizationCase& o = c.optimization;
    EXPECT_TRUE(o.present);
    EXPECT_EQ(o.objective, "CD");
    EXPECT_FALSE(o.maximize);
    EXPECT_EQ(o.optimizer, "slsqp");
    EXPECT_EQ(o.maxEvaluations, 7);
    EXPECT_TRUE(o.alphaVariable);
    EXPECT_TRUE(o.liftConstraint);
    EXPECT_EQ(o.targetCL, 0.3);
    EXPECT_EQ(o.history, dir + "/runs/h.csv");
    EXPECT_EQ(o.iterations, dir + "/runs/shapes");
    EXPECT_EQ(o.startDesign, dir + "/runs/e63.json");
    const io::CaseFile back = io::parseCase(io::formatCase(c), path);
    EXPECT_EQ(back.optimization.objective, "CD");
    EXPECT_FALSE(back.optimization.maximize);
    EXPECT_EQ(back.optimization.history, o.history);
    EXPECT_EQ(back.optimization.iterations, o.iterations);
    EXPECT_EQ(back.optimization.startDesign, o.startDesign);
    EXPECT_EQ(back.optimization.targetCL, 0.3);
    // Default history beside the case; the errors name the key.
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {}, "optimization": {}})";
    EXPECT_EQ(io::readCase(path).optimization.history, dir + "/options_optimization.history.csv");
    auto refused = [&](const std::string& body, const std::string& message) {
        std::ofstream(path) << body;
        try {
            (void)io::readCase(path);
            ADD_FAILURE() << "accepted: " << body;
        } catch (const CaseError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    };
    refused(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "optimization": {}})", "needs a \"flow\" section");
    refused(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {}, "optimization": {"objective": "LD"}})",
            "optimization.objective");
    refused(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {}, "optimization": {"history": "h.txt"}})",
            "optimization.history: must end in .csv");
    refused(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {}, "optimization": {"start_design": "e63.csv"}})",
            "optimization.start_design: must be a case file");
    refused(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {"alpha": 20},
               "optimization": {"alpha_variable": true}})", "outside [alpha_lower, alpha_upper]");
    refused(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "flow": {}, "optimization": {"max_iterations": 0}})",
            "optimization.max_iterations");
    std::ifstream in(std::string(AEROFORM_SAMPLES_DIR) + "/../docs/case-file.md");
    std::stringstream doc;
    doc << in.rdbuf();
    for (const std::string& row : io::optionTableRows(options)) {
        EXPECT_NE(doc.str().find(row), std::string::npos) << "docs/case-file.md lacks (or has an old version of) the row\n" << row;
    }
}

// The mesh section's table: the level applies first, the keys override it, ranges come from the
// table, and the writer's output reads back to the same options.
TEST(Options, MeshTableAppliesTheLevelFirstAndChecksRanges) {
    const std::string path = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/options_mesh.json";
    std::ofstream(path) << R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs",
                             "mesh": {"radial_nodes": 33, "level": "paper", "increments": 12}})";
    const io::CaseFile c = io::readCase(path);
    EXPECT_EQ(c.mesh.level, "paper");
    EXPECT_EQ(c.mesh.extrusion.radialNodes, 33);                 // the override, not the level's 47
    EXPECT_EQ(c.mesh.extrusion.surfaceNodes, 31);                // the level's
    EXPECT_EQ(c.mesh.extrusion.gridWallSpacing, 1e-3);
    EXPECT_EQ(c.mesh.elasticity.increments, 12);
    const io::CaseFile back = io::parseCase(io::formatCase(c), path);
    EXPECT_EQ(back.mesh.extrusion.radialNodes, 33);
    EXPECT_EQ(back.mesh.level, "paper");
    for (const char* bad : {R"("level": "gigantic")", R"("increments": 0)", R"("poisson": 0.5)", R"("size_stiffening": 1e6)",
                            R"("farfield_radius": 1)"}) {
        std::ofstream(path) << std::string(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "mesh": {)") + bad + "}}";
        EXPECT_THROW((void)io::readCase(path), CaseError) << bad;
    }
    EXPECT_EQ(io::findOption(io::meshOptions(), "increments").spec.upper, 1000);
}

// An output never overwrites an input: the geometry, the case itself, the restart the flow reads,
// or another output (issue #20: output.geometry equal to the geometry replaced it with exit 0).
TEST(CaseFile, OutputsThatWouldOverwriteAnInputAreRefused) {
    expectCaseError(R"("output": {"geometry": "g.igs"})", "output.geometry: is the case's geometry file");
    expectCaseError(R"("output": {"plot3d": "../cases/g.igs"})", "output.plot3d: is the case's geometry file");
    expectCaseError(R"("output": {"residual_csv": "c.json"})", "output.residual_csv: is the case file itself");
    expectCaseError(R"("flow": {"restart": "r.bin"}, "output": {"residual_csv": "r.bin"})", "is the restart file the flow starts from");
    expectCaseError(R"("output": {"vtk": "a.vtm", "mesh_vtk": "a.vtm"})", "output.mesh_vtk: is the same file as output.vtk");
    // A restart continued in place is allowed.
    EXPECT_NO_THROW(io::parseCase(kHead + R"("flow": {"restart": "r.bin"}, "output": {"restart": "r.bin"}})", "/cases/c.json"));
}

// Lattices of hostile size are refused up front with the size in the message (issue #20).
TEST(CaseFile, HostileLatticeSizesAreRefused) {
    expectCaseError(R"("lattices": [{"counts": [200, 200, 200]}])", "200 x 200 x 200 control points after refinement, more than the 10^6");
    std::string knots;
    for (int i = 1; i <= 3001; ++i) knots += (i > 1 ? "," : "") + std::to_string(i / 3002.0);
    expectCaseError(R"("lattices": [{"refine": [{"direction": 0, "knots": [)" + knots + "]}]}]", "3001 knots to insert");
    EXPECT_NO_THROW(io::parseCase(kHead + R"("lattices": [{"counts": [6, 6, 2], "refine": [{"direction": 0, "knots": [0.5]}]}]})", "/cases/c.json"));
}
