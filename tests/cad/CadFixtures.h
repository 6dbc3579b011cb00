#pragma once
// Fixtures for the CAD adapter's tests, built with OpenCASCADE itself (an independent writer):
// B-spline and analytic faces, trimmed faces, written as IGES or STEP in a chosen unit with
// OCCT's own translators. Only the cad tests include this (it pulls in OCCT headers).
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepLib.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_Circle.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <IGESData_IGESModel.hxx>
#include <IGESData_IGESWriter.hxx>
#include <IGESSelect_WorkLibrary.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeFix_Face.hxx>
#include <StepData_Protocol.hxx>
#include <StepData_StepModel.hxx>
#include <StepData_StepWriter.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt2d.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/PatchSet.h"

namespace aero::cad::fixtures {

inline std::string outputPath(const std::string& name) {
    const std::filesystem::path dir = std::filesystem::path(AEROFORM_TEST_OUTPUT_DIR) / "cad";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
}

/// A biquadratic B-spline surface over [0, 2] x [0, 1] with two spans in u, values that are not
/// short decimals (so exactness is tested), scaled by `scale`.
inline Handle(Geom_BSplineSurface) wavySurface(double scale = 1.0) {
    TColgp_Array2OfPnt poles(1, 4, 1, 3);
    for (int i = 1; i <= 4; ++i)
        for (int j = 1; j <= 3; ++j)
            poles(i, j) = gp_Pnt(scale * (i - 1) / 1.5, scale * (j - 1) / 2.0,
                                 scale * (0.1 * i * j + 1.0 / 7.0 + 0.01 * i * i / 3.0));
    TColStd_Array1OfReal ku(1, 3), kv(1, 2);
    ku(1) = 0.0;
    ku(2) = 0.7;
    ku(3) = 2.0;
    kv(1) = 0.0;
    kv(2) = 1.0;
    TColStd_Array1OfInteger mu(1, 3), mv(1, 2);
    mu(1) = 3;
    mu(2) = 1;
    mu(3) = 3;
    mv.Init(3);
    return new Geom_BSplineSurface(poles, ku, kv, mu, mv, 2, 2);
}

/// A 2D B-spline curve through the given poles (clamped, uniform interior knots).
inline Handle(Geom2d_BSplineCurve) curve2d(const std::vector<gp_Pnt2d>& pts, int degree) {
    const int n = static_cast<int>(pts.size());
    TColgp_Array1OfPnt2d poles(1, n);
    for (int i = 0; i < n; ++i) poles(i + 1) = pts[static_cast<std::size_t>(i)];
    const int spans = n - degree;
    TColStd_Array1OfReal knots(1, spans + 1);
    TColStd_Array1OfInteger mults(1, spans + 1);
    for (int k = 0; k <= spans; ++k) {
        knots(k + 1) = static_cast<double>(k) / spans;
        mults(k + 1) = (k == 0 || k == spans) ? degree + 1 : 1;
    }
    return new Geom2d_BSplineCurve(poles, knots, mults, degree);
}

/// A face of `surface` bounded by a closed outer loop of two B-spline p-curves and, if `hole`, a
/// circular hole (a Geom2d_Circle p-curve), all inside [0, 2] x [0, 1]. Model-space edge curves
/// are computed by OCCT.
inline TopoDS_Face trimmedFace(const Handle(Geom_BSplineSurface) & surface, bool hole) {
    const Handle(Geom2d_BSplineCurve) lower = curve2d(
        {gp_Pnt2d(0.1, 0.1), gp_Pnt2d(0.7, 0.05), gp_Pnt2d(1.3, 0.3), gp_Pnt2d(1.9, 0.15)}, 3);
    const Handle(Geom2d_BSplineCurve) upper = curve2d(
        {gp_Pnt2d(1.9, 0.15), gp_Pnt2d(1.5, 0.9), gp_Pnt2d(0.4, 0.95), gp_Pnt2d(0.1, 0.1)}, 2);
    BRepBuilderAPI_MakeWire outer;
    outer.Add(BRepBuilderAPI_MakeEdge(lower, surface).Edge());
    outer.Add(BRepBuilderAPI_MakeEdge(upper, surface).Edge());
    BRepBuilderAPI_MakeFace make(surface, outer.Wire(), Standard_True);
    if (hole) {
        const Handle(Geom2d_Circle) circle =
            new Geom2d_Circle(gp_Ax2d(gp_Pnt2d(0.9, 0.45), gp_Dir2d(1, 0)), 0.15);
        BRepBuilderAPI_MakeWire w;
        w.Add(BRepBuilderAPI_MakeEdge(circle, surface).Edge());
        make.Add(TopoDS::Wire(w.Wire().Reversed()));
    }
    TopoDS_Face face = make.Face();
    BRepLib::BuildCurves3d(face, 1e-9);
    ShapeFix_Face fix(face);
    fix.FixOrientation();
    return fix.Face();
}

/// Writes `shape` with OCCT's IGES writer in `unit` ("MM", "M", "IN", ...; OCCT scales the
/// shape's millimetres to it) as BRep entities (mode 1) or trimmed surfaces (mode 0). With
/// `exact`, reals get 17 digits (the toolchain's recipe); else OCCT's default ~10 digits.
/// `surfaceCurves` = false writes no parameter-space curves (model-space trims only).
inline void writeIgesWithOcct(const TopoDS_Shape& shape, const char* unit, int mode,
                              const std::string& path, bool exact = true,
                              bool surfaceCurves = true) {
    IGESControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    Interface_Static::SetIVal("write.surfacecurve.mode", surfaceCurves ? 1 : 0);
    IGESControl_Writer writer(unit, mode);
    ASSERT_TRUE(writer.AddShape(shape));
    writer.ComputeModel();
    if (!exact) {
        ASSERT_TRUE(writer.Write(path.c_str()));
    } else {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        IGESData_IGESWriter iges(writer.Model());
        iges.FloatWriter().SetFormat("%.16E");
        iges.FloatWriter().SetZeroSuppress(Standard_False);
        iges.SendModel(IGESSelect_WorkLibrary::DefineProtocol());
        ASSERT_TRUE(iges.Print(out));
    }
    Interface_Static::SetIVal("write.surfacecurve.mode", 1);
}

/// Writes `shape` with OCCT's STEP writer in `unit` ("MM", "M", "INCH"; no scaling: the shape's
/// values are the file's), 17 digits when `exact`.
inline void writeStepWithOcct(const TopoDS_Shape& shape, const char* unit, const std::string& path,
                              bool exact = true) {
    STEPControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", unit);
    Interface_Static::SetCVal("write.step.unit", unit);
    STEPControl_Writer writer;
    ASSERT_EQ(writer.Transfer(shape, STEPControl_AsIs), IFSelect_RetDone);
    if (!exact) {
        ASSERT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
    } else {
        const Handle(StepData_StepModel) model = writer.Model();
        StepData_StepWriter step(model);
        step.FloatWriter().SetFormat("%.16E");
        step.FloatWriter().SetZeroSuppress(Standard_False);
        step.SendModel(Handle(StepData_Protocol)::DownCast(model->Protocol()));
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        ASSERT_TRUE(step.Print(out));
    }
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
}

/// OCCT's own reading of an IGES file with cascade unit `unit`: its B-spline faces' surfaces.
inline std::vector<Handle(Geom_BSplineSurface)> occtSurfaces(const std::string& path,
                                                             const char* unit) {
    IGESControl_Controller::Init();
    Interface_Static::SetCVal("xstep.cascade.unit", unit);
    Interface_Static::SetIVal("read.iges.bspline.continuity", 0);
    IGESControl_Reader reader;
    std::vector<Handle(Geom_BSplineSurface)> out;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) return out;
    reader.TransferRoots();
    for (TopExp_Explorer e(reader.OneShape(), TopAbs_FACE); e.More(); e.Next()) {
        Handle(Geom_Surface) s = BRep_Tool::Surface(TopoDS::Face(e.Current()));
        out.push_back(Handle(Geom_BSplineSurface)::DownCast(s));
    }
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    return out;
}

/// Poles, weights and knots of an OCCT surface equal (==) our patch's.
inline void expectSameSurface(const Geom_BSplineSurface& s, const geometry::Patch& p,
                              const std::string& what) {
    ASSERT_EQ(s.NbUPoles(), p.countU) << what;
    ASSERT_EQ(s.NbVPoles(), p.countV) << what;
    EXPECT_EQ(s.UDegree(), p.degreeU) << what;
    EXPECT_EQ(s.VDegree(), p.degreeV) << what;
    int mismatches = 0;
    for (int j = 0; j < p.countV; ++j)
        for (int i = 0; i < p.countU; ++i) {
            const gp_Pnt& q = s.Pole(i + 1, j + 1);
            const int k = p.index(i, j);
            mismatches += !(q.X() == p.points[3 * k] && q.Y() == p.points[3 * k + 1] &&
                            q.Z() == p.points[3 * k + 2]);
            if (p.rational()) mismatches += !(s.Weight(i + 1, j + 1) == p.weights[k]);
        }
    EXPECT_EQ(mismatches, 0) << what << ": poles or weights differ";
    TColStd_Array1OfReal ku(1, p.countU + p.degreeU + 1), kv(1, p.countV + p.degreeV + 1);
    s.UKnotSequence(ku);
    s.VKnotSequence(kv);
    EXPECT_EQ(std::vector<double>(ku.begin(), ku.end()), p.knotsU) << what;
    EXPECT_EQ(std::vector<double>(kv.begin(), kv.end()), p.knotsV) << what;
}

}  // namespace aero::cad::fixtures
