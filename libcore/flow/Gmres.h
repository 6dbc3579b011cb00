#pragma once
// Restarted GMRES with right preconditioning (Saad & Schultz): solves A M^-1 u = b, x = M^-1 u,
// so the monitored residual is the true ||b - A x||. Operators are callables out = Op(in) on
// vectors of length n.
//
// Orthogonalization is classical Gram-Schmidt with a second pass when the first cancelled most of
// the vector (the DGKS test; as stable as modified Gram-Schmidt, but each pass is two sweeps over
// the basis in fixed row chunks, so an iteration costs two to four parallel regions instead of
// two per basis vector, and the sums do not depend on the thread count); how much cancellation
// calls for the second pass is GmresOptions::reorthogonalizeBelow. Optionally the restarts are
// deflated (GMRES-DR, Morgan 2002): each cycle keeps the harmonic Ritz vectors of the `deflation`
// smallest harmonic Ritz values, so the slow eigencomponents found in one cycle are not lost at
// the restart (a restarted GMRES(60) on the flow's adjoint systems needs about twice the
// iterations of an unrestarted one; docs/performance.md).
#include <functional>
#include <memory>
#include <vector>

namespace aero::flow {

using LinearMap = std::function<void(const double* in, double* out)>;

struct GmresOptions {
    int restart = 40;          // Krylov vectors per cycle
    int maxIterations = 200;   // matrix-vector products in all
    double tolerance = 1e-2;   // on ||b - A x|| / ||b||
    double hopeless = 0;       // > 0: give up after a restart cycle when the residual's fall so
                               // far, extrapolated at the same rate per iteration to
                               // maxIterations, would not bring it below this (a caller that
                               // rejects such results saves the remaining cycles)
    int deflation = 0;         // > 0: harmonic Ritz vectors kept over a restart (GMRES-DR(m, k));
                               // must be below restart - 1 to leave room for new vectors
    bool singleBasis = false;  // the Krylov basis stored in float: half the basis memory and half
                               // the orthogonalization's memory traffic; the products, the
                               // Gram-Schmidt sums, x and the residual at each restart stay
                               // double, so a restart recovers full accuracy (docs/performance.md)
    // The Gram-Schmidt pass is repeated where it left the new vector shorter than this fraction
    // of its length (the DGKS test; 1/sqrt 2: "twice is enough"). The flow's Newton steps use
    // 0.1, a second pass only where the first cancelled 90 % of the vector: at their loose
    // tolerances the same iterations on the 75k and 98k samples with 0.6 times the sweeps over
    // the basis, where a single pass always (PETSc's default) let a restarted solve's true
    // residual drift from its estimate (docs/performance.md).
    double reorthogonalizeBelow = 0.7071067811865476;
};

struct GmresReport {
    int iterations = 0;
    double relativeResidual = 1.0;  // ||b - A x|| / ||b|| (the Arnoldi estimate)
    bool converged = false;
    bool gaveUp = false;            // stopped early: `hopeless` could not be reached
};

/// The Krylov basis and work vectors, kept between solves of the same size (a Newton iteration's
/// GMRES on 98k nodes would otherwise allocate and clear 60 vectors of 491k values every time).
/// Each precision's vectors are one allocation, so that release() gives the memory back to the
/// system: freed one by one, the 18 MB float vectors of the 903k paper grid stayed in the heap
/// (glibc raises its mmap threshold to the size of a freed block), and the next allocation of the
/// approximate Jacobian came on top of them. The vectors are allocated without being written
/// (not zero-filled): a large allocation is mapped pages that become resident only when a solve
/// writes them, so a solve that converges in 15 iterations of a GMRES(60) holds 17 vectors, not 62.
class GmresWorkspace {
public:
    /// At least `vectors` double and `singleVectors` float vectors of length n. Growing the count
    /// or changing n allocates again: the vectors' contents are not kept.
    void reserve(long n, int vectors, int singleVectors = 0);
    double* vector(int i) { return basis_.get() + stride_ * static_cast<std::size_t>(i); }
    float* singleVector(int i) { return singleData_ + stride_ * static_cast<std::size_t>(i); }
    long size() const { return n_; }
    int vectors() const { return vectors_; }
    int singleVectors() const { return singleVectors_; }
    /// Frees every vector (the next reserve() allocates them again) and forgets lent storage.
    void release();
    /// Storage of `bytes` that the float vectors use, instead of an allocation of their own,
    /// whenever it is large enough, until release(); the caller keeps it alive and does not use it
    /// meanwhile. The low-memory flow steps lend the approximate Jacobian's values, which an exact
    /// step does not need while GMRES runs (StepSystem): the matrix and the basis then take turns
    /// in one block whatever the heap does (freed and allocated again, they took turns only while
    /// malloc put each in the other's hole, and a small allocation in the hole added 100 MB to
    /// the 75k half-sphere's peak).
    void lend(void* storage, std::size_t bytes);
    bool usesLent() const { return singleData_ != nullptr && singleData_ == lent_; }
    /// The bytes reserve(n, any, singleVectors) needs for the float vectors.
    static std::size_t singleBytes(long n, int singleVectors);

private:
    long n_ = 0;
    std::size_t stride_ = 0;  // n rounded up to 16 values: each vector starts 64-byte aligned
    int vectors_ = 0, singleVectors_ = 0;
    std::unique_ptr<double[]> basis_;  // vectors_ * stride_ values, uninitialized
    std::unique_ptr<float[]> single_;  // singleVectors_ * stride_ values, uninitialized
    float* singleData_ = nullptr;      // single_'s values or the lent storage's
    void* lent_ = nullptr;
    std::size_t lentBytes_ = 0;

    void freeVectors();  // release() but for the lent storage
};

/// Solves A x = b; x holds the initial guess on entry. M (optional) applies the preconditioner
/// inverse. Never throws for non-convergence: see the report. `workspace` (optional) is reused
/// between calls.
GmresReport gmres(long n, const LinearMap& A, const LinearMap& M, const double* b, double* x,
                  const GmresOptions& o, GmresWorkspace* workspace = nullptr);

}  // namespace aero::flow
