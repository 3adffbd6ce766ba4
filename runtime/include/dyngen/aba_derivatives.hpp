// Partial derivatives of forward dynamics (Carpentier & Mansard, RSS 2018, sec. IV): since
// tau = ID(q, v, FD(q, v, tau)), d qdd / d(q, v) = -M^-1 d tau / d(q, v) at qdd = FD(q, v, tau),
// and d qdd / d tau = M^-1.
#pragma once

#include <cstddef>
#include <span>

#include "dyngen/aba.hpp"
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
  const std::size_t n = static_cast<std::size_t>(model.nv);
  aba<S>(model, ws, q, qd, tau, ws.qdd);
  rnea_derivatives<S>(model, ws, q, qd, ws.qdd, ws.dtau_dq, ws.dtau_dv);
  minv<S>(model, ws, q, Minv);
  // -M^-1 dtau, each entry summed over k in order
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < n; ++c) {
      S dq = Minv[r * n] * ws.dtau_dq[c], dv = Minv[r * n] * ws.dtau_dv[c];
      for (std::size_t k = 1; k < n; ++k) {
        dq = dq + Minv[r * n + k] * ws.dtau_dq[k * n + c];
        dv = dv + Minv[r * n + k] * ws.dtau_dv[k * n + c];
      }
      dqdd_dq[r * n + c] = -dq;
      dqdd_dv[r * n + c] = -dv;
    }
}

}  // namespace dyngen
