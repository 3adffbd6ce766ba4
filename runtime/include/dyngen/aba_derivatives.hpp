// Partial derivatives of forward dynamics (Carpentier & Mansard, RSS 2018, sec. IV): since
// tau = ID(q, v, FD(q, v, tau)), d qdd / d(q, v) = -M^-1 d tau / d(q, v) at qdd = FD(q, v, tau),
// and d qdd / d tau = M^-1.
//
// M^-1 comes from CRBA's M factorised as L^T D L (RBDA sec. 6.5), which keeps the branches'
// zeros, and qdd = M^-1 (tau - h) with h = nle(q, v): traced, that takes fewer operations on
// every test robot than ABA plus the articulated-body recursion for M^-1, which carry
// articulated inertias (21 numbers a body) through every joint where CRBA carries rigid ones (10)
// (docs/performance.md, "M^-1 from CRBA's factorised M"). minv takes the same path.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "dyngen/crba.hpp"
#include "dyngen/kernels.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/rnea_derivatives.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// d qdd / dq, d qdd / dv and M^-1 (= d qdd / d tau) of aba(q, v, tau), row-major nv x nv; the
/// columns of a free joint are tangent directions, as in rnea_derivatives. aba's precondition
/// (every joint moves some inertia, so M is positive definite) and minv's matrix buffers. No
/// allocation.
template <class S>
void aba_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                     std::span<const S> qd, std::span<const S> tau, std::span<S> dqdd_dq,
                     std::span<S> dqdd_dv, std::span<S> Minv) {
  const int n = model.nv;
  crba<S>(model, ws, q, ws.H);
  factor_ltdl<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv);
  ltdl_inverse<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv, ws.Linv, Minv);
  nle<S>(model, ws, q, qd, ws.h);
  // qdd = M^-1 (tau - h)
  TraceHook<S>::enter(-1, Pass::Product);
  for (int i = 0; i < n; ++i) ws.h[i] = tau[i] - ws.h[i];
  for (int i = 0; i < n; ++i) {
    S sum = S(0);
    for (int j = 0; j < n; ++j) sum = sum + Minv[row_major(n, i, j)] * ws.h[j];
    ws.qdd[i] = sum;
  }
  rnea_derivatives<S>(model, ws, q, qd, ws.qdd, ws.dtau_dq, ws.dtau_dv);
  // -M^-1 d tau over the entries of d tau that can be non-zero
  TraceHook<S>::enter(-1, Pass::Product);
  const int ints[] = {n};
  const std::string_view names[] = {"rows_begin", "rows", "Minv", "dtau", "dqdd"};
  const std::pair<std::span<const S>, std::span<S>> products[] = {{ws.dtau_dq, dqdd_dq},
                                                                  {ws.dtau_dv, dqdd_dv}};
  for (int d = 0; d < 2; ++d) {
    const std::vector<int>& begin = ws.product_begin[d];
    const std::vector<int>& rows = ws.product_rows[d];
    const std::span<const int> tables[] = {begin, rows};
    const std::span<const S> inputs[] = {Minv, products[d].first};
    const std::span<S> outputs[] = {products[d].second};
    run_kernel<S>({"neg_product", ints, tables, inputs, outputs, names},
                  [&](auto in, auto out) {
                    kernels::neg_product(n, begin.data(), rows.data(), in[0].data(), in[1].data(),
                                         out[0].data());
                  });
  }
}

}  // namespace dyngen
