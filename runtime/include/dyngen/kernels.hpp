// dyngen kernels: the loops of the algorithms whose work grows faster than the number of bodies
// (the pairs of joints in the derivatives of inverse dynamics, the product M^-1 d tau of the
// derivatives of forward dynamics, the columns of the derivatives of contact dynamics). The
// runtime calls them (dyngen::run_kernel), and generated code calls this same file, copied into
// each package as dyngen_kernels.hpp, so both compute the same bits; the generator records a
// call instead of unrolling the loops, which keeps a big robot's code small. In a package the
// namespace is the package's own, NAME::dyngen_kernels: packages of other dyngen versions and the
// runtime then never share a definition in one program. Self-contained C++17: no allocation, and
// no include but sincos.h (dyngen_sincos.h in a package) for DYNGEN_DISPATCH.
#pragma once

#include "sincos.h"

// Generated code calls the kernels with constant tables: a compiler that specialised a kernel
// for them would unroll its loops back into the code they replace (GCC -O3 then takes minutes
// and gigabytes on a 36-DoF robot), so each kernel stays one function. Under GCC a kernel has a
// clone per instruction set (DYNGEN_DISPATCH), called through the loader's choice, which no
// compiler inlines or specialises (and GCC refuses noclone on it); clang 14 makes no clones of a
// template, so its kernels run the baseline.
#if DYNGEN_DISPATCHES && !defined(__clang__)
#define DYNGEN_KERNEL DYNGEN_DISPATCH
#elif defined(__clang__)
#define DYNGEN_KERNEL __attribute__((noinline))
#elif defined(__GNUC__)
#define DYNGEN_KERNEL __attribute__((noinline, noclone))
#else
#define DYNGEN_KERNEL
#endif

namespace dyngen {
namespace kernels {

/// f . m for 6-vectors whose angular and linear parts are interleaved (x, x, y, y, z, z), in
/// the order of spatial.hpp's inner: the angular part and the linear part, each summed left to
/// right, then added.
template <class S>
inline S inner6(const S* f, const S* m) {
  return (f[0] * m[0] + f[2] * m[2] + f[4] * m[4]) + (f[1] * m[1] + f[3] * m[3] + f[5] * m[5]);
}

#if defined(__GNUC__)
/// inner6 for double with GCC's (and clang's) vector types: the angular sum in one lane, the
/// linear sum in the other, in the scalar order, then added.
inline double inner6(const double* f, const double* m) {
  typedef double pair __attribute__((vector_size(2 * sizeof(double))));
  pair sum, a, b;
  __builtin_memcpy(&a, f, sizeof a);
  __builtin_memcpy(&b, m, sizeof b);
  sum = a * b;
  for (int k = 2; k < 6; k += 2) {
    __builtin_memcpy(&a, f + k, sizeof a);
    __builtin_memcpy(&b, m + k, sizeof b);
    sum = sum + a * b;
  }
  return sum[0] + sum[1];
}
#endif

/// f = X^T f, a force in child coordinates expressed in parent coordinates, as spatial.hpp's
/// apply_force_T: [E^T n + r x E^T f; E^T f], with X as E (row-major) then r, and f
/// interleaved as inner6 takes it.
template <class S>
inline void force_to_parent(const S* X, S* f) {
  const S* E = X;
  const S* r = X + 9;
  const S l0 = E[0] * f[1] + E[3] * f[3] + E[6] * f[5];
  const S l1 = E[1] * f[1] + E[4] * f[3] + E[7] * f[5];
  const S l2 = E[2] * f[1] + E[5] * f[3] + E[8] * f[5];
  const S n0 = E[0] * f[0] + E[3] * f[2] + E[6] * f[4];
  const S n1 = E[1] * f[0] + E[4] * f[2] + E[7] * f[4];
  const S n2 = E[2] * f[0] + E[5] * f[2] + E[8] * f[4];
  f[0] = n0 + (r[1] * l2 - r[2] * l1);
  f[2] = n1 + (r[2] * l0 - r[0] * l2);
  f[4] = n2 + (r[0] * l1 - r[1] * l0);
  f[1] = l0, f[3] = l1, f[5] = l2;
}

/// The entries of d tau / dq and d tau / dv that pair joint column c with the columns r of its
/// own joint and of its ancestors (rnea_derivatives.hpp has the equations). Per column, motion
/// holds s, dv, alpha and beta and force Ic s, Bc^T s, P and Q (6 numbers each, interleaved as
/// inner6 takes them, in the column's body's coordinates); X holds each body's transform from
/// its parent, E then r (12 numbers). Column c is body column_body[c]'s; body b's columns are
/// [first[b], first[b + 1]) and its parent parent[b] (-1 for a root). With carry, the column's
/// forces are carried up its path, one transform a joint, and paired at each body with its
/// columns; without, every term is in base coordinates and X is not read.
template <class S>
inline void column_pairs(int n, int carry, int c, const int* column_body, const int* first,
                         const int* parent, const S* X, const S* motion, const S* force,
                         S* dtau_dq, S* dtau_dv) {
  S f[24];
  for (int k = 0; k < 24; ++k) f[k] = force[24 * c + k];
  const S* IcS = f;
  const S* BcS = f + 6;
  const S* P = f + 12;
  const S* Q = f + 18;
  int b = column_body[c];
  for (int r = first[b]; r < first[b + 1]; ++r) {
    const S* m = motion + 24 * r;  // s, dv, alpha, beta
    dtau_dq[c * n + r] = inner6(IcS, m + 12) + inner6(BcS, m + 6);
    dtau_dv[c * n + r] = inner6(IcS, m + 18) + inner6(BcS, m);
  }
  for (int j = parent[b]; j >= 0; b = j, j = parent[j]) {
    if (carry)
      for (int k = 0; k < 24; k += 6) force_to_parent(X + 12 * b, f + k);
    for (int r = first[j]; r < first[j + 1]; ++r) {
      const S* m = motion + 24 * r;
      dtau_dq[c * n + r] = inner6(IcS, m + 12) + inner6(BcS, m + 6);
      dtau_dv[c * n + r] = inner6(IcS, m + 18) + inner6(BcS, m);
      dtau_dq[r * n + c] = inner6(P, m);
      dtau_dv[r * n + c] = inner6(Q, m);
    }
  }
}

/// column_pairs of every column, n of them, into n x n row-major outputs whose every other
/// entry is zero.
template <class S>
DYNGEN_KERNEL void derivative_pairs(int n, int carry, const int* column_body, const int* first,
                                    const int* parent, const S* X, const S* motion,
                                    const S* force, S* dtau_dq, S* dtau_dv) {
  for (int e = 0; e < n * n; ++e) dtau_dq[e] = S(0), dtau_dv[e] = S(0);
  for (int c = 0; c < n; ++c)
    column_pairs(n, carry, c, column_body, first, parent, X, motion, force, dtau_dq, dtau_dv);
}

/// acc[j] += B[k][c] A[k][r0 + j] for j < W and the rows k of column c of B listed in
/// rows[rows_begin[c] .. rows_begin[c + 1]), in that order.
template <int W, class S>
struct ColumnTimesRows {
  static void run(int n, int c, int r0, const int* rows_begin, const int* rows, const S* A,
                  const S* B, S* acc) {
    for (int e = rows_begin[c]; e < rows_begin[c + 1]; ++e) {
      const int k = rows[e];
      const S b = B[k * n + c];
      for (int j = 0; j < W; ++j) acc[j] = acc[j] + b * A[k * n + r0 + j];
    }
  }
};

#if defined(__GNUC__)
// ColumnTimesRows for double and float with GCC's (and clang's) vector types, which GCC does
// not use by itself here: W rows of C in vectors of LANES and the rest in scalars, each lane
// doing the generic loop's operations in its order, so that the bits are the generic loop's.
template <int W, class S, int LANES>
struct ColumnTimesRowsInLanes {
  static void run(int n, int c, int r0, const int* rows_begin, const int* rows, const S* A,
                  const S* B, S* acc) {
    typedef S lanes __attribute__((vector_size(LANES * sizeof(S))));
    constexpr int V = W / LANES;
    constexpr int R = W - V * LANES;
    lanes sum[V > 0 ? V : 1]{};
    S rest[R > 0 ? R : 1]{};
    __builtin_memcpy(sum, acc, V * sizeof(lanes));
    for (int j = 0; j < R; ++j) rest[j] = acc[V * LANES + j];
    for (int e = rows_begin[c]; e < rows_begin[c + 1]; ++e) {
      const int k = rows[e];
      const S b = B[k * n + c];
      lanes bb{};
      for (int j = 0; j < LANES; ++j) bb[j] = b;
      // unrolled, so that the sums stay in registers at -O2 too
#pragma GCC unroll 16
      for (int j = 0; j < V; ++j) {
        lanes a;
        __builtin_memcpy(&a, A + k * n + r0 + j * LANES, sizeof a);
        sum[j] = sum[j] + bb * a;
      }
#pragma GCC unroll 4
      for (int j = 0; j < R; ++j) rest[j] = rest[j] + b * A[k * n + r0 + V * LANES + j];
    }
    __builtin_memcpy(acc, sum, V * sizeof(lanes));
    for (int j = 0; j < R; ++j) acc[V * LANES + j] = rest[j];
  }
};
template <int W>
struct ColumnTimesRows<W, double> : ColumnTimesRowsInLanes<W, double, 2> {};
template <int W>
struct ColumnTimesRows<W, float> : ColumnTimesRowsInLanes<W, float, 4> {};
#endif

/// Rows r0 .. r0 + W - 1 of column c of C = -(A B).
template <int W, class S>
inline void product_block(int n, int c, int r0, const int* rows_begin, const int* rows,
                          const S* A, const S* B, S* C) {
  S acc[W];
  for (int j = 0; j < W; ++j) acc[j] = S(0);
  ColumnTimesRows<W, S>::run(n, c, r0, rows_begin, rows, A, B, acc);
  for (int j = 0; j < W; ++j) C[(r0 + j) * n + c] = -acc[j];
}

/// product_block of width w, for 1 <= w <= W.
template <int W, class S>
inline void product_block_of(int w, int n, int c, int r0, const int* rows_begin, const int* rows,
                             const S* A, const S* B, S* C) {
  if constexpr (W > 1)
    if (w < W) return product_block_of<W - 1>(w, n, c, r0, rows_begin, rows, A, B, C);
  product_block<W>(n, c, r0, rows_begin, rows, A, B, C);
}

/// The rows of C that one pass over a column's rows of B computes, each in its own accumulator:
/// twelve vectors of two doubles fit in x86-64's sixteen registers, and fewer wait on each
/// addition's latency (solo12 floating's 18 rows in blocks of 16 and 2: the block of two took
/// two fifths of the time of the sixteen).
inline constexpr int product_rows_per_block = 24;

/// C = -(A B) for row-major n x n matrices, A symmetric, and column c of B zero but in the rows
/// rows[rows_begin[c] .. rows_begin[c + 1]) (M^-1 d tau: d tau's column of a joint is zero but
/// in the rows of its path to the root and of its subtree). Each entry is summed over those rows
/// in their order; the rows of C go in blocks of product_rows_per_block, the last the rest.
template <class S>
DYNGEN_KERNEL void neg_product(int n, const int* rows_begin, const int* rows, const S* A,
                               const S* B, S* C) {
  constexpr int block = product_rows_per_block;
  for (int c = 0; c < n; ++c)
    for (int r0 = 0; r0 < n; r0 += block)
      product_block_of<block>(n - r0 < block ? n - r0 : block, n, c, r0, rows_begin, rows, A, B,
                              C);
}

/// The columns of contact_dynamics_derivatives' system (contact_derivatives.hpp), each through
/// the Schur complement over M = L^T D L: for every column c of R1 (n x n) and R2 (m x n),
/// row-major, y = L^-T R1_c, r = R2_c - W D^-1 y, dlam_c = T r and dqdd_c = L^-1 D^-1 (y + W^T
/// dlam_c), with W^T (m x n) and T (m x m) row-major and L below the diagonal of M's factor (n x
/// n, along the columns' parents). Row s of W is zero but in the columns
/// w_columns[w_begin[s] .. w_begin[s + 1]) (its constraint's paths to the root), and column k
/// in the rows w_rows[w_rows_begin[k] .. w_rows_begin[k + 1]), both increasing. The innermost
/// loops run along a row, over the columns, which are independent and contiguous. dqdd may be
/// R1 and dlam R2 (in place); r is scratch (m x n).
template <class S>
DYNGEN_KERNEL void constrained_columns(int n, int m, const int* parent, const int* w_begin,
                                       const int* w_columns, const int* w_rows_begin,
                                       const int* w_rows, const S* L, const S* Dinv, const S* Wt,
                                       const S* T, const S* R1, const S* R2, S* dqdd, S* dlam,
                                       S* r) {
  S* y = dqdd;
  for (int e = 0; e < n * n; ++e) y[e] = R1[e];
  for (int k = n - 1; k >= 0; --k)  // y = L^-T y
    for (int i = parent[k]; i >= 0; i = parent[i])
      for (int c = 0; c < n; ++c) y[i * n + c] = y[i * n + c] - L[k * n + i] * y[k * n + c];
  for (int s = 0; s < m; ++s) {  // r = R2 - W D^-1 y
    for (int c = 0; c < n; ++c) r[s * n + c] = R2[s * n + c];
    for (int e = w_begin[s]; e < w_begin[s + 1]; ++e) {
      const int k = w_columns[e];
      const S w = Wt[s * n + k] * Dinv[k];
      for (int c = 0; c < n; ++c) r[s * n + c] = r[s * n + c] - w * y[k * n + c];
    }
  }
  for (int s = 0; s < m; ++s) {  // dlam = T r
    for (int c = 0; c < n; ++c) dlam[s * n + c] = T[s * m] * r[c];
    for (int t = 1; t < m; ++t)
      for (int c = 0; c < n; ++c) dlam[s * n + c] = dlam[s * n + c] + T[s * m + t] * r[t * n + c];
  }
  for (int k = 0; k < n; ++k) {  // y = D^-1 (y + W^T dlam)
    for (int e = w_rows_begin[k]; e < w_rows_begin[k + 1]; ++e) {
      const int s = w_rows[e];
      for (int c = 0; c < n; ++c) y[k * n + c] = y[k * n + c] + Wt[s * n + k] * dlam[s * n + c];
    }
    for (int c = 0; c < n; ++c) y[k * n + c] = y[k * n + c] * Dinv[k];
  }
  for (int k = 0; k < n; ++k)  // y = L^-1 y
    for (int i = parent[k]; i >= 0; i = parent[i])
      for (int c = 0; c < n; ++c) y[k * n + c] = y[k * n + c] - L[k * n + i] * y[i * n + c];
}

/// The tau columns of contact_dynamics_derivatives (contact_derivatives.hpp's tau_columns) from
/// Y = J M^-1 (m x n), T (m x m) and M^-1 (n x n), all row-major: dlam = -T Y (m x n) and dqdd =
/// M^-1 + Y^T dlam (n x n), symmetric: each row from the diagonal on, mirrored into its column.
/// The innermost loops run along rows.
template <class S>
DYNGEN_KERNEL void inverse_blocks(int n, int m, const S* T, const S* Y, const S* Minv, S* dqdd,
                                  S* dlam) {
  for (int s = 0; s < m; ++s) {
    S* row = dlam + s * n;
    for (int c = 0; c < n; ++c) row[c] = S(0);
    for (int t = 0; t < m; ++t)
      for (int c = 0; c < n; ++c) row[c] = row[c] + T[s * m + t] * Y[t * n + c];
    for (int c = 0; c < n; ++c) row[c] = -row[c];
  }
  for (int i = 0; i < n; ++i) {
    S* row = dqdd + i * n;
    for (int j = i; j < n; ++j) row[j] = Minv[i * n + j];
    for (int s = 0; s < m; ++s)
      for (int j = i; j < n; ++j) row[j] = row[j] + Y[s * n + i] * dlam[s * n + j];
    for (int j = i + 1; j < n; ++j) dqdd[j * n + i] = row[j];
  }
}

}  // namespace kernels
}  // namespace dyngen
