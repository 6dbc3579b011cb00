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
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <span>
#include <vector>

#include "common/Error.h"
#include "geometry/Trim.h"
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

// Where a patch is sampled, in its parameter space: surface points, the triangles between them
// (counter-clockwise in (u, v)) and the boundary polylines. An untrimmed patch is an n x n grid
// with its four edges; a trimmed one is clipped to its trim region (marching squares on a finer
// grid, crossings found by bisection against the trim's polygons) and its edges are the trim
// loops. It depends on the parameter space only, so deformations (which move control points)
// keep it: only the points are evaluated again.
struct Tessellation {
    bool grid = true;                         // n x n grid: sampled with nurbs::sampleGrid
    std::vector<double> uv;                   // 2 per surface point
    std::vector<std::array<int, 3>> triangles;
    std::vector<double> edgeUv;               // 2 per edge point
    std::vector<std::vector<int>> edgeLines;  // polylines into the edge points
    std::size_t trimKey = 0;                  // hash of the trim it was made for
    int points() const { return static_cast<int>(uv.size() / 2); }
    int edgePoints() const { return static_cast<int>(edgeUv.size() / 2); }
};

std::size_t hashTrim(const geometry::PatchTrim* trim) {
    if (!trim || !trim->trimmed()) return 0;
    std::size_t h = 1469598103934665603ULL;
    auto mix = [&](double x) {
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        h = (h ^ bits) * 1099511628211ULL;
    };
    std::vector<const geometry::TrimLoop*> loops{&trim->outer};
    for (const auto& l : trim->holes) loops.push_back(&l);
    for (const auto* l : loops) {
        mix(static_cast<double>(l->curves.size()));
        for (const auto& c : l->curves) {
            for (double x : c.curve.points) mix(x);
            for (double x : c.curve.knots) mix(x);
            for (double x : c.curve.weights) mix(x);
            mix(c.first);
            mix(c.last);
        }
    }
    return h == 0 ? 1 : h;
}

Tessellation gridTessellation(const Patch& s, int n, int m) {
    Tessellation t;
    const Range ru = parameterRange(s.knotsU, s.degreeU, s.countU);
    const Range rv = parameterRange(s.knotsV, s.degreeV, s.countV);
    const std::vector<double> us = uniform(ru, n), vs = uniform(rv, n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) t.uv.insert(t.uv.end(), {us[static_cast<size_t>(i)], vs[static_cast<size_t>(j)]});
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int a = i + n * j, b = a + 1, c = a + 1 + n, d = a + n;
            t.triangles.push_back({a, b, c});
            t.triangles.push_back({a, c, d});
        }
    const std::vector<double> ue = uniform(ru, m), ve = uniform(rv, m);
    for (int e = 0; e < 4; ++e) {
        std::vector<int> line;
        for (int k = 0; k < m; ++k) {
            const double u = e == 0 || e == 2 ? ue[static_cast<size_t>(k)] : (e == 1 ? ru.last : ru.first);
            const double v = e == 1 || e == 3 ? ve[static_cast<size_t>(k)] : (e == 2 ? rv.last : rv.first);
            line.push_back(t.edgePoints());
            t.edgeUv.insert(t.edgeUv.end(), {u, v});
        }
        t.edgeLines.push_back(std::move(line));
    }
    return t;
}

Tessellation trimmedTessellation(const Patch& s, const geometry::PatchTrim& trim, int n) {
    Tessellation t;
    t.grid = false;
    t.trimKey = hashTrim(&trim);
    const geometry::TrimPolygons poly = geometry::polygonize(trim, s, 24);
    const Range ru = parameterRange(s.knotsU, s.degreeU, s.countU);
    const Range rv = parameterRange(s.knotsV, s.degreeV, s.countV);
    const std::vector<double> us = uniform(ru, n), vs = uniform(rv, n);
    auto inside = [&](double u, double v) { return geometry::contains(poly, u, v); };
    std::vector<char> in(static_cast<size_t>(n) * static_cast<size_t>(n));
    std::vector<int> id(in.size(), -1);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) in[static_cast<size_t>(i + n * j)] = inside(us[static_cast<size_t>(i)], vs[static_cast<size_t>(j)]) ? 1 : 0;
    auto corner = [&](int i, int j) {
        const size_t k = static_cast<size_t>(i + n * j);
        if (id[k] < 0) {
            id[k] = t.points();
            t.uv.insert(t.uv.end(), {us[static_cast<size_t>(i)], vs[static_cast<size_t>(j)]});
        }
        return id[k];
    };
    // Crossing points on grid edges, shared by the two cells of an edge.
    std::unordered_map<long long, int> crossings;
    auto crossing = [&](int i0, int j0, int i1, int j1) {
        const long long key = (static_cast<long long>(std::min(i0 + n * j0, i1 + n * j1)) << 1) | (j0 != j1 ? 1 : 0);
        if (auto it = crossings.find(key); it != crossings.end()) return it->second;
        double a[2] = {us[static_cast<size_t>(i0)], vs[static_cast<size_t>(j0)]}, b[2] = {us[static_cast<size_t>(i1)], vs[static_cast<size_t>(j1)]};
        if (!in[static_cast<size_t>(i0 + n * j0)]) std::swap(a, b);  // a inside, b outside
        for (int it = 0; it < 30; ++it) {
            const double m[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])};
            if (inside(m[0], m[1])) {
                a[0] = m[0];
                a[1] = m[1];
            } else {
                b[0] = m[0];
                b[1] = m[1];
            }
        }
        const int k = t.points();
        t.uv.insert(t.uv.end(), {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])});
        crossings.emplace(key, k);
        return k;
    };
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
            bool inC[4];
            int count = 0;
            for (int c = 0; c < 4; ++c) count += (inC[c] = in[static_cast<size_t>(ci[c] + n * cj[c])] != 0) ? 1 : 0;
            if (count == 0) continue;
            if (count == 4) {
                const int a = corner(i, j), b = corner(i + 1, j), c = corner(i + 1, j + 1), d = corner(i, j + 1);
                t.triangles.push_back({a, b, c});
                t.triangles.push_back({a, c, d});
                continue;
            }
            // The cell clipped to the region: corners inside and edge crossings, counter-clockwise.
            std::vector<int> polygon;
            std::vector<char> isCorner;
            for (int c = 0; c < 4; ++c) {
                const int d = (c + 1) % 4;
                if (inC[c]) {
                    polygon.push_back(corner(ci[c], cj[c]));
                    isCorner.push_back(1);
                }
                if (inC[c] != inC[d]) {
                    polygon.push_back(crossing(ci[c], cj[c], ci[d], cj[d]));
                    isCorner.push_back(0);
                }
            }
            const bool saddle = count == 2 && inC[0] == inC[2];
            if (saddle && !inside(0.5 * (us[static_cast<size_t>(i)] + us[static_cast<size_t>(i + 1)]),
                                  0.5 * (vs[static_cast<size_t>(j)] + vs[static_cast<size_t>(j + 1)]))) {
                // Two separate corners of the region: a triangle at each, between its crossings.
                const std::size_t np = polygon.size();
                for (std::size_t k = 0; k < np; ++k)
                    if (isCorner[k]) t.triangles.push_back({polygon[(k + np - 1) % np], polygon[k], polygon[(k + 1) % np]});
                continue;
            }
            for (std::size_t k = 1; k + 1 < polygon.size(); ++k) t.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
        }
    // The trim loops (closed polylines) are the patch's edges.
    for (const auto& loop : poly.loops) {
        std::vector<int> line;
        for (const geometry::Point2& p : loop) {
            line.push_back(t.edgePoints());
            t.edgeUv.insert(t.edgeUv.end(), {p[0], p[1]});
        }
        if (!line.empty()) line.push_back(line.front());
        t.edgeLines.push_back(std::move(line));
    }
    return t;
}

// Evaluated samples of one patch: surface points with oriented unit normals, edge points.
// Plain arrays, filled without touching VTK (so patches can be sampled in parallel).
struct PatchSamples {
    std::vector<double> xyz;     // 3 per surface point
    std::vector<float> normals;  // 3 per surface point
    std::vector<double> edges;   // 3 per edge point
};

// Normals are flipped when `flip` is set; with `decide` the patch's orientation is chosen
// (normals pointing away from `centre` on the whole) and returned in flip.
void samplePatch(const Patch& s, const Tessellation& t, int n, const Eigen::Vector3d& centre, bool decide, bool& flip,
                 PatchSamples& out) {
    const Range ru = parameterRange(s.knotsU, s.degreeU, s.countU);
    const Range rv = parameterRange(s.knotsV, s.degreeV, s.countV);
    const size_t count = static_cast<size_t>(t.points());
    out.xyz.resize(3 * count);
    out.normals.resize(3 * count);
    if (t.grid) {
        const std::vector<double> us = uniform(ru, n), vs = uniform(rv, n);
        nurbs::sampleGrid(s, us, vs, out.xyz.data());
    } else if (count > 0) {
        nurbs::evaluate(s, t.uv, out.xyz.data());
    }
    std::vector<Eigen::Vector3d> nrm(count);
    double outward = 0;
    for (size_t k = 0; k < count; ++k) {
        nrm[k] = unitNormal(s, t.uv[2 * k], t.uv[2 * k + 1], ru, rv);
        const Eigen::Vector3d x(out.xyz[3 * k], out.xyz[3 * k + 1], out.xyz[3 * k + 2]);
        outward += nrm[k].dot(x - centre);
    }
    if (decide) flip = outward < 0;
    for (size_t k = 0; k < count; ++k) {
        const Eigen::Vector3d v = flip ? Eigen::Vector3d(-nrm[k]) : nrm[k];
        for (int c = 0; c < 3; ++c) out.normals[3 * k + static_cast<size_t>(c)] = static_cast<float>(v[c]);
    }
    out.edges.resize(3 * static_cast<size_t>(t.edgePoints()));
    if (t.edgePoints() > 0) nurbs::evaluate(s, t.edgeUv, out.edges.data());
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
    std::vector<Tessellation> tessellation;     // per patch, in parameter space
    std::vector<vtkIdType> surfaceOffset;       // first surface point of each patch
    std::vector<vtkIdType> edgeOffset;          // first edge point of each patch
    std::vector<char> flip;                     // orientation chosen at setPatchSet
    std::vector<char> visible;
    std::vector<char> highlighted;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    int controlPoints = 0;

    int patches() const { return static_cast<int>(netCounts.size()); }
    int n() const { return options.surfaceSamples; }
    int m() const { return options.edgeSamples; }
    // Trimmed patches are sampled twice as finely: the trimmed edge follows the grid.
    int trimmedN() const { return 2 * options.surfaceSamples - 1; }

    bool sameLayout(const geometry::PatchSet& set) const {
        if (set.size() != patches()) return false;
        for (int p = 0; p < set.size(); ++p) {
            const Patch& s = set.patches[static_cast<size_t>(p)];
            if (s.countU != netCounts[static_cast<size_t>(p)][0] || s.countV != netCounts[static_cast<size_t>(p)][1])
                return false;
            const std::size_t key = hashTrim(set.trimmed(p) ? &set.trims[static_cast<size_t>(p)] : nullptr);
            if (key != tessellation[static_cast<size_t>(p)].trimKey) return false;
        }
        return true;
    }

    // Writes the samples of patch p into the arrays (which have the full size already).
    void write(int p, const Patch& s, const PatchSamples& smp) {
        const vtkIdType base = surfaceOffset[static_cast<size_t>(p)];
        const vtkIdType count = static_cast<vtkIdType>(smp.xyz.size() / 3);
        vtkPoints* pts = surfacePoly->GetPoints();
        auto* normals = vtkFloatArray::SafeDownCast(surfacePoly->GetPointData()->GetNormals());
        for (vtkIdType k = 0; k < count; ++k) {
            const size_t kk = static_cast<size_t>(k);
            pts->SetPoint(base + k, smp.xyz[3 * kk], smp.xyz[3 * kk + 1], smp.xyz[3 * kk + 2]);
            normals->SetTypedTuple(base + k, smp.normals.data() + 3 * kk);
        }
        const vtkIdType edgeBase = edgeOffset[static_cast<size_t>(p)];
        vtkPoints* epts = edgePoly->GetPoints();
        for (vtkIdType k = 0; k < static_cast<vtkIdType>(smp.edges.size() / 3); ++k) {
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
            samplePatch(set.patches[static_cast<size_t>(p)], tessellation[static_cast<size_t>(p)], n(), centre, decide, f,
                        samples[static_cast<size_t>(i)]);
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
        vtkNew<vtkCellArray> triangles, lines, verts, netLines;
        std::vector<vtkIdType> ids;
        for (int p = 0; p < patches(); ++p) {
            if (!visible[static_cast<size_t>(p)]) continue;
            const Tessellation& t = tessellation[static_cast<size_t>(p)];
            const vtkIdType base = surfaceOffset[static_cast<size_t>(p)];
            const bool f = flip[static_cast<size_t>(p)] != 0;
            for (const auto& tri : t.triangles) {
                const vtkIdType c[3] = {base + tri[0], base + (f ? tri[2] : tri[1]), base + (f ? tri[1] : tri[2])};
                triangles->InsertNextCell(3, c);
            }
            for (const auto& line : t.edgeLines) {
                ids.clear();
                for (int k : line) ids.push_back(edgeOffset[static_cast<size_t>(p)] + k);
                lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
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
        for (int p = 0; p < patches(); ++p) {
            std::array<unsigned char, 3> rgb = patchColor(p, options.tintPatches);
            if (highlighted[static_cast<size_t>(p)]) rgb = {246, 196, 120};  // selected: warm amber
            const vtkIdType base = surfaceOffset[static_cast<size_t>(p)];
            for (vtkIdType k = 0; k < tessellation[static_cast<size_t>(p)].points(); ++k) colors->SetTypedTuple(base + k, rgb.data());
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
    d.tessellation.assign(static_cast<size_t>(P), {});
    d.surfaceOffset.assign(static_cast<size_t>(P), 0);
    d.edgeOffset.assign(static_cast<size_t>(P), 0);
    vtkIdType controls = 0, surfacePoints = 0, edgePoints = 0;
    for (int p = 0; p < P; ++p) {
        const Patch& s = set.patches[static_cast<size_t>(p)];
        d.tessellation[static_cast<size_t>(p)] = set.trimmed(p) ? trimmedTessellation(s, set.trims[static_cast<size_t>(p)], d.trimmedN())
                                                                : gridTessellation(s, d.n(), d.m());
        d.netCounts[static_cast<size_t>(p)] = {s.countU, s.countV};
        d.netOffset[static_cast<size_t>(p)] = controls;
        d.surfaceOffset[static_cast<size_t>(p)] = surfacePoints;
        d.edgeOffset[static_cast<size_t>(p)] = edgePoints;
        controls += s.controlCount();
        surfacePoints += d.tessellation[static_cast<size_t>(p)].points();
        edgePoints += d.tessellation[static_cast<size_t>(p)].edgePoints();
    }
    d.flip.assign(static_cast<size_t>(P), 0);
    d.visible.assign(static_cast<size_t>(P), 1);
    d.highlighted.assign(static_cast<size_t>(P), 0);
    d.controlPoints = static_cast<int>(controls);

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
    ep->SetNumberOfPoints(edgePoints);
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
    d_->tessellation.clear();
    d_->surfaceOffset.clear();
    d_->edgeOffset.clear();
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

PatchScene::SurfaceMesh PatchScene::surfaceMesh(int patch) const {
    SurfaceMesh mesh;
    if (patch < 0 || patch >= d_->patches() || !d_->surfacePoly) return mesh;
    const Tessellation& t = d_->tessellation[static_cast<size_t>(patch)];
    const vtkIdType base = d_->surfaceOffset[static_cast<size_t>(patch)];
    for (vtkIdType k = 0; k < t.points(); ++k) {
        double x[3];
        d_->surfacePoly->GetPoints()->GetPoint(base + k, x);
        mesh.points.insert(mesh.points.end(), {x[0], x[1], x[2]});
    }
    mesh.uv = t.uv;
    for (const auto& tri : t.triangles) mesh.triangles.insert(mesh.triangles.end(), {tri[0], tri[1], tri[2]});
    for (const auto& line : t.edgeLines) {
        std::vector<double> xyz;
        for (int k : line) {
            double x[3];
            d_->edgePoly->GetPoints()->GetPoint(d_->edgeOffset[static_cast<size_t>(patch)] + k, x);
            xyz.insert(xyz.end(), {x[0], x[1], x[2]});
        }
        mesh.edges.push_back(std::move(xyz));
    }
    return mesh;
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
