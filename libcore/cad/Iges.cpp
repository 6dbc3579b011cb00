// IGES import and export through OpenCASCADE (see Iges.h). The only translation unit of the
// project that includes OCCT headers.
//
// Exactness: we write reals with 17 significant digits ("%.16E", zero suppression off), both
// sides work in millimetres (so OCCT scales by exactly 1), the reader keeps B-spline knots as
// they are (read.iges.bspline.continuity = 0) and every entity 128 is flagged open, because the
// reader turns a surface flagged closed into a periodic one with different knots and poles.
// OCCT parses reals with a correctly rounded strtod, so write -> read is bit for bit.
#include "cad/Iges.h"

#include <unistd.h>

#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESEntity.hxx>
#include <IGESData_IGESModel.hxx>
#include <IGESData_IGESWriter.hxx>
#include <IGESGeom_BSplineSurface.hxx>
#include <IGESSelect_WorkLibrary.hxx>
#include <Interface_Check.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <Precision.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColStd_HArray1OfInteger.hxx>
#include <TColStd_HArray1OfReal.hxx>
#include <TColStd_HArray2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TColgp_HArray2OfXYZ.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <Transfer_Binder.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string_view>

#include "common/AtomicFile.h"
#include "common/Error.h"

namespace aero::cad {
namespace {

using geometry::Patch;
using geometry::PatchSet;

// OCCT's settings (Interface_Static), its default messenger and the stdout redirection below
// are process-wide: one IGES operation at a time.
std::mutex occtMutex;

/// While alive, file descriptor 1 is a copy of descriptor 2, so whatever OCCT prints (the
/// reader reports on stdout) lands on stderr and stdout stays machine-readable. Restored on
/// scope exit, exceptions included. Output of other threads meanwhile goes to stderr too.
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

/// Call with occtMutex held, before any IGES work.
void prepareOcct() {
    static std::once_flag once;
    std::call_once(once, [] {
        IGESControl_Controller::Init();
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
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    Interface_Static::SetIVal("read.iges.bspline.continuity", 0);
}

std::string quoted(const std::string& path) {
    return "'" + path + "'";
}

std::string occtMessage(const Standard_Failure& e) {
    const char* text = e.GetMessageString();
    std::string type = e.DynamicType()->Name();
    return (text && *text) ? type + ": " + text : type;
}

/// "entity 3 (type 128, directory line 5)": how messages name an IGES entity.
double igesValue(std::string_view t) {
    std::string s(t);
    for (char& c : s) {
        if (c == 'D' || c == 'd') c = 'E';  // Fortran double exponent
    }
    return s.empty() ? 0.0 : std::strtod(s.c_str(), nullptr);
}

/// Entity 128 (rational B-spline surface), checked against its own counts before OCCT reads it
/// (issue #20: counts or degrees that do not match the data crashed OCCT's reader; weights of 0,
/// -1 or 1e-300 became a polynomial surface without a word). p: the parameters, p[0] = 128.
void checkBSplineSurfaceEntity(const std::vector<std::string_view>& p, const std::string& path, const std::string& what) {
    auto fail = [&](const std::string& why) { throw InputError("IGES file " + quoted(path) + ": " + what + ": " + why); };
    if (p.size() < 10) fail("only " + std::to_string(p.size()) + " parameters (a B-spline surface has at least 10 before its data)");
    const double K1 = igesValue(p[1]), K2 = igesValue(p[2]), M1 = igesValue(p[3]), M2 = igesValue(p[4]);
    for (double v : {K1, K2, M1, M2}) {
        if (v != std::floor(v) || v < 0) fail("the counts and degrees (K1 K2 M1 M2 = " + std::string(p[1]) + " " + std::string(p[2]) + " " +
                                              std::string(p[3]) + " " + std::string(p[4]) + ") must be non-negative integers");
    }
    if (M1 < 1 || M2 < 1 || M1 > 25 || M2 > 25) fail("degrees " + std::string(p[3]) + ", " + std::string(p[4]) + " outside [1, 25]");
    if (K1 < M1 || K2 < M2 || K1 > 1e5 || K2 > 1e5) {
        fail("upper indices K1 = " + std::string(p[1]) + ", K2 = " + std::string(p[2]) +
             " must lie in [degree, 100000] (K + 1 control points per direction)");
    }
    const double nu = K1 + 1, nv = K2 + 1;
    if (nu * nv > 1e7) fail(std::to_string(static_cast<long>(nu * nv)) + " control points: more than the 10 million accepted");
    const double knotsU = K1 + M1 + 2, knotsV = K2 + M2 + 2;
    const double needed = 10 + knotsU + knotsV + 4 * nu * nv + 4;
    if (static_cast<double>(p.size()) < needed) {
        fail("K1 = " + std::string(p[1]) + ", K2 = " + std::string(p[2]) + ", M1 = " + std::string(p[3]) + ", M2 = " +
             std::string(p[4]) + " need " + std::to_string(static_cast<long>(needed)) + " parameters (knots, weights, points, "
             "parameter range), the entity has " + std::to_string(p.size()));
    }
    const std::size_t w0 = 10 + static_cast<std::size_t>(knotsU + knotsV);
    for (std::size_t k = 0; k < static_cast<std::size_t>(nu * nv); ++k) {
        const double w = igesValue(p[w0 + k]);
        if (!(w >= 1e-100) || !std::isfinite(w)) {
            fail("weight " + std::to_string(k + 1) + " is " + std::string(p[w0 + k]) +
                 " (weights must be positive and not vanishingly small)");
        }
    }
}

std::string describeEntity(int number, int type) {
    return "entity " + std::to_string(number) + " (type " + std::to_string(type) +
           ", directory line " + std::to_string(2 * number - 1) + ")";
}

// ------------------------------------------------------------------------------------------
// Reading: our own look at the text first

std::string readText(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError("cannot open IGES file " + quoted(path) + ": is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError("cannot open IGES file " + quoted(path) + ": " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad())
        throw InputError("cannot read IGES file " + quoted(path) + ": " + std::strerror(errno));
    return std::move(text).str();
}

/// An IGES parameter that is not a string: empty (default value), integer or real, with an
/// optional E or D exponent.
bool isIgesNumber(std::string_view t) {
    auto digit = [&](std::size_t i) {
        return i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]));
    };
    std::size_t i = 0, digits = 0;
    if (t.empty()) return true;
    if (t[i] == '+' || t[i] == '-') ++i;
    for (; digit(i); ++i) ++digits;
    if (i < t.size() && t[i] == '.')
        for (++i; digit(i); ++i) ++digits;
    if (digits == 0) return false;
    if (i < t.size() && std::strchr("EeDd", t[i])) {
        ++i;
        if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
        if (!digit(i)) return false;
        while (digit(i)) ++i;
    }
    return i == t.size();
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    return s;
}

/// Checks the fixed-format structure (section letter in column 73) and that every
/// non-string parameter of a geometric entity (types 100-199 and 500-599) is a number.
/// OCCT accepts "NaN" or garbage in a real field silently and makes up a value, so this is
/// the only place such a file is caught. Throws InputError naming the file and the entity.
void checkIgesText(const std::string& text, const std::string& path) {
    std::string global;
    std::map<int, std::string> params;  // directory entry line -> its parameter data
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.size() < 73) continue;
        const char section = line[72];
        if (section == 'G') global.append(line, 0, 72);
        if (section == 'P') params[std::atoi(line.substr(64, 8).c_str())].append(line, 0, 64);
    }
    if (global.empty()) throw InputError(quoted(path) + " is not an IGES file (no global section)");

    // Delimiters: the first two global parameters, each empty (default) or "1Hx".
    char pd = ',', rd = ';';
    std::size_t at = 0;
    if (global.compare(0, 2, "1H") == 0 && global.size() > 2) {
        pd = global[2];
        at = 3;
    }
    if (at < global.size() && global[at] == pd) ++at;
    if (global.compare(at, 2, "1H") == 0 && global.size() > at + 2) rd = global[at + 2];

    for (const auto& [de, data] : params) {
        std::string_view s = data;
        int type = 0, index = 0;
        std::vector<std::string_view> numbers;  // the entity's parameters (type 128 only)
        for (std::size_t i = 0; i < s.size();) {
            ++index;
            std::size_t start = i;
            while (start < s.size() && s[start] == ' ') ++start;
            std::size_t h = start;
            while (h < s.size() && std::isdigit(static_cast<unsigned char>(s[h]))) ++h;
            std::size_t end;
            if (h > start && h < s.size() && s[h] == 'H') {  // Hollerith string nHxxx
                std::size_t length = 0;
                for (std::size_t d = start; d < h; ++d)
                    length = std::min<std::size_t>(10 * length + (s[d] - '0'), s.size());
                end = std::min(s.size(), h + 1 + length);
                while (end < s.size() && s[end] != pd && s[end] != rd) ++end;
            } else {
                end = std::min(s.find(pd, i), s.find(rd, i));
                if (end == std::string_view::npos) end = s.size();
                const std::string_view token = trim(s.substr(i, end - i));
                if (index == 1) type = std::atoi(std::string(token).c_str());
                const bool geometric = (type >= 100 && type < 200) || (type >= 500 && type < 600);
                if (geometric && !isIgesNumber(token))
                    throw InputError("IGES file " + quoted(path) + ": " +
                                     describeEntity((de + 1) / 2, type) + ", parameter " +
                                     std::to_string(index) + " is not a number: '" +
                                     std::string(token) + "'");
                if (type == 128) numbers.push_back(token);
            }
            if (end >= s.size() || s[end] == rd) break;  // after the record delimiter: comment
            i = end + 1;
        }
        if (type == 128) checkBSplineSurfaceEntity(numbers, path, describeEntity((de + 1) / 2, type));
    }
}

// ------------------------------------------------------------------------------------------
// Reading: OCCT faces to patches

/// The face's surface as a non-periodic B-spline, with what it took in the report.
Handle(Geom_BSplineSurface)
    faceSurface(const TopoDS_Face& face, const std::string& what, IgesReadReport& report) {
    Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
    if (surface.IsNull()) throw Standard_Failure("face without a surface");
    Standard_Real u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);

    bool trimmed = false;
    if (auto rt = Handle(Geom_RectangularTrimmedSurface)::DownCast(surface); !rt.IsNull()) {
        if (rt->BasisSurface()->IsKind(STANDARD_TYPE(Geom_BSplineSurface))) {
            surface = rt->BasisSurface();
            trimmed = true;
        }
    }

    auto bspline = Handle(Geom_BSplineSurface)::DownCast(surface);
    if (bspline.IsNull()) {
        // Analytic surfaces are often infinite or periodic: convert the part the face uses.
        Handle(Geom_Surface) part = surface;
        if (!surface->IsKind(STANDARD_TYPE(Geom_RectangularTrimmedSurface)))
            part = new Geom_RectangularTrimmedSurface(surface, u0, u1, v0, v1);
        bspline = GeomConvert::SurfaceToBSplineSurface(part);
        ++report.converted;
        report.warnings.push_back(what + ": " + surface->DynamicType()->Name() +
                                  " converted to a B-spline surface");
    } else if (!trimmed) {
        // Trimming curves are not read; a face narrower than its surface is trimmed.
        Standard_Real s0, s1, t0, t1;
        bspline->Bounds(s0, s1, t0, t1);
        const double tol = Precision::PConfusion() * std::max({1.0, s1 - s0, t1 - t0});
        trimmed = u0 > s0 + tol || u1 < s1 - tol || v0 > t0 + tol || v1 < t1 - tol;
    }
    if (trimmed) {
        ++report.trimmed;
        report.warnings.push_back(what + ": trimmed face; its whole (untrimmed) surface is used");
    }

    if (bspline->IsUPeriodic() || bspline->IsVPeriodic()) {
        bspline = Handle(Geom_BSplineSurface)::DownCast(bspline->Copy());
        if (bspline->IsUPeriodic()) bspline->SetUNotPeriodic();
        if (bspline->IsVPeriodic()) bspline->SetVNotPeriodic();
        report.warnings.push_back(what + ": periodic surface converted to a non-periodic one");
    }
    // Our knot vectors are clamped; an unperiodized surface (or a file's) may not be.
    const auto clamped = [](const Geom_BSplineSurface& s) {
        const int pu = s.UDegree() + 1, pv = s.VDegree() + 1;
        return s.UMultiplicity(1) == pu && s.UMultiplicity(s.NbUKnots()) == pu &&
               s.VMultiplicity(1) == pv && s.VMultiplicity(s.NbVKnots()) == pv;
    };
    if (!clamped(*bspline)) {
        bspline = Handle(Geom_BSplineSurface)::DownCast(bspline->Copy());
        Standard_Real s0, s1, t0, t1;
        bspline->Bounds(s0, s1, t0, t1);
        bspline->Segment(s0, s1, t0, t1);  // same surface, end knots of full multiplicity
    }
    return bspline;
}

/// Transfers the roots one at a time, because OCCT skips silently an entity it cannot build.
/// An entity 128 that gives no face is a GeometryError (OCCT's reason in the message); any
/// other root that fails is skipped with a warning. Returns the faces of all results.
TopTools_IndexedMapOfShape transferFaces(IGESControl_Reader& reader, const std::string& path,
                                         IgesReadReport& report) {
    const Handle(Transfer_TransientProcess) process =
        reader.WS()->TransferReader()->TransientProcess();
    for (int r = 1; r <= reader.NbRootsForTransfer(); ++r) {
        const auto entity = Handle(IGESData_IGESEntity)::DownCast(reader.RootForTransfer(r));
        const int before = reader.NbShapes();
        reader.TransferOneRoot(r);
        bool face = false;
        for (int k = before + 1; k <= reader.NbShapes(); ++k)
            face = face || TopExp_Explorer(reader.Shape(k), TopAbs_FACE).More();
        if (entity.IsNull()) continue;

        std::string reason;
        if (const Handle(Transfer_Binder) binder = process->Find(entity); !binder.IsNull())
            for (int f = 1; f <= binder->Check()->NbFails(); ++f)
                reason += std::string(reason.empty() ? "" : "; ") + binder->Check()->CFail(f);
        if (face || (reason.empty() && entity->TypeNumber() != 128)) continue;

        const std::string what =
            describeEntity(reader.Model()->Number(entity), entity->TypeNumber());
        if (reason.empty()) reason = "no surface built";
        if (entity->TypeNumber() == 128)
            throw GeometryError("IGES file " + quoted(path) + ": " + what +
                                " is not a valid B-spline surface: " + reason);
        report.warnings.push_back(what + " skipped: " + reason);
    }
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(reader.OneShape(), TopAbs_FACE, faces);
    return faces;
}

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

// ------------------------------------------------------------------------------------------
// Writing

/// Flat knot vector -> (distinct knots, multiplicities), 1-based as OCCT wants them.
void compressKnots(const std::vector<double>& flat, Handle(TColStd_HArray1OfReal) & knots,
                   Handle(TColStd_HArray1OfInteger) & mults) {
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
    knots = new TColStd_HArray1OfReal(1, n);
    mults = new TColStd_HArray1OfInteger(1, n);
    for (int i = 0; i < n; ++i) {
        knots->SetValue(i + 1, distinct[i]);
        mults->SetValue(i + 1, count[i]);
    }
}

/// A rational patch whose weights are all equal becomes polynomial in OCCT (same surface).
Handle(Geom_BSplineSurface) toOcct(const Patch& p) {
    Handle(TColStd_HArray1OfReal) ku, kv;
    Handle(TColStd_HArray1OfInteger) mu, mv;
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
        return new Geom_BSplineSurface(poles, weights, ku->Array1(), kv->Array1(), mu->Array1(),
                                       mv->Array1(), p.degreeU, p.degreeV);
    return new Geom_BSplineSurface(poles, ku->Array1(), kv->Array1(), mu->Array1(), mv->Array1(),
                                   p.degreeU, p.degreeV);
}

/// Clears the "closed" flags of every entity 128: the reader makes a surface flagged closed
/// periodic (re-knotted, fewer poles), which would break the exact round trip. Our patches
/// carry no notion of closure, so they are written open.
void writeOpen(const Handle(IGESData_IGESModel) & model) {
    for (int n = 1; n <= model->NbEntities(); ++n) {
        auto e = Handle(IGESGeom_BSplineSurface)::DownCast(model->Value(n));
        if (e.IsNull() || !(e->IsClosedU() || e->IsClosedV())) continue;
        const int nu = e->UpperIndexU(), nv = e->UpperIndexV();
        const int du = e->DegreeU(), dv = e->DegreeV();
        Handle(TColStd_HArray1OfReal) ku = new TColStd_HArray1OfReal(-du, nu + 1);
        Handle(TColStd_HArray1OfReal) kv = new TColStd_HArray1OfReal(-dv, nv + 1);
        for (int i = -du; i <= nu + 1; ++i) ku->SetValue(i, e->KnotU(i));
        for (int j = -dv; j <= nv + 1; ++j) kv->SetValue(j, e->KnotV(j));
        Handle(TColStd_HArray2OfReal) w = new TColStd_HArray2OfReal(0, nu, 0, nv);
        Handle(TColgp_HArray2OfXYZ) poles = new TColgp_HArray2OfXYZ(0, nu, 0, nv);
        for (int i = 0; i <= nu; ++i)
            for (int j = 0; j <= nv; ++j) {
                w->SetValue(i, j, e->Weight(i, j));
                poles->SetValue(i, j, e->Pole(i, j).XYZ());
            }
        e->Init(nu, nv, du, dv, Standard_False, Standard_False, e->IsPolynomial(), e->IsPeriodicU(),
                e->IsPeriodicV(), ku, kv, w, poles, e->UMin(), e->UMax(), e->VMin(), e->VMax());
    }
}

}  // namespace

PatchSet readIges(const std::string& path, IgesReadReport* report) {
    IgesReadReport local;
    IgesReadReport& rep = report ? *report : local;
    rep = {};

    const std::string text = readText(path);
    checkIgesText(text, path);

    PatchSet set;
    set.source = path;
    {
        std::lock_guard lock(occtMutex);
        StdoutToStderr quiet;
        try {
            prepareOcct();
            IGESControl_Reader reader;
            // (ReadStream does not work for IGES in OCCT 7.6: the file is read a second time.)
            if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
                throw InputError(quoted(path) + " is not a readable IGES file");

            const IGESData_GlobalSection& header = reader.IGESModel()->GlobalSection();
            if (header.UnitFlag() != 2) {
                const Handle(TCollection_HAsciiString) unit = header.UnitName();
                rep.warnings.push_back(std::string("file unit is ") +
                                       (unit.IsNull() ? "unknown" : unit->ToCString()) +
                                       "; coordinates converted to millimetres");
            }

            const TopTools_IndexedMapOfShape faces = transferFaces(reader, path, rep);
            for (int n = 1; n <= faces.Extent(); ++n) {
                const std::string name = "face " + std::to_string(n);
                try {
                    set.patches.push_back(toPatch(*faceSurface(TopoDS::Face(faces(n)), name, rep)));
                } catch (const Standard_Failure& e) {
                    throw InputError("cannot read IGES file " + quoted(path) + ": " + name + ": " +
                                     occtMessage(e));
                }
                set.names.push_back(name);
            }
            rep.faces = faces.Extent();
            if (set.patches.empty())
                throw InputError("IGES file " + quoted(path) + " has no surfaces");
        } catch (const Standard_Failure& e) {
            throw InputError("cannot read IGES file " + quoted(path) + ": " + occtMessage(e));
        }
    }
    geometry::validate(set);
    return set;
}

void writeIges(const PatchSet& set, const std::string& path) {
    geometry::validate(set);
    // Written to a temporary file and renamed over the target: a failed write (disk full) leaves
    // the existing file as it was; a symlink's target is replaced, the link kept.
    AtomicFile file(path, "IGES file");
    errno = 0;
    std::ofstream out(file.temporary(), std::ios::binary | std::ios::trunc);
    if (!out) file.fail();
    try {
        std::lock_guard lock(occtMutex);
        StdoutToStderr quiet;
        prepareOcct();
        IGESControl_Writer writer("MM", 0);
        for (int k = 0; k < set.size(); ++k) {
            Handle(Geom_BSplineSurface) surface;
            try {
                surface = toOcct(set.patches[k]);
            } catch (const Standard_Failure& e) {
                throw GeometryError(set.describe(k) +
                                    ": rejected by OpenCASCADE: " + occtMessage(e));
            }
            if (!writer.AddGeom(surface))
                throw GeometryError("cannot write " + set.describe(k) + " to IGES");
        }
        writer.ComputeModel();
        const Handle(IGESData_IGESModel)& model = writer.Model();
        writeOpen(model);
        IGESData_GlobalSection header = model->GlobalSection();
        header.SetFileName(
            new TCollection_HAsciiString(std::filesystem::path(path).filename().string().c_str()));
        model->SetGlobalSection(header);

        IGESData_IGESWriter iges(model);
        iges.FloatWriter().SetFormat("%.16E");               // 17 significant digits: exact
        iges.FloatWriter().SetZeroSuppress(Standard_False);  // with it, exponents are lost
        iges.SendModel(IGESSelect_WorkLibrary::DefineProtocol());
        if (!iges.Print(out) || !out.flush()) file.fail();
    } catch (const Standard_Failure& e) {
        throw InputError("cannot write IGES file " + quoted(path) + ": " + occtMessage(e));
    }
    out.close();
    if (!out) file.fail();
    file.commit();
}

}  // namespace aero::cad
