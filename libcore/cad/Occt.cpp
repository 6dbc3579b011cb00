// The bridge to OpenCASCADE (see Occt.h): the one translation unit of the project that includes
// OCCT headers. IGES entities that our own reader does not take exactly (Iges.cpp), STEP in and
// out.
//
// Units: OCCT scales coordinates by (file unit / xstep.cascade.unit), millimetres by default.
// We set the cascade unit to the file's own unit, so the factor is exactly 1 and values come in
// as the file writes them (tests check this bit for bit).
#include "cad/Occt.h"

#include <unistd.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepLib.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dConvert.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomProjLib.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_Curve.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_IGESEntity.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Check.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <ShapeFix_Face.hxx>
#include <Standard_Failure.hxx>
#include <StepData_Protocol.hxx>
#include <StepData_StepModel.hxx>
#include <StepData_StepWriter.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <StepGeom_BSplineCurve.hxx>
#include <StepGeom_BSplineSurface.hxx>
#include <StepGeom_HArray1OfCartesianPoint.hxx>
#include <StepGeom_HArray2OfCartesianPoint.hxx>
#include <StepGeom_Curve.hxx>
#include <StepGeom_Pcurve.hxx>
#include <StepGeom_Placement.hxx>
#include <StepRepr_DefinitionalRepresentation.hxx>
#include <StepRepr_HArray1OfRepresentationItem.hxx>
#include <StepShape_Face.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TColgp_Array1OfPnt2d.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <TransferBRep.hxx>
#include <Transfer_Binder.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <set>

#include "common/AtomicFile.h"
#include "common/Error.h"
#include "geometry/Units.h"
#include "nurbs/Basis.h"

namespace aero::cad::occt {

namespace {

using geometry::Patch;
using geometry::TrimCurve;
using geometry::TrimLoop;

// OCCT's settings (Interface_Static), its default messenger and the stdout redirection below are
// process-wide: one OCCT operation at a time.
std::mutex occtMutex;

/// While alive, file descriptor 1 is a copy of descriptor 2, so whatever OCCT prints (its readers
/// report on stdout) lands on stderr and stdout stays machine-readable. Restored on scope exit,
/// exceptions included. Output of other threads meanwhile goes to stderr too.
class StdoutToStderr {
  public:
    StdoutToStderr() {
        flush();
        saved_ = ::dup(STDOUT_FILENO);
        if (saved_ >= 0 && ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
            ::close(saved_);
            saved_ = -1;
        }
    }
    ~StdoutToStderr() {
        flush();
        if (saved_ >= 0) {
            ::dup2(saved_, STDOUT_FILENO);
            ::close(saved_);
        }
    }
    StdoutToStderr(const StdoutToStderr&) = delete;
    StdoutToStderr& operator=(const StdoutToStderr&) = delete;

  private:
    static void flush() {
        std::cout.flush();
        std::fflush(stdout);
    }
    int saved_ = -1;
};

/// Call with occtMutex held, before any OCCT data exchange.
void prepareOcct(const std::string& cascadeUnit) {
    static std::once_flag once;
    std::call_once(once, [] {
        IGESControl_Controller::Init();
        STEPControl_Controller::Init();
        // The default printer writes every info message to std::cout; keep failures only, on
        // std::cerr ("cerr" is a reserved name of Message_PrinterOStream, not a file).
        const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
        messenger->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
        Handle(Message_PrinterOStream) printer =
            new Message_PrinterOStream("cerr", Standard_False, Message_Fail);
        printer->SetToColorize(Standard_False);
        messenger->AddPrinter(printer);
    });
    // Set every time: these are global and somebody else may have changed them.
    Interface_Static::SetCVal("xstep.cascade.unit", cascadeUnit.c_str());
    Interface_Static::SetIVal("read.iges.bspline.continuity",
                              0);  // keep B-spline knots as they are
    // Curves OpenCASCADE computes (p-curves of model-space trims) to 1e-9 of the file's unit,
    // not to the file's stated resolution.
    Interface_Static::SetIVal("read.precision.mode", 1);
    Interface_Static::SetRVal("read.precision.val", 1e-9);
}

std::string quoted(const std::string& path) {
    return "'" + path + "'";
}

std::string occtMessage(const Standard_Failure& e) {
    const char* text = e.GetMessageString();
    std::string type = e.DynamicType()->Name();
    return (text && *text) ? type + ": " + text : type;
}

// ------------------------------------------------------------------------------------------
// OCCT geometry <-> our plain data

Patch toPatch(const Geom_BSplineSurface& s) {
    Patch p;
    p.degreeU = s.UDegree();
    p.degreeV = s.VDegree();
    p.countU = s.NbUPoles();
    p.countV = s.NbVPoles();
    TColStd_Array1OfReal ku(1, p.countU + p.degreeU + 1), kv(1, p.countV + p.degreeV + 1);
    s.UKnotSequence(ku);
    s.VKnotSequence(kv);
    p.knotsU.assign(ku.begin(), ku.end());
    p.knotsV.assign(kv.begin(), kv.end());
    const bool rational = s.IsURational() || s.IsVRational();
    p.points.resize(3 * static_cast<std::size_t>(p.controlCount()));
    if (rational) p.weights.resize(static_cast<std::size_t>(p.controlCount()));
    for (int j = 0; j < p.countV; ++j)
        for (int i = 0; i < p.countU; ++i) {
            const int k = p.index(i, j);
            const gp_Pnt& pole = s.Pole(i + 1, j + 1);
            p.points[3 * k + 0] = pole.X();
            p.points[3 * k + 1] = pole.Y();
            p.points[3 * k + 2] = pole.Z();
            if (rational) p.weights[k] = s.Weight(i + 1, j + 1);
        }
    return p;
}

/// Flat knot vector -> (distinct knots, multiplicities), 1-based as OCCT wants them.
void compressKnots(const std::vector<double>& flat, TColStd_Array1OfReal& knots,
                   TColStd_Array1OfInteger& mults) {
    std::vector<double> distinct;
    std::vector<int> count;
    for (double k : flat) {
        if (distinct.empty() || k != distinct.back()) {
            distinct.push_back(k);
            count.push_back(0);
        }
        ++count.back();
    }
    const int n = static_cast<int>(distinct.size());
    knots.Resize(1, n, Standard_False);
    mults.Resize(1, n, Standard_False);
    for (int i = 0; i < n; ++i) {
        knots(i + 1) = distinct[static_cast<std::size_t>(i)];
        mults(i + 1) = count[static_cast<std::size_t>(i)];
    }
}

Handle(Geom_BSplineSurface) toOcct(const Patch& p) {
    TColStd_Array1OfReal ku(1, 1), kv(1, 1);
    TColStd_Array1OfInteger mu(1, 1), mv(1, 1);
    compressKnots(p.knotsU, ku, mu);
    compressKnots(p.knotsV, kv, mv);
    TColgp_Array2OfPnt poles(1, p.countU, 1, p.countV);
    TColStd_Array2OfReal weights(1, p.countU, 1, p.countV);
    for (int j = 0; j < p.countV; ++j)
        for (int i = 0; i < p.countU; ++i) {
            const int k = p.index(i, j);
            poles(i + 1, j + 1) = gp_Pnt(p.points[3 * k], p.points[3 * k + 1], p.points[3 * k + 2]);
            weights(i + 1, j + 1) = p.rational() ? p.weights[k] : 1.0;
        }
    if (p.rational())
        return new Geom_BSplineSurface(poles, weights, ku, kv, mu, mv, p.degreeU, p.degreeV);
    return new Geom_BSplineSurface(poles, ku, kv, mu, mv, p.degreeU, p.degreeV);
}

Handle(Geom2d_BSplineCurve) toOcct2d(const TrimCurve& c) {
    TColStd_Array1OfReal knots(1, 1);
    TColStd_Array1OfInteger mults(1, 1);
    compressKnots(c.curve.knots, knots, mults);
    const int n = c.curve.count();
    TColgp_Array1OfPnt2d poles(1, n);
    TColStd_Array1OfReal weights(1, n);
    for (int i = 0; i < n; ++i) {
        poles(i + 1) = gp_Pnt2d(c.curve.points[3 * i], c.curve.points[3 * i + 1]);
        weights(i + 1) = c.curve.rational() ? c.curve.weights[i] : 1.0;
    }
    if (c.curve.rational())
        return new Geom2d_BSplineCurve(poles, weights, knots, mults, c.curve.degree);
    return new Geom2d_BSplineCurve(poles, knots, mults, c.curve.degree);
}

bool clamped(const Geom_BSplineSurface& s) {
    const int pu = s.UDegree() + 1, pv = s.VDegree() + 1;
    return s.UMultiplicity(1) == pu && s.UMultiplicity(s.NbUKnots()) == pu &&
           s.VMultiplicity(1) == pv && s.VMultiplicity(s.NbVKnots()) == pv;
}

/// A p-curve on [f, l] as a clamped, non-periodic B-spline piece.
TrimCurve toTrimCurve(const Handle(Geom2d_Curve) & pcurve, double f, double l) {
    Handle(Geom2d_Curve) c = pcurve;
    while (auto t = Handle(Geom2d_TrimmedCurve)::DownCast(c)) c = t->BasisCurve();
    Handle(Geom2d_BSplineCurve) b = Handle(Geom2d_BSplineCurve)::DownCast(c);
    if (b.IsNull()) {
        b = Geom2dConvert::CurveToBSplineCurve(new Geom2d_TrimmedCurve(c, f, l));
        f = b->FirstParameter();
        l = b->LastParameter();
    }
    const int p = b->Degree() + 1;
    if (b->IsPeriodic() || b->Multiplicity(1) != p || b->Multiplicity(b->NbKnots()) != p) {
        b = Handle(Geom2d_BSplineCurve)::DownCast(b->Copy());
        b->Segment(f, l);
        if (b->IsPeriodic()) b->SetNotPeriodic();
        f = b->FirstParameter();
        l = b->LastParameter();
    }
    TrimCurve out;
    out.curve.degree = b->Degree();
    TColStd_Array1OfReal knots(1, b->NbPoles() + b->Degree() + 1);
    b->KnotSequence(knots);
    out.curve.knots.assign(knots.begin(), knots.end());
    const bool rational = b->IsRational();
    for (int i = 1; i <= b->NbPoles(); ++i) {
        out.curve.points.insert(out.curve.points.end(), {b->Pole(i).X(), b->Pole(i).Y(), 0.0});
        if (rational) out.curve.weights.push_back(b->Weight(i));
    }
    out.first = std::max(f, out.curve.knots.front());
    out.last = std::min(l, out.curve.knots.back());
    return out;
}

/// Largest distance from S(p-curve(t)) to the edge's model-space curve (projected onto it: the
/// geometric distance, whatever the two parametrizations).
double edgeDeviation(const TopoDS_Edge& edge, const Handle(Geom2d_Curve) & pcurve, double f,
                     double l, const Patch& patch) {
    if (BRep_Tool::Degenerated(edge)) return 0;
    Standard_Real f3, l3;
    TopLoc_Location loc;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, loc, f3, l3);
    if (curve.IsNull()) return 0;
    const Handle(Geom_Curve) moved =
        loc.IsIdentity() ? curve
                         : Handle(Geom_Curve)::DownCast(curve->Transformed(loc.Transformation()));
    double worst = 0;
    for (int k = 0; k <= 16; ++k) {
        const gp_Pnt2d uv = pcurve->Value(f + (l - f) * k / 16);
        const auto s = nurbs::evaluate(patch, uv.X(), uv.Y());
        const gp_Pnt x(s.x(), s.y(), s.z());
        GeomAPI_ProjectPointOnCurve proj(x, moved, f3, l3);
        double d =
            proj.NbPoints() > 0 ? proj.LowerDistance() : std::numeric_limits<double>::infinity();
        d = std::min({d, x.Distance(moved->Value(f3)), x.Distance(moved->Value(l3))});
        worst = std::max(worst, d);
    }
    return worst;
}

/// Whether a location moves nothing: every entry of its 3 x 4 matrix exactly that of the identity
/// (STEP faces carry placements that compose to the identity).
bool identity(const TopLoc_Location& loc) {
    if (loc.IsIdentity()) return true;
    const gp_Trsf t = loc.Transformation();
    for (int r = 1; r <= 3; ++r)
        for (int c = 1; c <= 4; ++c)
            if (t.Value(r, c) != (r == c ? 1.0 : 0.0)) return false;
    return true;
}

/// The edge's model-space curve projected onto the (final) surface to 1e-10 of the patch's size:
/// exact where the projection is analytic, else an approximation tighter than OpenCASCADE's
/// reader makes. Null if the projection fails or the edge is a seam or degenerate.
Handle(Geom2d_Curve)
    projectEdge(const TopoDS_Edge& edge, const TopoDS_Face& face,
                const Handle(Geom_BSplineSurface) & surface, double size, double& f, double& l) {
    if (BRep_Tool::Degenerated(edge) || BRep_Tool::IsClosed(edge, face)) return nullptr;
    TopLoc_Location loc;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, loc, f, l);
    if (curve.IsNull()) return nullptr;
    const Handle(Geom_Curve) moved =
        loc.IsIdentity() ? curve
                         : Handle(Geom_Curve)::DownCast(curve->Transformed(loc.Transformation()));
    Standard_Real tolerance = 1e-10 * size;
    try {
        return GeomProjLib::Curve2d(moved, f, l, surface, tolerance);
    } catch (const Standard_Failure&) {
        return nullptr;
    }
}

Face convertFace(const TopoDS_Face& input, bool projectEdges) {
    Face out;
    TopoDS_Face face = TopoDS::Face(input.Oriented(TopAbs_FORWARD));
    TopLoc_Location loc;
    Handle(Geom_Surface) raw = BRep_Tool::Surface(face, loc);
    if (raw.IsNull()) throw Standard_Failure("face without a surface");
    Handle(Geom_Surface) basis = raw;
    while (auto rt = Handle(Geom_RectangularTrimmedSurface)::DownCast(basis))
        basis = rt->BasisSurface();
    out.surfaceType = basis->DynamicType()->Name();

    std::vector<std::string> done;
    Handle(Geom_BSplineSurface) bspline = Handle(Geom_BSplineSurface)::DownCast(basis);
    if (bspline.IsNull()) {
        // Analytic and swept surfaces: the face with its surface and p-curves as NURBS.
        BRepBuilderAPI_NurbsConvert convert(face, Standard_True);
        face = TopoDS::Face(convert.Shape().Oriented(TopAbs_FORWARD));
        Handle(Geom_Surface) s = BRep_Tool::Surface(face);  // location applied
        while (auto rt = Handle(Geom_RectangularTrimmedSurface)::DownCast(s))
            s = rt->BasisSurface();
        bspline = Handle(Geom_BSplineSurface)::DownCast(s);
        if (bspline.IsNull())
            throw Standard_Failure("could not be converted to a B-spline surface");
        done.push_back(out.surfaceType + " converted to an exact NURBS surface");
    } else if (!identity(loc)) {
        bspline = Handle(Geom_BSplineSurface)::DownCast(BRep_Tool::Surface(face));
        done.push_back("moved by its transformation");
    }
    if (bspline->IsUPeriodic() || bspline->IsVPeriodic()) {
        bspline = Handle(Geom_BSplineSurface)::DownCast(bspline->Copy());
        if (bspline->IsUPeriodic()) bspline->SetUNotPeriodic();
        if (bspline->IsVPeriodic()) bspline->SetVNotPeriodic();
        done.push_back("periodic knots made non-periodic");
    }
    if (!clamped(*bspline)) {
        bspline = Handle(Geom_BSplineSurface)::DownCast(bspline->Copy());
        Standard_Real s0, s1, t0, t1;
        bspline->Bounds(s0, s1, t0, t1);
        bspline->Segment(s0, s1, t0, t1);  // the same surface, end knots of full multiplicity
        done.push_back("unclamped knots clamped");
    }
    out.converted = !done.empty();
    for (const std::string& d : done) out.conversion += (out.conversion.empty() ? "" : "; ") + d;
    out.patch = toPatch(*bspline);
    // Our NURBS evaluate up to degree 9 (fixed workspaces): check before anything evaluates.
    nurbs::validate(out.patch, "the converted surface");
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t a = 0; a < out.patch.points.size(); ++a) {
        lo[a % 3] = std::min(lo[a % 3], out.patch.points[a]);
        hi[a % 3] = std::max(hi[a % 3], out.patch.points[a]);
    }
    const double size =
        std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);  // of the control net

    // The loops in the surface's parameter space, each curve in the direction the wire runs.
    geometry::PatchTrim trim;
    const TopoDS_Wire outer = BRepTools::OuterWire(face);
    int wires = 0;
    for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next()) {
        ++wires;
        const TopoDS_Wire wire = TopoDS::Wire(w.Current());
        TrimLoop loop;
        for (BRepTools_WireExplorer we(wire, face); we.More(); we.Next()) {
            const TopoDS_Edge& edge = we.Current();
            Standard_Real f, l;
            const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, f, l);
            if (pcurve.IsNull()) {
                out.trimProblem = "an edge of its boundary has no parameter-space curve";
                break;
            }
            TrimCurve tc = toTrimCurve(pcurve, f, l);
            if (tc.curve.degree > nurbs::kMaxDegree) {
                out.trimProblem = "a parameter-space curve of degree " +
                                  std::to_string(tc.curve.degree) + " (Aeroform's go up to " +
                                  std::to_string(nurbs::kMaxDegree) + ")";
                break;
            }
            double deviation = edgeDeviation(edge, pcurve, f, l, out.patch);
            if (projectEdges && deviation > 1e-12 * size) {
                // OpenCASCADE's reader computed this p-curve: project the edge more tightly and
                // keep whichever lies closer to it.
                Standard_Real pf, pl;
                if (const Handle(Geom2d_Curve) projected =
                        projectEdge(edge, face, bspline, size, pf, pl);
                    !projected.IsNull()) {
                    const double d = edgeDeviation(edge, projected, pf, pl, out.patch);
                    TrimCurve candidate = toTrimCurve(projected, pf, pl);
                    if (d < deviation && candidate.curve.degree <= nurbs::kMaxDegree) {
                        deviation = d;
                        tc = std::move(candidate);
                    }
                }
            }
            out.trimDeviation = std::max(out.trimDeviation, deviation);
            loop.curves.push_back(we.Orientation() == TopAbs_REVERSED ? geometry::reversed(tc)
                                                                      : tc);
        }
        if (!out.trimProblem.empty()) break;
        if (loop.curves.empty()) continue;
        if (wire.IsSame(outer)) {
            if (!geometry::onParameterBoundary(loop, out.patch)) trim.outer = std::move(loop);
        } else {
            trim.holes.push_back(std::move(loop));
        }
    }
    if (wires == 0) out.trimProblem.clear();  // a face on its natural bounds
    if (out.trimProblem.empty() && trim.trimmed()) {
        try {
            geometry::validate(trim, out.patch, "its trim");
            out.trim = std::move(trim);
        } catch (const GeometryError& e) {
            out.trimProblem = e.what();
        }
    }
    return out;
}

void appendFaces(const TopoDS_Shape& shape, bool projectEdges, std::vector<Face>& out,
                 std::string& failure) {
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    for (int n = 1; n <= faces.Extent(); ++n) {
        try {
            out.push_back(convertFace(TopoDS::Face(faces(n)), projectEdges));
        } catch (const Standard_Failure& e) {
            failure += (failure.empty() ? "" : "; ") + std::string("face ") + std::to_string(n) +
                       ": " + occtMessage(e);
        } catch (const GeometryError& e) {
            failure += (failure.empty() ? "" : "; ") + std::string("face ") + std::to_string(n) +
                       ": " + e.what();
        }
    }
}

const geometry::LengthUnit& unitOrMm(const std::string& name) {
    const geometry::LengthUnit* u = name.empty() ? nullptr : geometry::findLengthUnit(name);
    return u ? *u : *geometry::findLengthUnit("mm");
}

/// xstep.cascade.unit's name of a unit ("INCH" for inches, the IGES names otherwise).
std::string cascadeName(const geometry::LengthUnit& u) {
    return std::string(u.igesName);
}

double millimetres(const geometry::LengthUnit& u) {
    return static_cast<double>(u.tenthNanometres) / 1e7;
}

}  // namespace

std::vector<EntityFaces> transferIgesEntities(const std::string& path, const std::string& occtUnit,
                                              const std::vector<int>& directoryEntries,
                                              const std::vector<char>& projectEdges) {
    std::vector<EntityFaces> results(directoryEntries.size());
    std::lock_guard lock(occtMutex);
    StdoutToStderr quiet;
    try {
        prepareOcct(occtUnit);
        IGESControl_Reader reader;
        // (ReadStream does not work for IGES in OCCT 7.6: the file is read a second time.)
        if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
            throw InputError(quoted(path) + " is not a readable IGES file");
        const Handle(IGESData_IGESModel) model = reader.IGESModel();
        const Handle(Transfer_TransientProcess) process =
            reader.WS()->TransferReader()->TransientProcess();
        for (std::size_t k = 0; k < directoryEntries.size(); ++k) {
            const int number = (directoryEntries[k] + 1) / 2;
            EntityFaces& r = results[k];
            if (number < 1 || number > model->NbEntities()) {
                r.failure = "not in OpenCASCADE's model of the file";
                continue;
            }
            const Handle(IGESData_IGESEntity) entity = model->Entity(number);
            const int before = reader.NbShapes();
            try {
                reader.TransferEntity(entity);
            } catch (const Standard_Failure& e) {
                r.failure = occtMessage(e);
                continue;
            }
            const bool project = k < projectEdges.size() && projectEdges[k];
            for (int s = before + 1; s <= reader.NbShapes(); ++s)
                appendFaces(reader.Shape(s), project, r.faces, r.failure);
            if (r.faces.empty() && r.failure.empty()) {
                if (const Handle(Transfer_Binder) binder = process->Find(entity); !binder.IsNull())
                    for (int f = 1; f <= binder->Check()->NbFails(); ++f)
                        r.failure +=
                            std::string(r.failure.empty() ? "" : "; ") + binder->Check()->CFail(f);
                if (r.failure.empty()) r.failure = "OpenCASCADE built no face from it";
            }
        }
    } catch (const Standard_Failure& e) {
        throw InputError("cannot read IGES file " + quoted(path) + ": " + occtMessage(e));
    }
    return results;
}

namespace {

// OpenCASCADE's STEP translator uses the entities a file refers to without checking them: one it
// could not read (a syntax error, a reference to nothing or to something of another type) is a
// null handle there and the transfer crashes, e.g. on a control point of a B-spline, a placement's
// location or a direction (found by fuzz_step, tests/fuzz). Such a file is refused naming the
// file and the first entity. Points of B-splines and placements are also checked directly.
void checkStepControlPoints(STEPControl_Reader& reader, const std::string& path) {
    const Handle(StepData_StepModel) model = reader.StepModel();
    if (model.IsNull()) return;
    // The general case: OpenCASCADE records what it could not load (syntax errors, unresolved
    // references, wrong parameter counts or types) and then translates the rest with null handles
    // where those entities should be. Files it loads cleanly have no such failures.
    Interface_CheckIterator checks = reader.WS()->ModelCheckList();
    int fails = 0;
    std::string first;
    for (checks.Start(); checks.More(); checks.Next()) {
        const Handle(Interface_Check)& check = checks.Value();
        if (first.empty() && check->NbFails() > 0) {
            const int n = checks.Number();
            first = (n > 0 && n <= model->NbEntities()
                         ? "#" + std::to_string(model->IdentLabel(model->Value(n))) + ": "
                         : std::string()) +
                    check->CFail(1);
        }
        fails += check->NbFails();
    }
    if (fails > 0)
        throw InputError("STEP file " + quoted(path) + " is malformed (" + std::to_string(fails) +
                         " error" + (fails > 1 ? "s" : "") + " reading it; the first: " + first + ")");
    for (int i = 1; i <= model->NbEntities(); ++i) {
        const Handle(Standard_Transient) entity = model->Value(i);
        bool bad = false;
        const char* what = nullptr;
        if (const auto curve = Handle(StepGeom_BSplineCurve)::DownCast(entity); !curve.IsNull()) {
            what = "B-spline curve";
            const Handle(StepGeom_HArray1OfCartesianPoint) points = curve->ControlPointsList();
            bad = points.IsNull();
            for (int k = bad ? 0 : points->Lower(); !bad && k <= points->Upper(); ++k)
                bad = points->Value(k).IsNull();
        } else if (const auto surface = Handle(StepGeom_BSplineSurface)::DownCast(entity);
                   !surface.IsNull()) {
            what = "B-spline surface";
            const Handle(StepGeom_HArray2OfCartesianPoint) points = surface->ControlPointsList();
            bad = points.IsNull();
            for (int r = bad ? 0 : points->LowerRow(); !bad && r <= points->UpperRow(); ++r)
                for (int c = points->LowerCol(); !bad && c <= points->UpperCol(); ++c)
                    bad = points->Value(r, c).IsNull();
        } else if (const auto placement = Handle(StepGeom_Placement)::DownCast(entity);
                   !placement.IsNull()) {
            what = "placement";
            bad = placement->Location().IsNull();
        } else if (const auto pcurve = Handle(StepGeom_Pcurve)::DownCast(entity); !pcurve.IsNull()) {
            // The p-curve's 2D curve is the first item of its definitional representation; an item
            // of another type (a point) was a null curve in the translator (SEGV in
            // StepToGeom::MakeCurve2d; found by fuzz_step, 2026-12-05).
            const Handle(StepRepr_DefinitionalRepresentation) rep = pcurve->ReferenceToCurve();
            const Handle(StepRepr_HArray1OfRepresentationItem) items = rep.IsNull() ? nullptr : rep->Items();
            const Handle(Standard_Transient) item =
                items.IsNull() || items->Length() < 1 ? nullptr : Handle(Standard_Transient)(items->Value(items->Lower()));
            if (item.IsNull() || !item->IsKind(STANDARD_TYPE(StepGeom_Curve))) {
                std::string why = " is missing";
                if (!rep.IsNull()) {
                    why = " #" + std::to_string(model->IdentLabel(rep));
                    why += item.IsNull() ? " has no items"
                                         : " holds #" + std::to_string(model->IdentLabel(item)) + " (" +
                                               item->DynamicType()->Name() + "), not a curve";
                }
                throw InputError("STEP file " + quoted(path) + ": p-curve #" + std::to_string(model->IdentLabel(entity)) +
                                 ": its definitional representation" + why);
            }
        }
        if (bad)
            throw InputError("STEP file " + quoted(path) + ": " + what + " #" +
                             std::to_string(model->IdentLabel(entity)) +
                             " has a point that is not a readable CARTESIAN_POINT");
    }
}

}  // namespace

StepFile readStep(const std::string& path) {
    StepFile out;
    std::lock_guard lock(occtMutex);
    StdoutToStderr quiet;
    try {
        prepareOcct("MM");
        STEPControl_Reader reader;
        if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
            throw InputError(quoted(path) + " is not a readable STEP file");
        checkStepControlPoints(reader, path);
        TColStd_SequenceOfAsciiString lengths, angles, solidAngles;
        reader.FileUnits(lengths, angles, solidAngles);
        std::set<std::string> distinct;
        for (int i = 1; i <= lengths.Length(); ++i) distinct.insert(lengths(i).ToCString());
        const geometry::LengthUnit* unit = nullptr;
        if (!distinct.empty()) {
            out.unitName = lengths(1).ToCString();
            unit = geometry::findLengthUnit(out.unitName);
            if (!unit)
                out.warnings.push_back("the file's length unit '" + out.unitName +
                                       "' is not one Aeroform knows: coordinates were converted to "
                                       "millimetres by OpenCASCADE");
            if (distinct.size() > 1) {
                std::string all;
                for (const std::string& d : distinct) all += (all.empty() ? "" : ", ") + d;
                out.warnings.push_back("the file uses several length units (" + all +
                                       "): all coordinates were converted to '" + out.unitName +
                                       "'");
            }
        }
        const geometry::LengthUnit& target = unit ? *unit : *geometry::findLengthUnit("mm");
        if (unit) out.unit = std::string(unit->name);
        prepareOcct(cascadeName(target));
        reader.SetSystemLengthUnit(millimetres(target));
        out.roots = reader.NbRootsForTransfer();
        reader.TransferRoots();
        const TopoDS_Shape shape = reader.OneShape();
        if (shape.IsNull())
            throw InputError("STEP file " + quoted(path) + " has no shape OpenCASCADE can read");
        // The #id of each face's STEP entity, by the face's shape (without location).
        const Handle(Transfer_TransientProcess) process =
            reader.WS()->TransferReader()->TransientProcess();
        const Handle(StepData_StepModel) model = reader.StepModel();
        std::map<const TopoDS_TShape*, int> ids;
        for (int i = 1; i <= model->NbEntities(); ++i) {
            const Handle(Standard_Transient) entity = model->Value(i);
            if (!entity->IsKind(STANDARD_TYPE(StepShape_Face))) continue;
            const TopoDS_Shape result = TransferBRep::ShapeResult(process, entity);
            if (!result.IsNull()) ids[result.TShape().get()] = model->IdentLabel(entity);
        }
        TopTools_IndexedMapOfShape faces;
        TopExp::MapShapes(shape, TopAbs_FACE, faces);
        for (int n = 1; n <= faces.Extent(); ++n) {
            Face f;
            try {
                f = convertFace(TopoDS::Face(faces(n)), true);
            } catch (const Standard_Failure& e) {
                out.warnings.push_back("face " + std::to_string(n) + " skipped: " + occtMessage(e));
                continue;
            } catch (const GeometryError& e) {
                out.warnings.push_back("face " + std::to_string(n) + " skipped: " + e.what());
                continue;
            }
            if (auto it = ids.find(faces(n).TShape().get()); it != ids.end()) f.stepId = it->second;
            out.faces.push_back(std::move(f));
        }
    } catch (const Standard_Failure& e) {
        throw InputError("cannot read STEP file " + quoted(path) + ": " + occtMessage(e));
    }
    return out;
}

namespace {

TopoDS_Wire makeWire(const TrimLoop& loop, const Handle(Geom_Surface) & surface) {
    BRepBuilderAPI_MakeWire wire;
    for (const TrimCurve& c : loop.curves) {
        BRepBuilderAPI_MakeEdge edge(toOcct2d(c), surface, c.first, c.last);
        if (!edge.IsDone()) throw Standard_Failure("a trim curve gives no edge");
        wire.Add(edge.Edge());
        if (!wire.IsDone()) throw Standard_Failure("the trim curves do not join into a wire");
    }
    return wire.Wire();
}

TopoDS_Face makeFace(const Patch& p, const geometry::PatchTrim* trim) {
    const Handle(Geom_BSplineSurface) surface = toOcct(p);
    if (!trim || !trim->trimmed()) return BRepBuilderAPI_MakeFace(surface, Precision::Confusion());
    const TrimLoop outer = trim->outer.curves.empty()
                               ? geometry::rectangleLoop(p.knotsU.front(), p.knotsU.back(),
                                                         p.knotsV.front(), p.knotsV.back())
                               : trim->outer;
    BRepBuilderAPI_MakeFace make(surface, makeWire(outer, surface), Standard_True);
    for (const TrimLoop& hole : trim->holes) make.Add(makeWire(hole, surface));
    if (!make.IsDone()) throw Standard_Failure("no face from the trim loops");
    TopoDS_Face face = make.Face();
    // The model-space edge curves STEP needs, and the loops' orientation (outer counter-clockwise,
    // holes clockwise) as OCCT wants it: a change of direction only, not of geometry.
    BRepLib::BuildCurves3d(face, 1e-9);
    ShapeFix_Face fix(face);
    fix.FixOrientation();
    return fix.Face();
}

}  // namespace

void writeStep(const geometry::PatchSet& set, const std::string& path, const std::string& schema) {
    geometry::validate(set);
    AtomicFile file(path, "STEP file");
    errno = 0;
    std::ofstream out(file.temporary(), std::ios::binary | std::ios::trunc);
    if (!out) file.fail();
    {
        std::lock_guard lock(occtMutex);
        StdoutToStderr quiet;
        try {
            const geometry::LengthUnit& unit = unitOrMm(set.unit);
            prepareOcct(cascadeName(unit));
            Interface_Static::SetCVal("write.step.unit", cascadeName(unit).c_str());
            Interface_Static::SetCVal("write.step.schema",
                                      schema == "AP242" ? "AP242DIS" : "AP214IS");
            Interface_Static::SetIVal("write.surfacecurve.mode", 1);  // write the p-curves too
            TopoDS_Compound compound;
            BRep_Builder builder;
            builder.MakeCompound(compound);
            for (int k = 0; k < set.size(); ++k) {
                try {
                    builder.Add(compound,
                                makeFace(set.patches[k], set.trimmed(k) ? &set.trims[k] : nullptr));
                } catch (const Standard_Failure& e) {
                    throw GeometryError(set.describe(k) +
                                        ": rejected by OpenCASCADE: " + occtMessage(e));
                }
            }
            STEPControl_Writer writer;
            if (writer.Transfer(compound, STEPControl_AsIs) != IFSelect_RetDone)
                throw InputError("cannot write STEP file " + quoted(path) +
                                 ": OpenCASCADE could not translate the faces");
            const Handle(StepData_StepModel) model = writer.Model();
            StepData_StepWriter step(model);
            step.FloatWriter().SetFormat("%.16E");               // 17 significant digits: exact
            step.FloatWriter().SetZeroSuppress(Standard_False);  // with it, exponents are lost
            step.SendModel(Handle(StepData_Protocol)::DownCast(model->Protocol()));
            if (!step.Print(out) || !out.flush()) file.fail();
        } catch (const Standard_Failure& e) {
            throw InputError("cannot write STEP file " + quoted(path) + ": " + occtMessage(e));
        }
    }
    out.close();
    if (!out) file.fail();
    file.commit();
}

}  // namespace aero::cad::occt
