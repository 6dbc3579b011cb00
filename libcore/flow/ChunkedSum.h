#pragma once
// A dot product over a long vector taken in fixed chunks of rows, the chunk sums added in chunk
// order by one thread: the same bits on any number of threads (GMRES's sums are taken so too).

namespace aero::flow {

/// sum_i a_i b_i over i < n (defined in Gmres.cpp, next to GMRES's chunked sums).
double chunkedDot(long n, const double* a, const double* b);

}  // namespace aero::flow
