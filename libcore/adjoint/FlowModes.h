#pragma once
// Linear modes of the pseudo-time flow dynamics at a state: why a flow solve stalls.
//
// The solver marches D dq/dtau = -R(q) (D = V/dtau at CFL 1, flow::timeStepScale) towards a
// steady state; near a state q it follows dq'/dtau = mu q' for the eigenpairs of
//   -D^-1 J v = mu v,   J = dR/dq (exact).
// A mode with Re(mu) > 0 grows in pseudo-time: there the flow has no stable steady state on this
// grid at this dissipation (a separated or unsteady region, e.g. behind a blunt trailing edge),
// and for a real mu the solver's own matrix D / CFL + J is singular at CFL = 1 / mu, where its
// linear solves fail. A stall with no such mode is the solver's failure, not the flow's.
//
// The modes that grow fastest relative to the others are the dominant eigenvalues of one implicit
// pseudo-time step at a moderate CFL c,
//   M_c = (D / c + J)^-1 D / c,   M_c v = v / (1 - c mu),
// (|1 / (1 - c mu)| > 1 exactly when the mode grows at that step), found by Arnoldi with each
// product one GMRES solve preconditioned as the flow solver does. No factorization of J: the cost
// is about as many GMRES iterations as a few dozen Newton steps.
#include <atomic>
#include <complex>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "flow/FlowMesh.h"
#include "flow/Gmres.h"
#include "flow/Residual.h"

namespace aero::adjoint {

/// Ritz pairs of a linear operator from `steps` Arnoldi steps (full re-orthogonalization) started
/// at `start`: values by decreasing modulus; vector(k) of unit 2-norm; residual |h_{m+1,m} y_m|,
/// the 2-norm of op(v) - value v. Stops early (fewer pairs) at an invariant subspace or when `op`
/// returns false (e.g. a failed inner solve).
struct RitzPairs {
    std::vector<std::complex<double>> values;
    std::vector<double> residuals;
    int steps = 0;
    std::vector<std::vector<double>> basis;                     // the Arnoldi vectors (steps)
    std::vector<std::vector<std::complex<double>>> coefficients; // per pair, in the basis
    std::vector<std::complex<double>> vector(std::size_t k) const;
};
using CheckedMap = std::function<bool(const double* in, double* out)>;
RitzPairs arnoldi(long n, const CheckedMap& op, const std::vector<double>& start, int steps);

struct ModeOptions {
    double cfl = 50;          // the implicit step whose amplification is analysed (the flow solver's
                              // GMRES converges there; larger c separates the growing modes less)
    int steps = 30;           // Arnoldi steps (GMRES solves)
    double tolerance = 1e-6;  // GMRES relative residual per solve
    int maxIterations = 600;  // GMRES products per solve
    int gmresRestart = 60;
    int gmresDeflation = 20;
    const std::atomic<bool>* cancel = nullptr;  // set: stop between Arnoldi steps (ModeReport::failure
                                                // "cancelled"), within one GMRES solve of the stop
};

struct FlowMode {
    std::complex<double> rate;  // mu, per unit of CFL-1 pseudo time (Re > 0: grows)
    double residual = 0;        // ||M_c v - nu v|| / |nu| of the Ritz pair (v of unit norm)
    double defect = 0;          // ||J v + mu D v|| / (||J v|| + ||mu D v||): the vector as an
                                // eigenvector of the linearization. The Ritz values converge much
                                // faster than the vectors where the spectrum clusters (near nu = 1):
                                // a value right to 4 digits (against a direct factorization) may
                                // have a vector with a defect of 0.1, still in the right place
    long node = -1;             // global node where |v| is largest
    double share = 0;           // that node's share of |v|^2
    double regionShare = 0;     // share of |v|^2 within the 20 largest nodes
    std::vector<std::complex<double>> vector;  // v (5 per node, unit 2-norm)
    bool grows() const { return rate.real() > 0; }
};

struct ModeReport {
    std::vector<FlowMode> modes;  // the converged Ritz pairs, by decreasing Re(mu)
    int steps = 0;                // Arnoldi steps done
    int linearIterations = 0;
    double seconds = 0;
    std::string failure;          // non-empty: a GMRES solve failed (the modes are then partial)
    /// The fastest-growing converged mode, or null.
    const FlowMode* growing() const { return !modes.empty() && modes.front().grows() ? &modes.front() : nullptr; }
    /// Whether the analysis has a verdict: a growing mode, or converged modes without a failed
    /// solve (none grows). A failed GMRES solve or no converged Ritz pair says nothing.
    bool conclusive() const { return growing() != nullptr || (failure.empty() && !modes.empty()); }
    /// Its rate, 0 when none grows, NaN without a verdict (the sweep's and the optimizer
    /// history's growing_mode_rate, empty then).
    double growthRate() const {
        if (growing()) return growing()->rate.real();
        return conclusive() ? 0.0 : std::numeric_limits<double>::quiet_NaN();
    }
};

/// Where a mode vector (5 values per node) lives: its `count` largest nodes by |v|^2, largest
/// first, each one's share of |v|^2, and their shares' sum.
struct ModeLocation {
    std::vector<long> nodes;
    std::vector<double> shares;
    double regionShare = 0;
};
ModeLocation locateMode(const std::vector<std::complex<double>>& v, long nodeCount, int count = 20);

/// The dominant modes of the implicit pseudo-time step at `q` (see the header comment). A Ritz
/// pair counts as converged (is reported) when its FlowMode::residual is below `converged`.
ModeReport pseudoTimeModes(const flow::FlowMesh& fm, const std::vector<double>& metrics, const std::vector<double>& q,
                           const flow::ResidualOptions& o, const ModeOptions& opt = {}, double converged = 1e-3);

}  // namespace aero::adjoint
