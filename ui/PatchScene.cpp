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

vtkSmartPointer<vtkPolyData> buildSurfaces(const geometry::PatchSet& set, int n, bool tint,
                                           const Eigen::Vector3d& centre) {
    const vtkIdType perPatch = static_cast<vtkIdType>(n) * n;
    const vtkIdType total = perPatch * set.size();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    points->SetNumberOfPoints(total);
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(total);
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(3);
    colors->SetNumberOfTuples(total);
    vtkNew<vtkCellArray> triangles;
    triangles->AllocateExact(2 * static_cast<vtkIdType>(n - 1) * (n - 1) * set.size(),
                             6 * static_cast<vtkIdType>(n - 1) * (n - 1) * set.size());

    std::vector<double> xyz(3 * static_cast<size_t>(perPatch));
    std::vector<Eigen::Vector3d> nrm(static_cast<size_t>(perPatch));
    for (int p = 0; p < set.size(); ++p) {
        const Patch& s = set.patches[static_cast<size_t>(p)];
        const Range ru = parameterRange(s.knotsU, s.degreeU, s.countU);
        const Range rv = parameterRange(s.knotsV, s.degreeV, s.countV);
        const std::vector<double> us = uniform(ru, n), vs = uniform(rv, n);
        nurbs::sampleGrid(s, us, vs, xyz.data());

        // Orientation: normals of the patch should on the whole point away from the centre
        // of the set (outward for closed-ish bodies); flip the whole patch otherwise.
        double outward = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const size_t k = static_cast<size_t>(i + n * j);
                nrm[k] =
                    unitNormal(s, us[static_cast<size_t>(i)], vs[static_cast<size_t>(j)], ru, rv);
                const Eigen::Vector3d x(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
                outward += nrm[k].dot(x - centre);
            }
        const bool flip = outward < 0;

        const vtkIdType base = perPatch * p;
        const auto rgb = patchColor(p, tint);
        for (vtkIdType k = 0; k < perPatch; ++k) {
            const size_t kk = static_cast<size_t>(k);
            points->SetPoint(base + k, xyz[3 * kk], xyz[3 * kk + 1], xyz[3 * kk + 2]);
            const Eigen::Vector3d m = flip ? Eigen::Vector3d(-nrm[kk]) : nrm[kk];
            const float nv[3] = {static_cast<float>(m.x()), static_cast<float>(m.y()),
                                 static_cast<float>(m.z())};
            normals->SetTypedTuple(base + k, nv);
            colors->SetTypedTuple(base + k, rgb.data());
        }
        // Two triangles per grid cell, wound like Su x Sv (or reversed with the normals).
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                const vtkIdType a = base + i + static_cast<vtkIdType>(n) * j;
                const vtkIdType b = a + 1, c = a + 1 + n, d = a + n;
                if (!flip) {
                    const vtkIdType t0[3] = {a, b, c}, t1[3] = {a, c, d};
                    triangles->InsertNextCell(3, t0);
                    triangles->InsertNextCell(3, t1);
                } else {
                    const vtkIdType t0[3] = {a, c, b}, t1[3] = {a, d, c};
                    triangles->InsertNextCell(3, t0);
                    triangles->InsertNextCell(3, t1);
                }
            }
    }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->SetPolys(triangles);
    poly->GetPointData()->SetNormals(normals);
    poly->GetPointData()->SetScalars(colors);
    return poly;
}

vtkSmartPointer<vtkPolyData> buildEdges(const geometry::PatchSet& set, int m) {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    vtkNew<vtkCellArray> lines;
    std::vector<double> xyz(3 * static_cast<size_t>(m));
    std::vector<vtkIdType> ids(static_cast<size_t>(m));
    for (const Patch& s : set.patches) {
        const Range ru = parameterRange(s.knotsU, s.degreeU, s.countU);
        const Range rv = parameterRange(s.knotsV, s.degreeV, s.countV);
        const std::vector<double> us = uniform(ru, m), vs = uniform(rv, m);
        const double u0[1] = {ru.first}, u1[1] = {ru.last}, v0[1] = {rv.first}, v1[1] = {rv.last};
        // Edges 0..3 as in nurbs::boundaryCurve: v = v0, u = u1, v = v1, u = u0.
        const std::span<const double> rows[4][2] = {{us, v0}, {u1, vs}, {us, v1}, {u0, vs}};
        for (const auto& edge : rows) {
            nurbs::sampleGrid(s, edge[0], edge[1], xyz.data());
            for (int k = 0; k < m; ++k) {
                const size_t kk = static_cast<size_t>(k);
                ids[kk] = points->InsertNextPoint(xyz[3 * kk], xyz[3 * kk + 1], xyz[3 * kk + 2]);
            }
            lines->InsertNextCell(m, ids.data());
        }
    }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->SetLines(lines);
    return poly;
}

vtkSmartPointer<vtkPolyData> buildControlNets(const geometry::PatchSet& set) {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> verts, lines;
    std::vector<vtkIdType> ids;
    for (const Patch& s : set.patches) {
        const vtkIdType base = points->GetNumberOfPoints();
        for (int k = 0; k < s.controlCount(); ++k) {
            const size_t kk = static_cast<size_t>(k);
            points->InsertNextPoint(s.points[3 * kk], s.points[3 * kk + 1], s.points[3 * kk + 2]);
            const vtkIdType id = base + k;
            verts->InsertNextCell(1, &id);
        }
        ids.resize(static_cast<size_t>(s.countU));
        for (int j = 0; j < s.countV; ++j) {
            for (int i = 0; i < s.countU; ++i) ids[static_cast<size_t>(i)] = base + s.index(i, j);
            lines->InsertNextCell(s.countU, ids.data());
        }
        ids.resize(static_cast<size_t>(s.countV));
        for (int i = 0; i < s.countU; ++i) {
            for (int j = 0; j < s.countV; ++j) ids[static_cast<size_t>(j)] = base + s.index(i, j);
            lines->InsertNextCell(s.countV, ids.data());
        }
    }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->SetVerts(verts);
    poly->SetLines(lines);
    return poly;
}

}  // namespace

struct PatchScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    PatchSceneOptions options;
    vtkNew<vtkPolyDataMapper> surfaceMapper, edgeMapper, netMapper;
    vtkNew<vtkActor> surfaces, edges, nets;
    int patches = 0;
    int controlPoints = 0;
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

    // The centre used to orient the patches: the middle of the control-point bounding box.
    const geometry::BoundingBox box = geometry::controlBoundingBox(set);
    const Eigen::Vector3d centre(0.5 * (box.min[0] + box.max[0]), 0.5 * (box.min[1] + box.max[1]),
                                 0.5 * (box.min[2] + box.max[2]));

    auto surfaces = buildSurfaces(set, d_->options.surfaceSamples, d_->options.tintPatches, centre);
    auto edges = buildEdges(set, d_->options.edgeSamples);
    auto nets = buildControlNets(set);
    d_->surfaceMapper->SetInputData(surfaces);
    d_->edgeMapper->SetInputData(edges);
    d_->netMapper->SetInputData(nets);
    d_->patches = set.size();
    d_->controlPoints = set.controlPointCount();
}

void PatchScene::clear() {
    d_->surfaceMapper->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->edgeMapper->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->netMapper->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->patches = 0;
    d_->controlPoints = 0;
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
    return d_->patches;
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
                           const std::array<double, 3>& viewUp, double fill) const {
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
