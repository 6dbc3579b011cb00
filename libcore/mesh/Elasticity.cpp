// The elasticity move of the control grid and its reverse, the mesh adjoint (Elasticity.h); the
// element they assemble is HexElement.cpp.
#include "mesh/Elasticity.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "common/Error.h"
#include "mesh/BlockCg.h"
#include "mesh/HexElement.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace aero::mesh {

std::vector<char> boundaryConstraints(const MultiBlockMesh& m) {
    std::vector<char> c(m.control.size(), 0);
    for (const ControlBlock& b : m.blocks) {
        for (int f = 0; f < 6; ++f) {
            const BoundaryKind kind = b.faces[f].kind;
            if (kind == BoundaryKind::Interface) continue;
            const int d = f / 2, fixed = (f % 2 == 0) ? 0 : b.count[d] - 1;
            const int a1 = (d + 1) % 3, a2 = (d + 2) % 3;
            for (int t = 0; t < b.count[a2]; ++t) {
                for (int s = 0; s < b.count[a1]; ++s) {
                    int ijk[3];
                    ijk[d] = fixed;
                    ijk[a1] = s;
                    ijk[a2] = t;
                    const std::size_t g = static_cast<std::size_t>(b.nodes[b.local(ijk[0], ijk[1], ijk[2])]);
                    if (kind == BoundaryKind::Symmetry) {
                        c[3 * g + 1] = 1;
                    } else {
                        c[3 * g] = c[3 * g + 1] = c[3 * g + 2] = 1;
                    }
                }
            }
        }
    }
    return c;
}

// Every control cell of every block in order (blocks, then k, j, i), with its corner nodes.
struct CellList {
    std::vector<int> nodes;         // 8 per cell, VTK order
    std::vector<int> block;         // per cell
    std::vector<std::array<int, 3>> index;  // per cell, (i, j, k) in its block
    long count() const { return static_cast<long>(block.size()); }
};

namespace {

CellList listCells(const MultiBlockMesh& m) {
    CellList l;
    for (std::size_t bi = 0; bi < m.blocks.size(); ++bi) {
        const ControlBlock& b = m.blocks[bi];
        const int off[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
        for (int k = 0; k + 1 < b.count[2]; ++k) {
            for (int j = 0; j + 1 < b.count[1]; ++j) {
                for (int i = 0; i + 1 < b.count[0]; ++i) {
                    for (int a = 0; a < 8; ++a) l.nodes.push_back(b.nodes[b.local(i + off[a][0], j + off[a][1], k + off[a][2])]);
                    l.block.push_back(static_cast<int>(bi));
                    l.index.push_back({i, j, k});
                }
            }
        }
    }
    return l;
}

}  // namespace

// The structure of K_ff for one control grid's topology and constraints, in 3x3 node blocks,
// built once per move (or kept between moves by a MoveWorkspace) and reused by every increment
// with its buffers: the
// block rows (nodes with at least one free DOF), the block pattern, and where each corner pair of
// each cell goes. A node with some DOFs constrained (a symmetry-plane node: u_y = 0) keeps its
// block row; the constrained component's row and column hold the identity and a zero right-hand
// side, so the free DOFs see exactly K_ff. Assembly is a parallel pass over the cells' element
// matrices and one scatter in cell order (the same sums in the same order every time: bitwise
// reproducible whatever the thread count).
struct StiffnessLayout {
    CellList cells;
    std::vector<char> constrained;  // per DOF
    std::vector<int> freeIndex;     // per DOF: its index in the block system's vectors, -1 when constrained
    std::vector<int> blockRow;      // per node: its block row, -1 when all three DOFs are constrained
    int blockRows = 0;
    std::vector<int> slot;  // per cell, 8 x 8 corner pairs: the block index, -1 when either node has no block row
    // Buffers reused by every increment (no page faults for fresh allocations).
    std::vector<double> elements;  // 576 per cell of one chunk of cells
    Block3Matrix A;                // K_ff's pattern, and its values once assembled
    std::vector<double> rhs;
    BlockIncompleteCholesky preconditioner;
    CgWorkspace cg;                               // the solves' work vectors
    std::vector<std::vector<double>> guessBasis;  // the earlier solutions on the free DOFs
    // MoveWorkspace::setKeepIncrements: each increment's K_ff values and factor of the last move
    // that recorded a history (`keptStamp`, 0 when none is whole), for its mesh adjoint. They are
    // swapped in and out of A and the preconditioner (no copies): the increment assembles and
    // factors straight into its own buffers.
    struct KeptIncrement {
        std::vector<double> values;
        BlockIncompleteCholesky::Factor factor;
        bool factored = false;  // the incomplete factorization succeeded
        double meanVolume = 0;
    };
    std::vector<KeptIncrement> kept;
    std::uint64_t keptStamp = 0;
    ElasticityOptions keptOptions;
    int size() const { return 3 * blockRows; }
};

namespace {

StiffnessLayout makeLayout(const MultiBlockMesh& m, CellList cellList, const std::vector<char>& constrained) {
    StiffnessLayout L;
    L.cells = std::move(cellList);
    L.constrained = constrained;
    const int nodes = static_cast<int>(m.control.size() / 3);
    L.blockRow.assign(nodes, -1);
    L.freeIndex.assign(m.control.size(), -1);
    for (int n = 0; n < nodes; ++n) {
        if (constrained[3 * n] && constrained[3 * n + 1] && constrained[3 * n + 2]) continue;
        L.blockRow[n] = L.blockRows++;
        for (int c = 0; c < 3; ++c) {
            if (!constrained[3 * n + c]) L.freeIndex[3 * n + c] = 3 * L.blockRow[n] + c;
        }
    }
    const long cells = L.cells.count();
    // The block pattern straight from the cells: each node's incident cells (in cell order), then
    // each block row's neighbours among their corners, sorted without duplicates.
    std::vector<int> incidentStart(nodes + 1, 0), incident(8 * static_cast<std::size_t>(cells));
    for (long c = 0; c < 8 * cells; ++c) ++incidentStart[L.cells.nodes[c] + 1];
    for (int n = 0; n < nodes; ++n) incidentStart[n + 1] += incidentStart[n];
    {
        std::vector<int> next(incidentStart.begin(), incidentStart.end() - 1);
        for (long c = 0; c < cells; ++c) {
            for (int a = 0; a < 8; ++a) incident[next[L.cells.nodes[8 * c + a]]++] = static_cast<int>(c);
        }
    }
    Block3Matrix& A = L.A;
    A.rows = L.blockRows;
    A.rowStart.assign(A.rows + 1, 0);
    A.cols.clear();
    std::vector<int> row;
    for (int n = 0; n < nodes; ++n) {
        const int r = L.blockRow[n];
        if (r < 0) continue;
        row.assign(1, r);
        for (int t = incidentStart[n]; t < incidentStart[n + 1]; ++t) {
            const int* cn = &L.cells.nodes[8 * static_cast<std::size_t>(incident[t])];
            for (int b = 0; b < 8; ++b) {
                if (L.blockRow[cn[b]] >= 0) row.push_back(L.blockRow[cn[b]]);
            }
        }
        std::sort(row.begin(), row.end());
        row.erase(std::unique(row.begin(), row.end()), row.end());
        A.cols.insert(A.cols.end(), row.begin(), row.end());
        A.rowStart[r + 1] = static_cast<int>(A.cols.size());
    }
    A.values.resize(9 * A.cols.size());  // zeroed by every assembly
    L.slot.assign(static_cast<std::size_t>(cells) * 64, -1);
#pragma omp parallel for schedule(static)
    for (long c = 0; c < cells; ++c) {
        const int* cn = &L.cells.nodes[8 * c];
        for (int a = 0; a < 8; ++a) {
            const int ra = L.blockRow[cn[a]];
            if (ra < 0) continue;
            const int* first = L.A.cols.data() + L.A.rowStart[ra];
            const int* last = L.A.cols.data() + L.A.rowStart[ra + 1];
            for (int b = 0; b < 8; ++b) {
                const int rb = L.blockRow[cn[b]];
                if (rb >= 0) L.slot[64 * static_cast<std::size_t>(c) + 8 * a + b] = static_cast<int>(std::lower_bound(first, last, rb) - L.A.cols.data());
            }
        }
    }
    return L;
}

// K restricted to the free DOFs (in layout.A) and the right-hand side -K_fc u_c of one increment
// (in layout.rhs), at the current control grid; or the first inverted cell (nothing assembled).
struct FreeSystem {
    double meanVolume = 0;
    bool invalidCell = false;
    std::string message;
};

FreeSystem assembleFree(const MultiBlockMesh& m, StiffnessLayout& L, const std::vector<double>& prescribed,
                        const ElasticityOptions& o) {
    FreeSystem s;
    const long cells = L.cells.count();
    auto corners = [&](long c, double* x) {
        for (int a = 0; a < 8; ++a) {
            for (int d = 0; d < 3; ++d) x[3 * a + d] = m.control[3 * static_cast<std::size_t>(L.cells.nodes[8 * c + a]) + d];
        }
    };
    // Cell volumes in parallel; the mean (the size-stiffening reference) summed in cell order. A
    // cell with non-positive volume has no stiffness of the right sign: report the first instead
    // of assembling an indefinite K.
    std::vector<double> volume(cells);
#pragma omp parallel for schedule(static)
    for (long c = 0; c < cells; ++c) {
        double x[24];
        corners(c, x);
        volume[c] = cellVolume(x);
    }
    double total = 0;
    for (long c = 0; c < cells; ++c) {
        const double vol = volume[c];
        if (!(vol > 0)) {
            double x[24], centre[3] = {0, 0, 0};
            corners(c, x);
            for (int a = 0; a < 8; ++a) {
                for (int d = 0; d < 3; ++d) centre[d] += x[3 * a + d] / 8.0;
            }
            const std::array<int, 3>& ijk = L.cells.index[c];
            char buf[320];
            std::snprintf(buf, sizeof buf,
                          "control cell (%d, %d, %d) of block '%s' near (%.4g, %.4g, %.4g) has volume %.3g (inverted)",
                          ijk[0], ijk[1], ijk[2], m.blocks[L.cells.block[c]].name.c_str(), centre[0], centre[1], centre[2],
                          vol);
            s.invalidCell = true;
            s.message = buf;
            return s;
        }
        total += vol;
    }
    s.meanVolume = total / std::max(1L, cells);
    // Element matrices in parallel, then their scatter, chunk by chunk (a chunk's matrices stay in
    // cache, and the paper-size grid does not hold 51 MB of them at once). The scatter is split by
    // block rows: each thread adds the chunk's contributions to its own range of rows, cell by
    // cell, so every entry is summed in cell order whatever the thread count (the same bits on 1
    // or 2 threads, as the solves).
    constexpr long kChunk = 512;
    L.elements.resize(static_cast<std::size_t>(std::min(cells, kChunk)) * 576);
    L.rhs.assign(L.size(), 0.0);
    double* values = L.A.values.data();
    const long valueCount = static_cast<long>(L.A.values.size());
#pragma omp parallel for schedule(static)
    for (long v = 0; v < valueCount; ++v) values[v] = 0.0;
    for (long c0 = 0; c0 < cells; c0 += kChunk) {
        const long c1 = std::min(cells, c0 + kChunk);
#pragma omp parallel for schedule(static)
        for (long c = c0; c < c1; ++c) {
            double x[24];
            corners(c, x);
            hexStiffness<double>(x, modulusWithVolume(x, volume[c], s.meanVolume, o), o.poisson, &L.elements[576 * static_cast<std::size_t>(c - c0)]);
        }
#pragma omp parallel
        {
#if defined(_OPENMP)
            const int parts = omp_get_num_threads(), part = omp_get_thread_num();
#else
            const int parts = 1, part = 0;
#endif
            const int rowBegin = static_cast<int>(static_cast<long>(L.blockRows) * part / parts);
            const int rowEnd = static_cast<int>(static_cast<long>(L.blockRows) * (part + 1) / parts);
            for (long c = c0; c < c1; ++c) {
                const int* cn = &L.cells.nodes[8 * c];
                const double* K = &L.elements[576 * static_cast<std::size_t>(c - c0)];
                const int* slot = &L.slot[64 * static_cast<std::size_t>(c)];
                for (int a = 0; a < 8; ++a) {
                    const int row = L.blockRow[cn[a]];
                    if (row < rowBegin || row >= rowEnd) continue;  // another thread's row, or none
                    for (int ra = 0; ra < 3; ++ra) {
                        const int fr = L.freeIndex[3 * cn[a] + ra];
                        if (fr < 0) continue;
                        const double* Krow = K + 24 * (3 * a + ra);
                        for (int b = 0; b < 8; ++b) {
                            double* block = slot[8 * a + b] >= 0 ? values + 9 * static_cast<std::size_t>(slot[8 * a + b]) + 3 * ra : nullptr;
                            for (int cb = 0; cb < 3; ++cb) {
                                const int gc = 3 * cn[b] + cb;
                                if (L.constrained[gc]) {
                                    L.rhs[fr] -= Krow[3 * b + cb] * prescribed[gc];
                                } else {
                                    block[cb] += Krow[3 * b + cb];
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    // The identity for the constrained components of nodes that keep a block row.
    const int nodes = static_cast<int>(L.blockRow.size());
    for (int n = 0; n < nodes; ++n) {
        const int r = L.blockRow[n];
        if (r < 0) continue;
        for (int c = 0; c < 3; ++c) {
            if (!L.constrained[3 * n + c]) continue;
            const int* first = L.A.cols.data() + L.A.rowStart[r];
            const int* last = L.A.cols.data() + L.A.rowStart[r + 1];
            const long diag = std::lower_bound(first, last, r) - L.A.cols.data();
            values[9 * diag + 4 * c] = 1.0;
        }
    }
    return s;
}

// Solves A x = rhs as the options ask: conjugate gradients with the incomplete block Cholesky,
// then (Auto, Direct) a supernodal sparse Cholesky. Factors once; several right-hand sides reuse
// the factors (the mesh adjoint's functionals share each increment's K).
class FreeSolver {
public:
    // `keptFactor`: ic already holds A's factorization (a kept increment's), and whether it
    // succeeded; otherwise it is computed here.
    FreeSolver(const Block3Matrix& A, BlockIncompleteCholesky& ic, CgWorkspace& work, const ElasticityOptions& o,
               std::optional<bool> keptFactor = std::nullopt)
        : A_(A), o_(o), ic_(ic), work_(work) {
        if (o.solver != ElasticityOptions::Solver::Direct) preconditioned_ = keptFactor ? *keptFactor : ic_.compute(A);
    }
    bool preconditioned() const { return preconditioned_; }

    // x0: the starting guess. Fills the report fields of r (iterations, residual, converged,
    // direct, message).
    std::vector<double> solve(const std::vector<double>& rhs, const std::vector<double>& x0, IncrementResult& r) {
        std::vector<double> sol = x0;
        bool solved = false;
        if (o_.solver != ElasticityOptions::Solver::Direct) {
            const int limit = o_.solver == ElasticityOptions::Solver::Auto ? std::min(o_.maxIterations, o_.directAfter)
                                                                            : o_.maxIterations;
            if (preconditioned_) {
                const CgReport cg = conjugateGradients(A_, ic_, rhs, sol, o_.tolerance, limit, work_);
                r.iterations = cg.iterations;
                r.residual = cg.residual;
                r.converged = cg.converged;
                if (!r.converged) {
                    r.message = "PCG stopped at relative residual " + std::to_string(r.residual) + " after " +
                                std::to_string(r.iterations) + " iterations";
                }
            } else {
                r.residual = 1.0;
                r.message = "the incomplete Cholesky factorization broke down (a control cell is degenerate)";
            }
            solved = r.converged || o_.solver == ElasticityOptions::Solver::Iterative;
        }
        if (solved) return sol;
        // Supernodal sparse Cholesky: K is SPD for -1 < poisson < 0.5 and positive cell volumes,
        // and the solve is exact to round-off however distorted the cells are.
        r.direct = true;
        if (!factored_) {
            scalar_ = toScalar(A_);
            llt_.cholmod().print = 0;  // no CHOLMOD warnings on stderr: a failure is reported in r.message
            llt_.compute(scalar_);
            factored_ = true;
        }
        if (llt_.info() != Eigen::Success) {
            r.converged = false;
            r.residual = 1.0;
            r.message = "the stiffness matrix is not positive definite (a control cell is degenerate)";
            return std::vector<double>(rhs.size(), 0.0);
        }
        const Eigen::Map<const Eigen::VectorXd> b(rhs.data(), static_cast<Eigen::Index>(rhs.size()));
        const Eigen::VectorXd x = llt_.solve(b);
        const double bn = b.norm();
        r.residual = bn > 0 ? (scalar_ * x - b).norm() / bn : 0.0;
        r.converged = std::isfinite(r.residual) && r.residual <= std::max(o_.tolerance, 1e-8);
        r.message = r.converged ? "" : "the direct solve left a relative residual of " + std::to_string(r.residual);
        return std::vector<double>(x.data(), x.data() + x.size());
    }

private:
    // The block matrix as scalar compressed columns (the identity rows included: still SPD).
    static Eigen::SparseMatrix<double> toScalar(const Block3Matrix& A) {
        std::vector<Eigen::Triplet<double>> t;
        t.reserve(A.values.size());
        for (int r = 0; r < A.rows; ++r) {
            for (int k = A.rowStart[r]; k < A.rowStart[r + 1]; ++k) {
                for (int e = 0; e < 9; ++e) {
                    const double v = A.values[9 * static_cast<std::size_t>(k) + e];
                    if (v != 0.0) t.emplace_back(3 * r + e / 3, 3 * A.cols[k] + e % 3, v);
                }
            }
        }
        Eigen::SparseMatrix<double> S(3 * A.rows, 3 * A.rows);
        S.setFromTriplets(t.begin(), t.end());
        return S;
    }

    const Block3Matrix& A_;
    ElasticityOptions o_;
    BlockIncompleteCholesky& ic_;
    CgWorkspace& work_;
    bool preconditioned_ = false;
    Eigen::SparseMatrix<double> scalar_;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt_;
    bool factored_ = false;
};

}  // namespace

namespace {

// Puts a kept increment's K_ff values and factor into the layout's A and preconditioner for its
// lifetime (swaps, no copies), and back into the kept increment after.
class SwappedIn {
public:
    SwappedIn(StiffnessLayout& L, StiffnessLayout::KeptIncrement& k) : L_(L), k_(k) { swap(); }
    ~SwappedIn() { swap(); }
    SwappedIn(const SwappedIn&) = delete;
    SwappedIn& operator=(const SwappedIn&) = delete;

private:
    void swap() {
        L_.A.values.swap(k_.values);
        L_.preconditioner.swapFactor(k_.factor);
    }
    StiffnessLayout& L_;
    StiffnessLayout::KeptIncrement& k_;
};

// `previous`: earlier solutions of similar systems (all DOFs), for the starting guess. `keep`
// (optional): the increment assembles and factors into these buffers, which keep K_ff, its
// factor and the mean cell volume after.
IncrementResult solveIncrement(const MultiBlockMesh& m, StiffnessLayout& layout, const std::vector<double>& prescribed,
                               const ElasticityOptions& o, const std::vector<std::vector<double>>& previous,
                               StiffnessLayout::KeptIncrement* keep = nullptr) {
    const int ndof = static_cast<int>(m.control.size());
    IncrementResult r;
    std::optional<SwappedIn> swapped;
    if (keep) {
        keep->values.resize(layout.A.values.size());
        keep->factored = false;
        swapped.emplace(layout, *keep);
    }
    const FreeSystem s = assembleFree(m, layout, prescribed, o);
    if (keep) keep->meanVolume = s.meanVolume;
    if (s.invalidCell) {
        r.invalidCell = true;
        r.message = s.message;
        r.u.assign(ndof, 0.0);
        return r;
    }
    std::vector<std::vector<double>>& basis = layout.guessBasis;  // its vectors kept for the next increment
    basis.resize(previous.size());
    for (std::size_t k = 0; k < previous.size(); ++k) {
        basis[k].resize(layout.size());
        for (int d = 0; d < ndof; ++d) {
            if (layout.freeIndex[d] >= 0) basis[k][layout.freeIndex[d]] = previous[k][d];
        }
    }
    const std::vector<double> x0 = galerkinGuess(layout.A, basis, layout.rhs, layout.cg);
    FreeSolver solver(layout.A, layout.preconditioner, layout.cg, o);
    if (keep) keep->factored = solver.preconditioned();
    const std::vector<double> sol = solver.solve(layout.rhs, x0, r);
    r.u.assign(ndof, 0.0);
    for (int d = 0; d < ndof; ++d) {
        r.u[d] = layout.freeIndex[d] >= 0 ? sol[layout.freeIndex[d]] : (layout.constrained[d] ? prescribed[d] : 0.0);
    }
    return r;
}

}  // namespace

MoveWorkspace::MoveWorkspace() = default;
MoveWorkspace::~MoveWorkspace() = default;
MoveWorkspace::MoveWorkspace(MoveWorkspace&&) noexcept = default;
MoveWorkspace& MoveWorkspace::operator=(MoveWorkspace&&) noexcept = default;

StiffnessLayout& MoveWorkspace::layoutFor(const MultiBlockMesh& m, const std::vector<char>& constrained) {
    CellList cells = listCells(m);
    if (!layout_ || layout_->cells.nodes != cells.nodes || layout_->constrained != constrained) {
        layout_ = std::make_unique<StiffnessLayout>(makeLayout(m, std::move(cells), constrained));
        ++builds_;
    }
    return *layout_;
}

IncrementResult solveElasticity(const MultiBlockMesh& m, const std::vector<char>& constrained,
                                const std::vector<double>& prescribed, const ElasticityOptions& o,
                                const std::vector<double>* initial) {
    StiffnessLayout layout = makeLayout(m, listCells(m), constrained);
    std::vector<std::vector<double>> previous;
    if (initial) previous.push_back(*initial);
    return solveIncrement(m, layout, prescribed, o, previous);
}

MoveReport moveControlGrid(MultiBlockMesh& m, const std::vector<double>& surface, const ElasticityOptions& o,
                           const std::function<void(int, int)>& progress, const std::atomic<bool>* cancel,
                           MoveHistory* history, MoveWorkspace* workspace) {
    const auto t0 = std::chrono::steady_clock::now();
    MoveReport rep;
    if (surface.size() != 3 * m.surfaceNode.size()) {
        throw GeometryError("mesh movement: " + std::to_string(surface.size() / 3) + " surface points for " +
                            std::to_string(m.surfaceNode.size()) + " wall control nodes");
    }
    const std::vector<char> constrained = boundaryConstraints(m);
    // A0 and the total wall displacement A^(m) - A0.
    std::vector<double> delta(m.control.size(), 0.0);
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        for (int c = 0; c < 3; ++c) delta[3 * static_cast<std::size_t>(m.surfaceNode[u]) + c] = surface[3 * u + c] - m.control[3 * static_cast<std::size_t>(m.surfaceNode[u]) + c];
    }
    rep.freeDofs = 0;
    for (char c : constrained) rep.freeDofs += c ? 0 : 1;
    if (history) *history = {};
    MoveWorkspace local;
    StiffnessLayout& layout = (workspace ? *workspace : local).layoutFor(m, constrained);
    // Each increment's K and factor kept for the mesh adjoint of this history: valid (the stamp
    // set) once every increment has been solved.
    const bool keep = history && workspace && workspace->keepsIncrements();
    if (keep) {
        layout.keptStamp = 0;
        layout.kept.resize(o.increments);
    }
    std::vector<std::vector<double>> previous;  // the earlier increments' solutions
    for (int inc = 1; inc <= o.increments; ++inc) {
        if (cancel && cancel->load()) {
            rep.status = SolveStatus::Cancelled;
            rep.message = "cancelled after " + std::to_string(inc - 1) + " of " + std::to_string(o.increments) + " increments";
            break;
        }
        // Each increment prescribes 1/m of the wall motion relative to the current grid.
        std::vector<double> prescribed(m.control.size(), 0.0);
        for (std::size_t d = 0; d < delta.size(); ++d) prescribed[d] = delta[d] / o.increments;
        const IncrementResult r = solveIncrement(m, layout, prescribed, o, previous, keep ? &layout.kept[inc - 1] : nullptr);
        if (r.invalidCell) {
            rep.status = SolveStatus::InvalidCell;
            rep.message = "increment " + std::to_string(inc) + " of " + std::to_string(o.increments) + ": " + r.message +
                          "; the wall moved further than the control grid can follow (more mesh.increments, or a smaller "
                          "deformation)";
            break;
        }
        rep.cgIterations.push_back(r.iterations);
        rep.directSolves += r.direct ? 1 : 0;
        rep.residuals.push_back(r.residual);
        rep.totalIterations += r.iterations;
        if (history) {
            history->before.push_back(m.control);
            history->displacement.push_back(r.u);
        }
        for (std::size_t d = 0; d < m.control.size(); ++d) m.control[d] += r.u[d];
        previous.push_back(r.u);
        if (progress) progress(inc, o.increments);
        if (!r.converged) {
            rep.status = SolveStatus::NotConverged;
            rep.message = "increment " + std::to_string(inc) + ": " + r.message;
            break;
        }
    }
    // Wall nodes end exactly on the geometry's control points.
    if (rep.status == SolveStatus::Converged) {
        for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
            for (int c = 0; c < 3; ++c) m.control[3 * static_cast<std::size_t>(m.surfaceNode[u]) + c] = surface[3 * u + c];
        }
        if (keep) {
            static std::atomic<std::uint64_t> moves{0};
            history->stamp = layout.keptStamp = ++moves;
            layout.keptOptions = o;
        }
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
}

std::size_t MoveWorkspace::keptBytes() const {
    std::size_t n = 0;
    if (layout_) {
        for (const auto& k : layout_->kept) n += k.values.capacity() * sizeof(double) + k.factor.bytes();
    }
    return n;
}

std::size_t MoveHistory::bytes() const {
    std::size_t n = 0;
    for (const auto& v : before) n += v.size() * sizeof(double);
    for (const auto& v : displacement) n += v.size() * sizeof(double);
    return n;
}

namespace {

// Calls fn(x, nodes, cell) for every control cell of every block (cell: a global cell number,
// blocks one after the other), in parallel over the cells (fn must only write per-cell data:
// see CellContributions). One parallel region for all blocks.
template <class Fn>
void forEachCellParallel(const MultiBlockMesh& m, Fn&& fn) {
    std::vector<long> first(m.blocks.size() + 1, 0);
    for (std::size_t b = 0; b < m.blocks.size(); ++b) {
        const ControlBlock& cb = m.blocks[b];
        first[b + 1] = first[b] + static_cast<long>(cb.count[0] - 1) * (cb.count[1] - 1) * (cb.count[2] - 1);
    }
    const long total = first.back();
#pragma omp parallel for schedule(dynamic, 64)
    for (long cell = 0; cell < total; ++cell) {
        const std::size_t b = static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), cell) - first.begin() - 1);
        const ControlBlock& cb = m.blocks[b];
        const long c = cell - first[b];
        const int ni = cb.count[0] - 1, nj = cb.count[1] - 1;
        double x[24];
        int nodes[8];
        cellCorners(m, cb, static_cast<int>(c % ni), static_cast<int>((c / ni) % nj),
                    static_cast<int>(c / (static_cast<long>(ni) * nj)), x, nodes);
        fn(x, nodes, cell);
    }
}

long cellCount(const MultiBlockMesh& m) {
    long n = 0;
    for (const ControlBlock& b : m.blocks) n += static_cast<long>(b.count[0] - 1) * (b.count[1] - 1) * (b.count[2] - 1);
    return n;
}

double meanCellVolume(const MultiBlockMesh& m) {
    double total = 0;
    for (const ControlBlock& b : m.blocks) {
        forEachCell(m, b, [&](const double* x, const int*) { total += cellVolume(x); });
    }
    return total / std::max(1L, cellCount(m));
}

// Per-cell contributions (24 per cell: 3 per corner) computed in parallel, then added to the
// node values in cell order by one thread: the same sums in the same order on any number of
// threads, so a gradient is reproducible bit for bit (atomic adds are not: an optimization resumed
// from its history must follow the same path).
struct CellContributions {
    std::vector<int> nodes;     // 8 per cell
    std::vector<double> value;  // 24 per cell
    explicit CellContributions(long cells) : nodes(8 * static_cast<std::size_t>(cells)), value(24 * static_cast<std::size_t>(cells), 0.0) {}
    void setNodes(long cell, const int* n) { std::copy(n, n + 8, nodes.begin() + 8 * cell); }
    double* of(long cell) { return value.data() + 24 * cell; }
    void addTo(std::vector<double>& g) const {
        const std::size_t cells = nodes.size() / 8;
        for (std::size_t c = 0; c < cells; ++c) {
            for (int r = 0; r < 24; ++r) g[3 * static_cast<std::size_t>(nodes[8 * c + r / 3]) + r % 3] += value[24 * c + r];
        }
    }
};

}  // namespace

std::vector<double> stiffnessProduct(const MultiBlockMesh& m, const ElasticityOptions& o, const std::vector<double>& v) {
    const double mean = meanCellVolume(m);
    std::vector<double> out(m.control.size(), 0.0);
    CellContributions parts(cellCount(m));
    forEachCellParallel(m, [&](const double* x, const int* nodes, long cell) {
        double K[24 * 24];
        hexStiffness<double>(x, cellModulus(x, mean, o), o.poisson, K);
        parts.setNodes(cell, nodes);
        double* part = parts.of(cell);
        for (int r = 0; r < 24; ++r) {
            double s = 0;
            for (int c = 0; c < 24; ++c) s += K[24 * r + c] * v[3 * static_cast<std::size_t>(nodes[c / 3]) + c % 3];
            part[r] = s;
        }
    });
    parts.addTo(out);
    return out;
}

std::vector<double> stiffnessProductGradient(const MultiBlockMesh& m, const ElasticityOptions& o,
                                             const std::vector<double>& lambda, const std::vector<double>& u) {
    return stiffnessProductGradients(m, o, {lambda}, u).front();
}

namespace {

// The mesh adjoint's per-increment work arrays, kept from one increment to the next (fresh ones
// would cost page faults on every increment on this project's VMs: ~3 ms per MB).
struct AdjointScratch {
    std::vector<double> dVolume;                   // 24 per cell
    std::vector<double> dMeanOfCell;               // per cell, one per functional
    std::vector<std::vector<double>> contribution;  // per functional, 24 per cell
    std::vector<double> wallContribution;          // 24 per cell with a wall corner
};

// stiffnessProductGradients for the cells of `cells` (listCells order) whose mean volume is
// `mean`, into g (one vector per lambda, overwritten).
void stiffnessProductGradientsInto(const MultiBlockMesh& m, const CellList& cellList, double mean,
                                   const ElasticityOptions& o, const std::vector<std::vector<double>>& lambdas,
                                   const std::vector<double>& u, AdjointScratch& w,
                                   std::vector<std::vector<double>>& g) {
    // K_e = E(x, mean) K1_e(x) with K1 the stiffness of unit modulus, so for s = lambda^T K u
    //   ds/dx = E ds1/dx + s1 dE/dx,   ds/dmean = s1 dE/dmean = s1 E size_stiffening / mean,
    // and d mean/dx = (1/N) d vol/dx. dE/dx, d vol/dx and the Gauss points' gradients are shared
    // by all lambdas.
    const long cells = cellList.count();
    const std::size_t nl = lambdas.size();
    const int* cellNodes = cellList.nodes.data();
    w.dVolume.resize(24 * static_cast<std::size_t>(cells));
    w.dMeanOfCell.resize(nl * static_cast<std::size_t>(cells));
    w.contribution.resize(nl);
    for (std::vector<double>& c : w.contribution) c.resize(24 * static_cast<std::size_t>(cells));
#pragma omp parallel for schedule(dynamic, 64)
    for (long cell = 0; cell < cells; ++cell) {
        const int* nodes = cellNodes + 8 * cell;
        double x[24], ue[24];
        for (int r = 0; r < 24; ++r) {
            const std::size_t dof = 3 * static_cast<std::size_t>(nodes[r / 3]) + r % 3;
            x[r] = m.control[dof];
            ue[r] = u[dof];
        }
        const CellGauss gauss(x);
        double dE[24];
        double* dv = &w.dVolume[24 * static_cast<std::size_t>(cell)];
        double vol0 = 0;
        const double E = modulusGradient(x, gauss, mean, o, dE, dv, &vol0);
        for (std::size_t p = 0; p < nl; ++p) {
            double le[24];
            bool active = false;
            for (int r = 0; r < 24; ++r) {
                le[r] = lambdas[p][3 * static_cast<std::size_t>(nodes[r / 3]) + r % 3];
                active = active || le[r] != 0;
            }
            double* part = &w.contribution[p][24 * static_cast<std::size_t>(cell)];
            double s1 = 0;
            if (active) {
                double ds1[24];
                s1 = bilinearGradient(gauss, o.poisson, le, ue, ds1);
                for (int i = 0; i < 24; ++i) part[i] = E * ds1[i] + s1 * dE[i];
            } else {
                for (int i = 0; i < 24; ++i) part[i] = 0;
            }
            w.dMeanOfCell[nl * cell + p] = (vol0 > 0 && o.sizeStiffening != 0) ? s1 * E * o.sizeStiffening / mean : 0.0;
        }
    }
    // The cells' contributions added in cell order (the same bits on any number of threads).
    g.resize(nl);
    for (std::size_t p = 0; p < nl; ++p) {
        g[p].assign(m.control.size(), 0.0);
        const double* part = w.contribution[p].data();
        for (long cell = 0; cell < cells; ++cell) {
            for (int r = 0; r < 24; ++r) {
                g[p][3 * static_cast<std::size_t>(cellNodes[8 * cell + r / 3]) + r % 3] += part[24 * cell + r];
            }
        }
        double dMean = 0;
        for (long cell = 0; cell < cells; ++cell) dMean += w.dMeanOfCell[nl * cell + p];
        if (dMean == 0) continue;
        const double weight = dMean / static_cast<double>(std::max(1L, cells));
        for (long cell = 0; cell < cells; ++cell) {
            for (int i = 0; i < 24; ++i) {
                g[p][3 * static_cast<std::size_t>(cellNodes[8 * cell + i / 3]) + i % 3] +=
                    weight * w.dVolume[24 * static_cast<std::size_t>(cell) + i];
            }
        }
    }
}

// (K lambda) at the DOFs of the wall nodes (flagged in wallNode), into out (its other entries are
// left alone), from the cells with a wall corner (wallCells, in cell order: each entry is summed
// as over all cells); mean: the cells' mean volume. work: 24 values per wall cell.
void wallStiffnessProduct(const MultiBlockMesh& grid, const CellList& cells, const std::vector<long>& wallCells,
                          const std::vector<char>& wallNode, double mean, const ElasticityOptions& o,
                          const std::vector<double>& lambda, std::vector<double>& work, std::vector<double>& out) {
    const long count = static_cast<long>(wallCells.size());
    work.resize(24 * wallCells.size());
#pragma omp parallel for schedule(static)
    for (long t = 0; t < count; ++t) {
        const int* nodes = &cells.nodes[8 * wallCells[t]];
        double x[24], le[24];
        for (int r = 0; r < 24; ++r) {
            const std::size_t dof = 3 * static_cast<std::size_t>(nodes[r / 3]) + r % 3;
            x[r] = grid.control[dof];
            le[r] = lambda[dof];
        }
        double K[24 * 24];
        hexStiffness<double>(x, cellModulus(x, mean, o), o.poisson, K);
        for (int r = 0; r < 24; ++r) {
            double sum = 0;
            for (int c = 0; c < 24; ++c) sum += K[24 * r + c] * le[c];
            work[24 * t + r] = sum;
        }
    }
    for (std::size_t n = 0; n < wallNode.size(); ++n) {
        if (!wallNode[n]) continue;
        for (int c = 0; c < 3; ++c) out[3 * n + c] = 0;
    }
    for (long t = 0; t < count; ++t) {
        const int* nodes = &cells.nodes[8 * wallCells[t]];
        for (int r = 0; r < 24; ++r) {
            if (wallNode[nodes[r / 3]]) out[3 * static_cast<std::size_t>(nodes[r / 3]) + r % 3] += work[24 * t + r];
        }
    }
}

}  // namespace

std::vector<std::vector<double>> stiffnessProductGradients(const MultiBlockMesh& m, const ElasticityOptions& o,
                                                           const std::vector<std::vector<double>>& lambdas,
                                                           const std::vector<double>& u) {
    AdjointScratch w;
    std::vector<std::vector<double>> g;
    stiffnessProductGradientsInto(m, listCells(m), meanCellVolume(m), o, lambdas, u, w, g);
    return g;
}

std::vector<double> moveControlGridAdjoint(const MultiBlockMesh& m, const MoveHistory& history,
                                           const ElasticityOptions& o, const std::vector<double>& gFinal,
                                           MeshAdjointReport* report) {
    return moveControlGridAdjoints(m, history, o, {gFinal}, report).front();
}

std::vector<std::vector<double>> moveControlGridAdjoints(const MultiBlockMesh& m, const MoveHistory& history,
                                                         const ElasticityOptions& o,
                                                         const std::vector<std::vector<double>>& gFinals,
                                                         MeshAdjointReport* report, MoveWorkspace* workspace) {
    const auto t0 = std::chrono::steady_clock::now();
    MeshAdjointReport rep;
    const std::size_t ndof = m.control.size();
    for (const auto& gf : gFinals) {
        if (gf.size() != ndof) {
            throw GeometryError("mesh adjoint: " + std::to_string(gf.size() / 3) + " gradient values for " +
                                std::to_string(ndof / 3) + " control nodes");
        }
    }
    const std::size_t nr = gFinals.size();
    const int increments = static_cast<int>(history.before.size());
    std::vector<std::vector<double>> gA(nr, std::vector<double>(3 * m.surfaceNode.size(), 0.0));
    std::vector<std::vector<double>> gb = gFinals;
    // The move ends by setting the wall nodes to A exactly: their final gradient goes to A.
    for (std::size_t p = 0; p < nr; ++p) {
        for (std::size_t s = 0; s < m.surfaceNode.size(); ++s) {
            for (int c = 0; c < 3; ++c) {
                const std::size_t d = 3 * static_cast<std::size_t>(m.surfaceNode[s]) + c;
                gA[p][3 * s + c] += gb[p][d];
                gb[p][d] = 0;
            }
        }
    }
    const std::vector<char> constrained = boundaryConstraints(m);
    MoveWorkspace local;
    StiffnessLayout& layout = (workspace ? *workspace : local).layoutFor(m, constrained);
    MultiBlockMesh grid = m;  // structure; the control points of each increment from the history
    const std::vector<double> zero(ndof, 0.0);
    // K lambda is needed at the wall's DOFs only: from the cells with a wall corner (in cell
    // order, so each wall entry is summed as over all cells).
    const CellList& cells = layout.cells;
    std::vector<char> wallNode(ndof / 3, 0);
    for (int n : m.surfaceNode) wallNode[n] = 1;
    std::vector<long> wallCells;
    for (long c = 0; c < cells.count(); ++c) {
        bool wall = false;
        for (int a = 0; a < 8; ++a) wall = wall || wallNode[cells.nodes[8 * c + a]];
        if (wall) wallCells.push_back(c);
    }
    // The forward move's K and factors, when this workspace kept them for this history with the
    // same options (the same matrices to the bit: assembling them again gives the same values).
    auto sameOptions = [&](const ElasticityOptions& k) {
        return k.poisson == o.poisson && k.sizeStiffening == o.sizeStiffening &&
               k.orthogonalityStiffening == o.orthogonalityStiffening && k.solver == o.solver;
    };
    const bool reuse = history.stamp != 0 && layout.keptStamp == history.stamp &&
                       static_cast<int>(layout.kept.size()) == increments && sameOptions(layout.keptOptions);
    if (reuse) rep.keptBytes = (workspace ? *workspace : local).keptBytes();
    AdjointScratch scratch;
    std::vector<double> Kl(ndof, 0.0);
    std::vector<std::vector<double>> gK;
    std::vector<std::vector<std::vector<double>>> earlier(nr);  // per functional: its solutions so far
    for (int inc = increments; inc >= 1 && rep.converged; --inc) {
        grid.control = history.before[inc - 1];
        const std::vector<double>& u = history.displacement[inc - 1];
        // b^(i) = b^(i-1) + u^(i): ubar = gb. u_f solves K_ff u_f = -K_fc u_c, so
        // K_ff lambda = ubar_f, the prescribed values get ubar_c - (K lambda)_c, and b^(i-1) gets
        // -d(lambda^T K u)/db. One K and one factorization for all right-hand sides.
        std::optional<SwappedIn> swapped;
        std::optional<bool> keptFactor;
        double meanVolume = 0;
        if (reuse) {
            StiffnessLayout::KeptIncrement& k = layout.kept[inc - 1];
            swapped.emplace(layout, k);
            keptFactor = k.factored;
            meanVolume = k.meanVolume;
            ++rep.reusedIncrements;
        } else {
            const FreeSystem s = assembleFree(grid, layout, zero, o);
            if (s.invalidCell) {
                rep.converged = false;
                rep.message = "increment " + std::to_string(inc) + ": " + s.message;
                break;
            }
            meanVolume = s.meanVolume;
        }
        FreeSolver solver(layout.A, layout.preconditioner, layout.cg, o, keptFactor);
        std::vector<std::vector<double>> lambdas(nr, std::vector<double>(ndof, 0.0));
        for (std::size_t p = 0; p < nr && rep.converged; ++p) {
            std::vector<double> rhs(layout.size(), 0.0);
            for (std::size_t d = 0; d < ndof; ++d) {
                if (layout.freeIndex[d] >= 0) rhs[layout.freeIndex[d]] = gb[p][d];
            }
            IncrementResult r;
            // Start from the best combination of this functional's later-increment solutions (the
            // increments' systems and right-hand sides are alike).
            const std::vector<double> sol = solver.solve(rhs, galerkinGuess(layout.A, earlier[p], rhs, layout.cg), r);
            earlier[p].push_back(sol);
            rep.iterations.push_back(r.iterations);
            rep.directSolves += r.direct ? 1 : 0;
            if (!r.converged) {
                rep.converged = false;
                rep.message = "increment " + std::to_string(inc) + ": " + r.message;
                break;
            }
            for (std::size_t d = 0; d < ndof; ++d) {
                if (layout.freeIndex[d] >= 0) lambdas[p][d] = sol[layout.freeIndex[d]];
            }
            wallStiffnessProduct(grid, cells, wallCells, wallNode, meanVolume, o, lambdas[p], scratch.wallContribution, Kl);
            for (std::size_t sn = 0; sn < m.surfaceNode.size(); ++sn) {
                for (int c = 0; c < 3; ++c) {
                    const std::size_t d = 3 * static_cast<std::size_t>(m.surfaceNode[sn]) + c;
                    gA[p][3 * sn + c] += (gb[p][d] - Kl[d]) / increments;  // the wall's prescribed u is (A - A0)/m
                }
            }
        }
        if (!rep.converged) break;
        stiffnessProductGradientsInto(grid, cells, meanVolume, o, lambdas, u, scratch, gK);
        for (std::size_t p = 0; p < nr; ++p) {
            for (std::size_t d = 0; d < ndof; ++d) gb[p][d] -= gK[p][d];
        }
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (report) *report = rep;
    return gA;
}

}  // namespace aero::mesh
