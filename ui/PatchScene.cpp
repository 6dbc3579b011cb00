#include "PatchScene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkMapper.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "common/Error.h"
#include "nurbs/Surface.h"

namespace aero::ui {

namespace {

using geometry::Patch;

struct Range {
    double first, last;
};

// The valid parameter interval [t_p, t_n] of a knot vector (clamped or not).
Range parameterRange(const std::vector<double>& knots, int degree, int count) {
    return {knots[static_cast<size_t>(degree)], knots[static_cast<size_t>(count)]};
}

std::vector<double> uniform(Range r, int n) {
    std::vector<double> t(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        t[static_cast<size_t>(i)] = r.first + (r.last - r.first) * i / (n - 1);
    t.back() = r.last;
    return t;
}

// Unit normal Su x Sv at (u, v). At degenerate points (a collapsed edge, e.g. a pole) the
// cross product vanishes; step towards the patch centre until it does not.
Eigen::Vector3d unitNormal(const Patch& s, double u, double v, Range ru, Range rv) {
    const double uc = 0.5 * (ru.first + ru.last), vc = 0.5 * (rv.first + rv.last);
    for (double step : {0.0, 1e-6, 1e-4, 1e-2}) {
        const auto d = nurbs::evaluateDerivatives(s, u + step * (uc - u), v + step * (vc - v), 1);
        const Eigen::Vector3d n = d.Su.cross(d.Sv);
        const double scale = d.Su.norm() * d.Sv.norm();
        if (scale > 0 && n.norm() > 1e-10 * scale) return n.normalized();
    }
    return Eigen::Vector3d::Zero();
}

// Base colour: a light grey-blue.
constexpr double kSurfaceRgb[3] = {0.70, 0.76, 0.86};

std::array<unsigned char, 3> patchColor(int patch, bool tint) {
    // Lightness factors 0.94 .. 1.06 in a pattern that differs between neighbours.
    const double f = tint ? 1.0 + 0.03 * static_cast<double>((patch * 3) % 5 - 2) : 1.0;
    std::array<unsigned char, 3> c{};
    for (int k = 0; k < 3; ++k)
        c[static_cast<size_t>(k)] =
            static_cast<unsigned char>(std::clamp(kSurfaceRgb[k] * f, 0.0, 1.0) * 255.0 + 0.5);
    return c;
}

// Samples of one patch: n x n surface points with oriented unit normals, 4 boundary curves of m
// points each, and the control points. Plain arrays, filled without touching VTK (so patches
// can be sampled in parallel).
struct PatchSamples {
    std::vector<double> xyz;      // 3 n^2, u fastest
    std::vector<float> normals;   // 3 n^2
    std::vector<double> edges;    // 3 * 4m: edges 0..3 as in nurbs::boundaryCurve
};

// Normals are flipped when `flip` is set; with `decide` the patch's orientation is chosen
// (normals pointing away from `centre` on the whole) and returned in flip.
void samplePatch(const Patch& s, int n, int m, const Eigen::Vector3d& centre, bool decide, bool& flip,
                 PatchSamples& out) {
    const Range ru = parameterRange(s.knotsU, s.degreeU, s.countU);
    const Range rv = parameterRange(s.knotsV, s.degreeV, s.countV);
    const std::vector<double> us = uniform(ru, n), vs = uniform(rv, n);
    const size_t perPatch = static_cast<size_t>(n) * static_cast<size_t>(n);
    out.xyz.resize(3 * perPatch);
    out.normals.resize(3 * perPatch);
    nurbs::sampleGrid(s, us, vs, out.xyz.data());
    std::vector<Eigen::Vector3d> nrm(perPatch);
    double outward = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t k = static_cast<size_t>(i + n * j);
            nrm[k] = unitNormal(s, us[static_cast<size_t>(i)], vs[static_cast<size_t>(j)], ru, rv);
            const Eigen::Vector3d x(out.xyz[3 * k], out.xyz[3 * k + 1], out.xyz[3 * k + 2]);
            outward += nrm[k].dot(x - centre);
        }
    if (decide) flip = outward < 0;
    for (size_t k = 0; k < perPatch; ++k) {
        const Eigen::Vector3d v = flip ? Eigen::Vector3d(-nrm[k]) : nrm[k];
        for (int c = 0; c < 3; ++c) out.normals[3 * k + static_cast<size_t>(c)] = static_cast<float>(v[c]);
    }

    const std::vector<double> ue = uniform(ru, m), ve = uniform(rv, m);
    const double u0[1] = {ru.first}, u1[1] = {ru.last}, v0[1] = {rv.first}, v1[1] = {rv.last};
    const std::span<const double> rows[4][2] = {{ue, v0}, {u1, ve}, {ue, v1}, {u0, ve}};
    out.edges.resize(3 * 4 * static_cast<size_t>(m));
    for (int e = 0; e < 4; ++e)
        nurbs::sampleGrid(s, rows[e][0], rows[e][1], out.edges.data() + 3 * static_cast<size_t>(m) * static_cast<size_t>(e));
}

}  // namespace

struct PatchScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    PatchSceneOptions options;
    vtkNew<vtkPolyDataMapper> surfaceMapper, edgeMapper, netMapper;
    vtkNew<vtkActor> surfaces, edges, nets;
    vtkSmartPointer<vtkPolyData> surfacePoly, edgePoly, netPoly;

    // Layout of the displayed set (what updatePatches() requires to stay the same).
    std::vector<std::array<int, 2>> netCounts;  // countU, countV per patch
    std::vector<vtkIdType> netOffset;           // first control point of each patch
    std::vector<char> flip;                     // orientation chosen at setPatchSet
    std::vector<char> visible;
    std::vector<char> highlighted;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    int controlPoints = 0;

    int patches() const { return static_cast<int>(netCounts.size()); }
    int n() const { return options.surfaceSamples; }
    int m() const { return options.edgeSamples; }

    bool sameLayout(const geometry::PatchSet& set) const {
        if (set.size() != patches()) return false;
        for (int p = 0; p < set.size(); ++p) {
            const Patch& s = set.patches[static_cast<size_t>(p)];
            if (s.countU != netCounts[static_cast<size_t>(p)][0] || s.countV != netCounts[static_cast<size_t>(p)][1])
                return false;
        }
        return true;
    }

    // Writes the samples of patch p into the arrays (which have the full size already).
    void write(int p, const Patch& s, const PatchSamples& smp) {
        const vtkIdType perPatch = static_cast<vtkIdType>(n()) * n();
        const vtkIdType base = perPatch * p;
        vtkPoints* pts = surfacePoly->GetPoints();
        auto* normals = vtkFloatArray::SafeDownCast(surfacePoly->GetPointData()->GetNormals());
        for (vtkIdType k = 0; k < perPatch; ++k) {
            const size_t kk = static_cast<size_t>(k);
            pts->SetPoint(base + k, smp.xyz[3 * kk], smp.xyz[3 * kk + 1], smp.xyz[3 * kk + 2]);
            normals->SetTypedTuple(base + k, smp.normals.data() + 3 * kk);
        }
        const vtkIdType edgeBase = static_cast<vtkIdType>(4) * m() * p;
        vtkPoints* epts = edgePoly->GetPoints();
        for (vtkIdType k = 0; k < 4 * static_cast<vtkIdType>(m()); ++k) {
            const size_t kk = static_cast<size_t>(k);
            epts->SetPoint(edgeBase + k, smp.edges[3 * kk], smp.edges[3 * kk + 1], smp.edges[3 * kk + 2]);
        }
        vtkPoints* npts = netPoly->GetPoints();
        for (int k = 0; k < s.controlCount(); ++k) {
            const size_t kk = static_cast<size_t>(k);
            npts->SetPoint(netOffset[static_cast<size_t>(p)] + k, s.points[3 * kk], s.points[3 * kk + 1], s.points[3 * kk + 2]);
        }
    }

    void sampleAndWrite(const geometry::PatchSet& set, const std::vector<int>& list, bool decide) {
        std::vector<PatchSamples> samples(list.size());
        const int count = static_cast<int>(list.size());
#pragma omp parallel for schedule(dynamic) if (count > 1)
        for (int i = 0; i < count; ++i) {
            const int p = list[static_cast<size_t>(i)];
            bool f = flip[static_cast<size_t>(p)] != 0;
            samplePatch(set.patches[static_cast<size_t>(p)], n(), m(), centre, decide, f, samples[static_cast<size_t>(i)]);
            flip[static_cast<size_t>(p)] = f ? 1 : 0;
        }
        for (int i = 0; i < count; ++i) {
            const int p = list[static_cast<size_t>(i)];
            write(p, set.patches[static_cast<size_t>(p)], samples[static_cast<size_t>(i)]);
        }
        surfacePoly->GetPoints()->Modified();
        surfacePoly->GetPointData()->GetNormals()->Modified();
        edgePoly->GetPoints()->Modified();
        netPoly->GetPoints()->Modified();
        surfacePoly->Modified();
        edgePoly->Modified();
        netPoly->Modified();
    }

    // Cells of the visible patches: triangles wound like the chosen normals, edge polylines,
    // control-point vertices and net lines.
    void rebuildCells() {
        const int N = n(), M = m();
        vtkNew<vtkCellArray> triangles, lines, verts, netLines;
        for (int p = 0; p < patches(); ++p) {
            if (!visible[static_cast<size_t>(p)]) continue;
            const vtkIdType base = static_cast<vtkIdType>(N) * N * p;
            const bool f = flip[static_cast<size_t>(p)] != 0;
            for (int j = 0; j + 1 < N; ++j)
                for (int i = 0; i + 1 < N; ++i) {
                    const vtkIdType a = base + i + static_cast<vtkIdType>(N) * j;
                    const vtkIdType b = a + 1, c = a + 1 + N, d = a + N;
                    const vtkIdType t0[3] = {a, f ? c : b, f ? b : c}, t1[3] = {a, f ? d : c, f ? c : d};
                    triangles->InsertNextCell(3, t0);
                    triangles->InsertNextCell(3, t1);
                }
            std::vector<vtkIdType> ids(static_cast<size_t>(M));
            for (int e = 0; e < 4; ++e) {
                for (int k = 0; k < M; ++k) ids[static_cast<size_t>(k)] = static_cast<vtkIdType>(4) * M * p + static_cast<vtkIdType>(M) * e + k;
                lines->InsertNextCell(M, ids.data());
            }
            const int cu = netCounts[static_cast<size_t>(p)][0], cv = netCounts[static_cast<size_t>(p)][1];
            const vtkIdType nb = netOffset[static_cast<size_t>(p)];
            for (int k = 0; k < cu * cv; ++k) {
                const vtkIdType id = nb + k;
                verts->InsertNextCell(1, &id);
            }
            ids.resize(static_cast<size_t>(cu));
            for (int j = 0; j < cv; ++j) {
                for (int i = 0; i < cu; ++i) ids[static_cast<size_t>(i)] = nb + i + static_cast<vtkIdType>(cu) * j;
                netLines->InsertNextCell(cu, ids.data());
            }
            ids.resize(static_cast<size_t>(cv));
            for (int i = 0; i < cu; ++i) {
                for (int j = 0; j < cv; ++j) ids[static_cast<size_t>(j)] = nb + i + static_cast<vtkIdType>(cu) * j;
                netLines->InsertNextCell(cv, ids.data());
            }
        }
        surfacePoly->SetPolys(triangles);
        edgePoly->SetLines(lines);
        netPoly->SetVerts(verts);
        netPoly->SetLines(netLines);
    }

    void recolor() {
        auto* colors = vtkUnsignedCharArray::SafeDownCast(surfacePoly->GetPointData()->GetScalars());
        if (!colors) return;
        const vtkIdType perPatch = static_cast<vtkIdType>(n()) * n();
        for (int p = 0; p < patches(); ++p) {
            std::array<unsigned char, 3> rgb = patchColor(p, options.tintPatches);
            if (highlighted[static_cast<size_t>(p)]) rgb = {246, 196, 120};  // selected: warm amber
            for (vtkIdType k = 0; k < perPatch; ++k) colors->SetTypedTuple(perPatch * p + k, rgb.data());
        }
        colors->Modified();
        surfacePoly->Modified();
    }
};

PatchScene::PatchScene(vtkRenderer* renderer, PatchSceneOptions options)
    : d_(std::make_unique<Impl>()) {
    d_->renderer = renderer;
    d_->options = options;
    d_->options.surfaceSamples = std::max(2, options.surfaceSamples);
    d_->options.edgeSamples = std::max(2, options.edgeSamples);

    // Edges and nets lie exactly on / near the surface: push filled polygons back a little.
    vtkMapper::SetResolveCoincidentTopologyToPolygonOffset();

    d_->surfaceMapper->SetScalarModeToUsePointData();
    d_->surfaceMapper->SetColorModeToDirectScalars();
    d_->surfaceMapper->ScalarVisibilityOn();
    d_->surfaces->SetMapper(d_->surfaceMapper);
    vtkProperty* sp = d_->surfaces->GetProperty();
    sp->SetInterpolationToPhong();
    sp->SetColor(kSurfaceRgb[0], kSurfaceRgb[1], kSurfaceRgb[2]);
    sp->SetAmbient(0.10);
    sp->SetDiffuse(0.85);
    sp->SetSpecular(0.25);
    sp->SetSpecularPower(40.0);
    sp->SetSpecularColor(1.0, 1.0, 1.0);

    d_->edgeMapper->ScalarVisibilityOff();
    d_->edges->SetMapper(d_->edgeMapper);
    vtkProperty* ep = d_->edges->GetProperty();
    ep->SetColor(0.13, 0.15, 0.20);
    ep->SetLineWidth(1.5f);
    ep->LightingOff();

    d_->netMapper->ScalarVisibilityOff();
    d_->nets->SetMapper(d_->netMapper);
    vtkProperty* np = d_->nets->GetProperty();
    np->SetColor(0.85, 0.33, 0.10);
    np->SetLineWidth(1.0f);
    np->SetPointSize(7.0f);
    np->RenderPointsAsSpheresOn();
    np->LightingOff();
    d_->nets->VisibilityOff();

    // Surfaces and nets are not pickable: lattice picking is done in screen space.
    d_->surfaces->PickableOff();
    d_->edges->PickableOff();
    d_->nets->PickableOff();

    clear();
    d_->renderer->AddActor(d_->surfaces);
    d_->renderer->AddActor(d_->edges);
    d_->renderer->AddActor(d_->nets);
}

PatchScene::~PatchScene() {
    d_->renderer->RemoveActor(d_->surfaces);
    d_->renderer->RemoveActor(d_->edges);
    d_->renderer->RemoveActor(d_->nets);
}

void PatchScene::setPatchSet(const geometry::PatchSet& set) {
    geometry::validate(set);  // throws GeometryError naming the patch; scene unchanged

    Impl& d = *d_;
    // The centre used to orient the patches: the middle of the control-point bounding box.
    const geometry::BoundingBox box = geometry::controlBoundingBox(set);
    d.centre = Eigen::Vector3d(0.5 * (box.min[0] + box.max[0]), 0.5 * (box.min[1] + box.max[1]),
                               0.5 * (box.min[2] + box.max[2]));
    const int P = set.size();
    d.netCounts.assign(static_cast<size_t>(P), {0, 0});
    d.netOffset.assign(static_cast<size_t>(P), 0);
    vtkIdType controls = 0;
    for (int p = 0; p < P; ++p) {
        const Patch& s = set.patches[static_cast<size_t>(p)];
        d.netCounts[static_cast<size_t>(p)] = {s.countU, s.countV};
        d.netOffset[static_cast<size_t>(p)] = controls;
        controls += s.controlCount();
    }
    d.flip.assign(static_cast<size_t>(P), 0);
    d.visible.assign(static_cast<size_t>(P), 1);
    d.highlighted.assign(static_cast<size_t>(P), 0);
    d.controlPoints = static_cast<int>(controls);

    const vtkIdType surfacePoints = static_cast<vtkIdType>(d.n()) * d.n() * P;
    d.surfacePoly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> sp;
    sp->SetDataTypeToFloat();
    sp->SetNumberOfPoints(surfacePoints);
    d.surfacePoly->SetPoints(sp);
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(surfacePoints);
    d.surfacePoly->GetPointData()->SetNormals(normals);
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(3);
    colors->SetNumberOfTuples(surfacePoints);
    d.surfacePoly->GetPointData()->SetScalars(colors);

    d.edgePoly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> ep;
    ep->SetDataTypeToFloat();
    ep->SetNumberOfPoints(static_cast<vtkIdType>(4) * d.m() * P);
    d.edgePoly->SetPoints(ep);

    d.netPoly = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> np;
    np->SetDataTypeToDouble();
    np->SetNumberOfPoints(controls);
    d.netPoly->SetPoints(np);

    std::vector<int> all(static_cast<size_t>(P));
    for (int p = 0; p < P; ++p) all[static_cast<size_t>(p)] = p;
    d.sampleAndWrite(set, all, /*decide=*/true);
    d.rebuildCells();
    d.recolor();
    d.surfaceMapper->SetInputData(d.surfacePoly);
    d.edgeMapper->SetInputData(d.edgePoly);
    d.netMapper->SetInputData(d.netPoly);
}

void PatchScene::updatePatches(const geometry::PatchSet& set, const std::vector<int>& patches) {
    if (!d_->surfacePoly || !d_->sameLayout(set)) {
        setPatchSet(set);
        return;
    }
    std::vector<int> list;
    for (int p : patches)
        if (p >= 0 && p < set.size()) list.push_back(p);
    if (list.empty()) return;
    d_->sampleAndWrite(set, list, /*decide=*/false);
}

void PatchScene::clear() {
    d_->surfacePoly = nullptr;
    d_->edgePoly = nullptr;
    d_->netPoly = nullptr;
    d_->surfaceMapper->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->edgeMapper->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->netMapper->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->netCounts.clear();
    d_->netOffset.clear();
    d_->flip.clear();
    d_->visible.clear();
    d_->highlighted.clear();
    d_->controlPoints = 0;
}

void PatchScene::setPatchVisible(int patch, bool visible) {
    if (patch < 0 || patch >= d_->patches() || (d_->visible[static_cast<size_t>(patch)] != 0) == visible) return;
    d_->visible[static_cast<size_t>(patch)] = visible ? 1 : 0;
    d_->rebuildCells();
}

bool PatchScene::patchVisible(int patch) const {
    return patch >= 0 && patch < d_->patches() && d_->visible[static_cast<size_t>(patch)] != 0;
}

void PatchScene::setHighlightedPatches(const std::vector<int>& patches) {
    if (!d_->surfacePoly) return;
    std::vector<char> h(static_cast<size_t>(d_->patches()), 0);
    for (int p : patches)
        if (p >= 0 && p < d_->patches()) h[static_cast<size_t>(p)] = 1;
    if (h == d_->highlighted) return;
    d_->highlighted = std::move(h);
    d_->recolor();
}

void PatchScene::setSurfacesVisible(bool visible) {
    d_->surfaces->SetVisibility(visible);
}
void PatchScene::setEdgesVisible(bool visible) {
    d_->edges->SetVisibility(visible);
}
void PatchScene::setControlNetsVisible(bool visible) {
    d_->nets->SetVisibility(visible);
}
bool PatchScene::surfacesVisible() const {
    return d_->surfaces->GetVisibility() != 0;
}
bool PatchScene::edgesVisible() const {
    return d_->edges->GetVisibility() != 0;
}
bool PatchScene::controlNetsVisible() const {
    return d_->nets->GetVisibility() != 0;
}

int PatchScene::patchCount() const {
    return d_->patches();
}
int PatchScene::controlPointCount() const {
    return d_->controlPoints;
}

std::array<double, 6> PatchScene::bounds() const {
    std::array<double, 6> b{0, 0, 0, 0, 0, 0};
    if (empty()) return b;
    bool first = true;
    for (vtkPolyDataMapper* mapper : {d_->surfaceMapper.Get(), d_->netMapper.Get()}) {
        double mb[6];
        mapper->GetInput()->GetBounds(mb);
        if (mb[0] > mb[1]) continue;  // empty data
        for (int k = 0; k < 3; ++k) {
            b[2 * k] = first ? mb[2 * k] : std::min(b[2 * k], mb[2 * k]);
            b[2 * k + 1] = first ? mb[2 * k + 1] : std::max(b[2 * k + 1], mb[2 * k + 1]);
        }
        first = false;
    }
    return b;
}

void PatchScene::fitCamera(vtkCamera* camera, double aspect,
                           const std::array<double, 3>& viewDirection,
                           const std::array<double, 3>& viewUp, double fill,
                           const std::vector<double>* extra) const {
    if (empty()) return;
    // Orthonormal view frame: f into the screen, r to the right, u up.
    const Eigen::Vector3d f =
        Eigen::Vector3d(viewDirection[0], viewDirection[1], viewDirection[2]).normalized();
    const Eigen::Vector3d r =
        f.cross(Eigen::Vector3d(viewUp[0], viewUp[1], viewUp[2])).normalized();
    const Eigen::Vector3d u = r.cross(f);

    // Extents of the displayed points in that frame.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
    Eigen::Vector3d hi = -lo;
    std::vector<vtkPolyData*> shown{vtkPolyData::SafeDownCast(d_->surfaceMapper->GetInput())};
    if (controlNetsVisible()) shown.push_back(vtkPolyData::SafeDownCast(d_->netMapper->GetInput()));
    for (vtkPolyData* poly : shown) {
        if (!poly || !poly->GetPoints()) continue;
        for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
            double x[3];
            poly->GetPoint(i, x);
            const Eigen::Vector3d p(x[0], x[1], x[2]);
            const Eigen::Vector3d q(p.dot(r), p.dot(u), p.dot(f));
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
    }
    if (extra) {
        for (size_t i = 0; i + 2 < extra->size(); i += 3) {
            const Eigen::Vector3d p((*extra)[i], (*extra)[i + 1], (*extra)[i + 2]);
            const Eigen::Vector3d q(p.dot(r), p.dot(u), p.dot(f));
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
    }
    if (lo.x() > hi.x()) return;
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    const Eigen::Vector3d half = 0.5 * (hi - lo);
    const Eigen::Vector3d focal = mid.x() * r + mid.y() * u + mid.z() * f;

    // Perspective fit: half extent / tan(half angle), plus the depth in front of the focal
    // plane (the nearest points are closer to the camera and look larger).
    constexpr double kPi = 3.14159265358979323846;
    const double tanV = std::tan(0.5 * camera->GetViewAngle() * kPi / 180.0);
    const double tanH = tanV * std::max(aspect, 1e-3);
    const double fit = std::max(half.x() / tanH, half.y() / tanV) / std::clamp(fill, 0.05, 1.0);
    const double dist = std::max(fit + half.z(), 1e-9);
    const Eigen::Vector3d eye = focal - dist * f;
    camera->SetFocalPoint(focal.x(), focal.y(), focal.z());
    camera->SetPosition(eye.x(), eye.y(), eye.z());
    camera->SetViewUp(u.x(), u.y(), u.z());
}

}  // namespace aero::ui
