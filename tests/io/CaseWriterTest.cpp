#include "io/CaseWriter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "io/CaseFile.h"

using namespace aero;

namespace {

// Field-by-field comparison (CaseFile has no operator==; NaN means "initial" volume).
void expectSameCase(const io::CaseFile& a, const io::CaseFile& b) {
    EXPECT_EQ(a.description, b.description);
    EXPECT_EQ(a.path, b.path);
    EXPECT_EQ(a.geometry, b.geometry);
    ASSERT_EQ(a.lattices.size(), b.lattices.size());
    for (std::size_t l = 0; l < a.lattices.size(); ++l) {
        SCOPED_TRACE("lattice " + std::to_string(l));
        const io::LatticeCase &x = a.lattices[l], &y = b.lattices[l];
        EXPECT_EQ(x.name, y.name);
        EXPECT_EQ(x.counts, y.counts);
        EXPECT_EQ(x.degrees, y.degrees);
        EXPECT_EQ(x.padding, y.padding);
        EXPECT_EQ(x.axes, y.axes);
        ASSERT_EQ(x.box.has_value(), y.box.has_value());
        if (x.box) {
            EXPECT_EQ(x.box->origin, y.box->origin);
            EXPECT_EQ(x.box->size, y.box->size);
            EXPECT_EQ(x.box->axes, y.box->axes);
        }
        EXPECT_EQ(x.patches, y.patches);
        EXPECT_EQ(x.refine, y.refine);
        EXPECT_EQ(x.crease, y.crease);
    }
    ASSERT_EQ(a.stations.size(), b.stations.size());
    for (std::size_t i = 0; i < a.stations.size(); ++i) {
        SCOPED_TRACE("station group " + std::to_string(i));
        const ffd::StationSpec &x = a.stations[i], &y = b.stations[i];
        EXPECT_EQ(x.prefix, y.prefix);
        EXPECT_EQ(x.lattice, y.lattice);
        EXPECT_EQ(x.direction, y.direction);
        EXPECT_EQ(x.bits, y.bits);
        EXPECT_EQ(x.sectionScaling, y.sectionScaling);
        EXPECT_EQ(x.taper, y.taper);
        EXPECT_EQ(x.vertical, y.vertical);
        EXPECT_EQ(x.streamwise, y.streamwise);
        EXPECT_EQ(x.translationBound, y.translationBound);
        EXPECT_EQ(x.scalingBounds, y.scalingBounds);
        EXPECT_EQ(x.taperBounds, y.taperBounds);
    }
    ASSERT_EQ(a.pointVariables.size(), b.pointVariables.size());
    for (std::size_t i = 0; i < a.pointVariables.size(); ++i) {
        const io::PointVariableCase &x = a.pointVariables[i], &y = b.pointVariables[i];
        EXPECT_EQ(x.lattice, y.lattice);
        EXPECT_EQ(x.index, y.index);
        EXPECT_EQ(x.axes, y.axes);
        EXPECT_EQ(x.bounds, y.bounds);
    }
    EXPECT_EQ(a.values, b.values);
    ASSERT_EQ(a.displacements.size(), b.displacements.size());
    for (std::size_t i = 0; i < a.displacements.size(); ++i) {
        EXPECT_EQ(a.displacements[i].lattice, b.displacements[i].lattice);
        EXPECT_EQ(a.displacements[i].index, b.displacements[i].index);
        EXPECT_EQ(a.displacements[i].delta, b.displacements[i].delta);
    }
    EXPECT_EQ(a.embedding.tolerance, b.embedding.tolerance);
    EXPECT_EQ(a.embedding.maxIterations, b.embedding.maxIterations);
    EXPECT_EQ(a.allowOutside, b.allowOutside);
    EXPECT_EQ(a.symmetry, b.symmetry);
    EXPECT_EQ(a.stationGap, b.stationGap);
    EXPECT_EQ(a.stationSecondDifference, b.stationSecondDifference);
    EXPECT_EQ(a.thickness.stations, b.thickness.stations);
    EXPECT_EQ(a.thickness.chordFractions, b.thickness.chordFractions);
    EXPECT_EQ(a.thickness.points, b.thickness.points);
    EXPECT_EQ(a.thickness.minRatio, b.thickness.minRatio);
    EXPECT_EQ(a.minLatticeJacobian, b.minLatticeJacobian);
    ASSERT_EQ(a.minVolume.has_value(), b.minVolume.has_value());
    if (a.minVolume) {
        EXPECT_EQ(std::isnan(*a.minVolume), std::isnan(*b.minVolume));
        if (!std::isnan(*a.minVolume)) {
            EXPECT_EQ(*a.minVolume, *b.minVolume);
        }
    }
    EXPECT_EQ(a.outputGeometry, b.outputGeometry);
    EXPECT_EQ(a.outputVtk, b.outputVtk);
    EXPECT_EQ(a.outputMeshVtk, b.outputMeshVtk);
    EXPECT_EQ(a.outputControlVtk, b.outputControlVtk);
    EXPECT_EQ(a.outputPlot3d, b.outputPlot3d);
    EXPECT_EQ(a.mesh.present, b.mesh.present);
    EXPECT_EQ(a.mesh.level, b.mesh.level);
    const mesh::ExtrusionOptions &e = a.mesh.extrusion, &f = b.mesh.extrusion;
    EXPECT_EQ(e.farfieldRadius, f.farfieldRadius);
    EXPECT_EQ(e.radialControlPoints, f.radialControlPoints);
    EXPECT_EQ(e.radialDegree, f.radialDegree);
    EXPECT_EQ(e.controlWallSpacing, f.controlWallSpacing);
    EXPECT_EQ(e.surfaceNodes, f.surfaceNodes);
    EXPECT_EQ(e.radialNodes, f.radialNodes);
    EXPECT_EQ(e.gridWallSpacing, f.gridWallSpacing);
    EXPECT_EQ(e.refine, f.refine);
    EXPECT_EQ(e.symmetryTolerance, f.symmetryTolerance);
    const mesh::ElasticityOptions &m = a.mesh.elasticity, &n = b.mesh.elasticity;
    EXPECT_EQ(m.poisson, n.poisson);
    EXPECT_EQ(m.increments, n.increments);
    EXPECT_EQ(m.sizeStiffening, n.sizeStiffening);
    EXPECT_EQ(m.orthogonalityStiffening, n.orthogonalityStiffening);
    EXPECT_EQ(m.tolerance, n.tolerance);
    EXPECT_EQ(m.maxIterations, n.maxIterations);
    EXPECT_EQ(a.flow.present, b.flow.present);
    EXPECT_EQ(a.flow.freeStream.mach, b.flow.freeStream.mach);
    EXPECT_EQ(a.flow.freeStream.alphaDeg, b.flow.freeStream.alphaDeg);
    EXPECT_EQ(a.flow.freeStream.gamma, b.flow.freeStream.gamma);
    EXPECT_EQ(a.flow.reference.area, b.flow.reference.area);
    EXPECT_EQ(a.flow.reference.length, b.flow.reference.length);
    EXPECT_EQ(a.flow.reference.point, b.flow.reference.point);
    EXPECT_EQ(a.flow.dissipation.kappa2, b.flow.dissipation.kappa2);
    EXPECT_EQ(a.flow.dissipation.kappa4, b.flow.dissipation.kappa4);
    EXPECT_EQ(a.flow.dissipation.lumping, b.flow.dissipation.lumping);
    EXPECT_EQ(a.flow.newton.relativeTolerance, b.flow.newton.relativeTolerance);
    EXPECT_EQ(a.flow.newton.maxIterations, b.flow.newton.maxIterations);
    EXPECT_EQ(a.flow.newton.cfl0, b.flow.newton.cfl0);
    EXPECT_EQ(a.flow.newton.cflGrowth, b.flow.newton.cflGrowth);
    EXPECT_EQ(a.flow.newton.linearTolerance, b.flow.newton.linearTolerance);
    EXPECT_EQ(a.flow.newton.iluFill, b.flow.newton.iluFill);
    EXPECT_EQ(a.flow.newton.preconditionerParts, b.flow.newton.preconditionerParts);
    EXPECT_EQ(a.flow.restart, b.flow.restart);
    EXPECT_EQ(a.outputFlowVtk, b.outputFlowVtk);
    EXPECT_EQ(a.outputResidualCsv, b.outputResidualCsv);
    EXPECT_EQ(a.outputRestart, b.outputRestart);
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string outputDir(const std::string& name) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/case_writer/" + name;
    std::filesystem::create_directories(dir);
    return dir;
}

// Every key of the format, with values away from the defaults (and awkward numbers: 0.1,
// 1/3, 1e-300, a non-trivial orthonormal frame).
const char* kEveryKey = R"({
  "format": "aeroform.case", "version": 1,
  "description": "every key",
  "geometry": "geometry/wing.igs",
  "lattices": [
    {"name": "inboard", "counts": [5, 7, 3], "degrees": [2, 3, 2], "padding": [0.1, 0, 0.3333333333333333],
     "axes": [[0.6, 0.8, 0], [-0.8, 0.6, 0], [0, 0, 1]],
     "patches": [1, 3, 20],
     "refine": [{"direction": 1, "knots": [0.25, 0.5]}, {"direction": 0, "knots": [0.125]}],
     "crease": [{"direction": 2, "at": 0.5}]},
    {"name": "tip", "counts": [2, 2, 2], "degrees": [1, 1, 1],
     "box": {"origin": [-1.5, 0.25, -1e-300], "size": [3, 0.1, 2.5]}}
  ],
  "design_variables": {
    "stations": [
      {"lattice": "inboard", "direction": 1, "bits": ["001", "011", "111", "000", "100", "010", "110"],
       "section_scaling": false, "taper": true, "vertical": "y", "streamwise": "z",
       "translation_bound": 0.75, "scaling_bounds": [0.25, 4], "taper_bounds": [0.5, 1.5]},
      {"lattice": 1, "direction": 0, "section_scaling": true, "taper": false}
    ],
    "points": [
      {"lattice": "tip", "index": [1, 0, 1], "axes": "zx", "bounds": [-0.2, 0.3]},
      {"lattice": "inboard", "index": [4, 6, 2]}
    ]
  },
  "values": {"inboard.S1.tx": 0.1, "tip.P5.z": -0.2, "inboard.S0.taperz": 1.0000000000000002},
  "displacements": [
    {"lattice": "tip", "index": [0, 1, 1], "delta": [0.1, -0.2, 3e-17]},
    {"lattice": "inboard", "index": [2, 3, 1], "delta": [0, 0, -0.05]}
  ],
  "embedding": {"tolerance": 1e-10, "max_iterations": 77, "allow_outside": true},
  "constraints": {"symmetry": false, "station_gap": 0.02, "station_second_difference": 0.3, "min_volume": 1.75,
                  "thickness": {"stations": [0, 0.5], "chord_fractions": [0.1, 0.30000000000000004], "points": [[0.2, 0.25]],
                                "min_ratio": 0.8},
                  "min_lattice_jacobian": 0.15},
  "mesh": {"level": "medium", "farfield_radius": 12.5, "radial_control_points": 9, "control_wall_spacing": 0.003,
           "surface_nodes": 11, "radial_nodes": 21, "grid_wall_spacing": 0.0007, "refine": 1.5, "increments": 4,
           "poisson": 0.1, "size_stiffening": 2, "orthogonality_stiffening": 0.5, "tolerance": 1e-9},
  "flow": {"mach": 0.3333333333333333, "alpha": -2.5, "gamma": 1.3, "reference_area": 0.1, "reference_length": 2,
           "reference_point": [0.25, 0, -1e-300], "kappa2": 0, "kappa4": 0.02, "tolerance": 1e-8, "max_iterations": 77,
           "cfl0": 5, "cfl_growth": 1.5, "linear_tolerance": 0.01, "ilu_fill": 3, "ilu_parts": 4, "lumping": 6, "restart": "out/start.restart"},
  "output": {"geometry": "out/wing_deformed.json", "vtk": "/elsewhere/wing.vtm", "mesh_vtk": "out/grid.vtm",
             "control_vtk": "out/control.vtm", "plot3d": "out/grid.xyz", "flow_vtk": "out/flow.vtm",
             "residual_csv": "out/residual.csv", "restart": "/elsewhere/end.restart"}
})";

}  // namespace

TEST(CaseWriter, SamplesRoundTripExactly) {
    for (const char* name : {"half_sphere_ffd.json", "bwb_deform.json", "half_sphere_flow.json"}) {
        SCOPED_TRACE(name);
        const io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/" + name);
        const std::string text = io::formatCase(c);
        expectSameCase(io::parseCase(text, c.path), c);
        // Formatting is canonical: a second pass gives the same text.
        EXPECT_EQ(io::formatCase(io::parseCase(text, c.path)), text);
        // The sample's geometry sits next to it: written relative, as in the sample.
        EXPECT_NE(text.find("\"geometry\": \"half_sphere.igs\""), std::string::npos) << text;
        if (!c.lattices.empty()) {
            EXPECT_NE(text.find("\"counts\": [6, 6, 2]"), std::string::npos) << text;
        }
    }
}

TEST(CaseWriter, EveryKeyRoundTripsExactly) {
    const io::CaseFile c = io::parseCase(kEveryKey, "/projects/wing/case.json");
    // The parse itself saw every key (guards against a silently ignored key in the fixture).
    ASSERT_EQ(c.lattices.size(), 2u);
    ASSERT_TRUE(c.lattices[1].box.has_value());
    ASSERT_EQ(c.lattices[0].refine.size(), 2u);
    ASSERT_EQ(c.stations.size(), 2u);
    ASSERT_EQ(c.pointVariables.size(), 2u);
    ASSERT_EQ(c.thickness.points.size(), 1u);
    ASSERT_EQ(c.minLatticeJacobian, 0.15);
    ASSERT_EQ(c.displacements.size(), 2u);
    EXPECT_EQ(c.geometry, "/projects/wing/geometry/wing.igs");
    EXPECT_EQ(c.outputVtk, "/elsewhere/wing.vtm");
    ASSERT_TRUE(c.mesh.present);
    EXPECT_EQ(c.mesh.extrusion.surfaceNodes, 11);
    EXPECT_EQ(c.outputPlot3d, "/projects/wing/out/grid.xyz");
    ASSERT_TRUE(c.flow.present);
    EXPECT_EQ(c.flow.freeStream.alphaDeg, -2.5);
    EXPECT_EQ(c.flow.newton.iluFill, 3);
    EXPECT_EQ(c.flow.newton.preconditionerParts, 4);
    EXPECT_EQ(c.flow.dissipation.lumping, 6.0);
    EXPECT_EQ(c.flow.restart, "/projects/wing/out/start.restart");
    EXPECT_EQ(c.outputRestart, "/elsewhere/end.restart");

    const std::string text = io::formatCase(c);
    const io::CaseFile back = io::parseCase(text, c.path);
    expectSameCase(back, c);
    EXPECT_EQ(io::formatCase(back), text);
    // Paths under the project's top-level folder are relative; others stay absolute.
    EXPECT_NE(text.find("\"geometry\": \"geometry/wing.igs\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"vtk\": \"/elsewhere/wing.vtm\""), std::string::npos) << text;
    // Lattices are referred to by name; patches are 1-based in the file.
    EXPECT_NE(text.find("\"lattice\": \"tip\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"patches\": [1, 3, 20]"), std::string::npos) << text;
}

TEST(CaseWriter, MeshLevelAloneRoundTrips) {
    for (const char* level : {"coarse", "medium", "paper"}) {
        SCOPED_TRACE(level);
        const io::CaseFile c = io::parseCase(std::string(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs",
                                                            "mesh": {"level": ")") + level + "\"}}",
                                             "/p/c.json");
        expectSameCase(io::parseCase(io::formatCase(c), c.path), c);
    }
    // Without a mesh section none is written.
    const io::CaseFile plain = io::parseCase(R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs"})", "/p/c.json");
    EXPECT_EQ(io::formatCase(plain).find("\"mesh\""), std::string::npos);
}

TEST(CaseWriter, RelativeCasePathsStayConsistent) {
    io::CaseFile c = io::parseCase(kEveryKey, "cases/wing/case.json");
    EXPECT_EQ(c.geometry, "cases/wing/geometry/wing.igs");
    expectSameCase(io::parseCase(io::formatCase(c), c.path), c);
    c.path.clear();  // never saved: paths are written as they are
    EXPECT_NE(io::formatCase(c).find("\"geometry\": \"cases/wing/geometry/wing.igs\""), std::string::npos);
}

TEST(CaseWriter, WriteCaseIsReadBackAndRunnable) {
    const std::string dir = outputDir("write");
    const io::CaseFile sample = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/bwb_deform.json");
    const std::string path = dir + "/project.json";
    std::filesystem::remove(path);
    io::writeCase(sample, path);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    const io::CaseFile back = io::readCase(path);
    io::CaseFile expected = sample;
    expected.path = path;
    expectSameCase(back, expected);
    EXPECT_EQ(slurp(path), io::formatCase(back));

    // The written case drives the same deformation as the sample.
    const geometry::PatchSet sphere = geometry::makeHalfSphere();
    const ffd::FfdModel m0 = io::buildModel(sample, sphere), m1 = io::buildModel(back, sphere);
    const auto v0 = io::designValues(sample, m0), v1 = io::designValues(back, m1);
    EXPECT_EQ(v0, v1);
    const auto a = m0.deformWith(io::movedLattices(sample, m0, v0));
    const auto b = m1.deformWith(io::movedLattices(back, m1, v1));
    ASSERT_EQ(a.size(), b.size());
    for (int p = 0; p < a.size(); ++p) EXPECT_EQ(a.patches[p].points, b.patches[p].points);
}

TEST(CaseWriter, OverwritesWholeFileAndReportsUnwritablePaths) {
    const std::string dir = outputDir("overwrite");
    const std::string path = dir + "/case.json";
    {
        std::ofstream out(path);
        out << std::string(20000, 'x');  // a longer old file must not leave a tail behind
    }
    const io::CaseFile c = io::parseCase(kEveryKey, path);
    io::writeCase(c, path);
    expectSameCase(io::readCase(path), c);

    try {
        io::writeCase(c, "/nonexistent-folder/case.json");
        ADD_FAILURE() << "no error for an unwritable path";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/case.json"), std::string::npos) << e.what();
    }
}

TEST(CaseWriter, BadLatticeReferenceNamesTheKey) {
    io::CaseFile c = io::parseCase(kEveryKey, "/p/c.json");
    c.displacements[1].lattice = 5;
    try {
        (void)io::formatCase(c);
        ADD_FAILURE() << "no error";
    } catch (const CaseError& e) {
        EXPECT_NE(std::string(e.what()).find("displacements[1].lattice"), std::string::npos) << e.what();
    }
}
