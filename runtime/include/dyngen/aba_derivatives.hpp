// Partial derivatives of forward dynamics (Carpentier & Mansard, RSS 2018, sec. IV): since
// tau = ID(q, v, FD(q, v, tau)), d qdd / d(q, v) = -M^-1 d tau / d(q, v) at qdd = FD(q, v, tau),
// and d qdd / d tau = M^-1.
#pragma once

#include <span>
#include <string_view>
#include <utility>

#include "dyngen/aba.hpp"
#include "dyngen/kernels.hpp"
#include "dyngen/minv.hpp"
#include "dyngen/rnea_derivatives.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// d qdd / dq, d qdd / dv and M^-1 (= d qdd / d tau) of aba(q, v, tau), row-major nv x nv; the
/// columns of a free joint are tangent directions, as in rnea_derivatives. The preconditions of
/// aba and minv. No allocation.
template <class S>
void aba_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                     std::span<const S> qd, std::span<const S> tau, std::span<S> dqdd_dq,
                     std::span<S> dqdd_dv, std::span<S> Minv) {
  aba<S>(model, ws, q, qd, tau, ws.qdd);
  rnea_derivatives<S>(model, ws, q, qd, ws.qdd, ws.dtau_dq, ws.dtau_dv);
  minv<S>(model, ws, q, Minv);
  // -M^-1 d tau over the entries of d tau that can be non-zero
  TraceHook<S>::enter(-1, Pass::Product);
  const int n = model.nv;
  const int ints[] = {n};
  const std::span<const int> tables[] = {ws.product_begin, ws.product_rows};
  const std::string_view names[] = {"rows_begin", "rows", "Minv", "dtau", "dqdd"};
  for (const auto& [dtau, dqdd] : {std::pair{std::span<const S>(ws.dtau_dq), dqdd_dq},
                                   std::pair{std::span<const S>(ws.dtau_dv), dqdd_dv}}) {
    const std::span<const S> inputs[] = {Minv, dtau};
    const std::span<S> outputs[] = {dqdd};
    run_kernel<S>({"neg_product", ints, tables, inputs, outputs, names},
                  [&](auto in, auto out) {
                    kernels::neg_product(n, ws.product_begin.data(), ws.product_rows.data(),
                                         in[0].data(), in[1].data(), out[0].data());
                  });
  }
}

}  // namespace dyngen
