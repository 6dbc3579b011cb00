#include "flow/Metrics.h"

#include <complex>

#include "flow/BlockView.h"
#include "flow/Sbp.h"

namespace aero::flow {

namespace {

// out[n] = D_d(in)[n] for a scalar field of one block.
template <class T>
void differentiate(const BlockView<const T>& in, int d, const BlockView<T>& out) {
    const long s = in.stride(d);
    const int n = in.dims[d];
    for (int k = 0; k < in.dims[2]; ++k) {
        for (int j = 0; j < in.dims[1]; ++j) {
            for (int i = 0; i < in.dims[0]; ++i) {
                const int idx[3] = {i, j, k};
                out.at(i, j, k)[0] = sbpDiff(in.at(i, j, k), s, idx[d], n);
            }
        }
    }
}

template <class T>
void blockMetrics(const FlowBlock& blk, const T* xyz, T* metrics) {
    const long N = blk.nodeCount();
    const std::array<int, 3> dims = blk.dims;
    // Coordinates split by component, and their derivatives dx[d][c] = D_d x_c.
    std::vector<T> x(3 * N), dx(9 * N), p(N), q(N), dp(N), dq(N);
    for (long n = 0; n < N; ++n) {
        for (int c = 0; c < 3; ++c) x[c * N + n] = xyz[3 * n + c];
    }
    auto view = [&](std::vector<T>& v, long first) { return BlockView<T>{v.data() + first, dims, 1}; };
    auto cview = [&](std::vector<T>& v, long first) {
        return BlockView<const T>{v.data() + first, dims, 1};
    };
    for (int d = 0; d < 3; ++d) {
        for (int c = 0; c < 3; ++c) differentiate(cview(x, c * N), d, view(dx, (3 * d + c) * N));
    }
    for (int d = 0; d < 3; ++d) {
        const int a = (d + 1) % 3, b = (d + 2) % 3;
        for (int c = 0; c < 3; ++c) {
            const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            const T* xc2 = &x[c2 * N];
            const T* da = &dx[(3 * a + c1) * N];
            const T* db = &dx[(3 * b + c1) * N];
            for (long n = 0; n < N; ++n) {
                p[n] = xc2[n] * da[n];  // x_c2 D_a x_c1
                q[n] = xc2[n] * db[n];  // x_c2 D_b x_c1
            }
            differentiate(cview(p, 0), b, view(dp, 0));
            differentiate(cview(q, 0), a, view(dq, 0));
            for (long n = 0; n < N; ++n) metrics[kMetricWidth * n + 3 * d + c] = dp[n] - dq[n];
        }
    }
    for (long n = 0; n < N; ++n) {
        T s = 0.0;
        for (int d = 0; d < 3; ++d) {
            for (int c = 0; c < 3; ++c) s += dx[(3 * d + c) * N + n] * metrics[kMetricWidth * n + 3 * d + c];
        }
        metrics[kMetricWidth * n + 9] = s / 3.0;
    }
}

}  // namespace

template <class T>
void computeMetrics(const FlowMesh& fm, const T* xyz, T* metrics) {
    // Blocks in parallel, each on one thread: one parallel region per call instead of ~30 per
    // block (with passive OpenMP waiting every region costs a wake-up of the team; the grid
    // sensitivities evaluate the metrics 81 times).
    const long nb = static_cast<long>(fm.blocks.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (long b = 0; b < nb; ++b) {
        const FlowBlock& blk = fm.blocks[b];
        blockMetrics(blk, xyz + 3 * blk.offset, metrics + kMetricWidth * blk.offset);
    }
}

std::vector<double> computeMetrics(const FlowMesh& fm, const std::vector<double>& xyz) {
    std::vector<double> m(kMetricWidth * static_cast<std::size_t>(fm.nodeCount));
    computeMetrics(fm, xyz.data(), m.data());
    return m;
}

VolumeCheck checkVolumes(const FlowMesh& fm, const std::vector<double>& metrics) {
    VolumeCheck c;
    bool first = true;
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const FlowBlock& blk = fm.blocks[b];
        for (long n = 0; n < blk.nodeCount(); ++n) {
            const double v = metrics[kMetricWidth * (blk.offset + n) + 9];
            if (first || v < c.minJinv) {
                c = {v, static_cast<int>(b), n};
                first = false;
            }
        }
    }
    return c;
}

template void computeMetrics<double>(const FlowMesh&, const double*, double*);
template void computeMetrics<std::complex<double>>(const FlowMesh&, const std::complex<double>*,
                                                   std::complex<double>*);
template void computeMetrics<Dual<3>>(const FlowMesh&, const Dual<3>*, Dual<3>*);

}  // namespace aero::flow
