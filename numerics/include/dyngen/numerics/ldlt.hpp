// Forward dynamics the other way: M from CRBA, the bias h = RNEA(q, qd, 0), then
// qdd = M^-1 (tau - h) through Eigen's LDL^T factorisation (with diagonal pivoting). The
// alternative to ABA that numerics.md and dyngen report compare it with.
#pragma once

#include <Eigen/Dense>

#include <span>
#include <vector>

#include "dyngen/crba.hpp"
#include "dyngen/rnea.hpp"

namespace dyngen::numerics {

/// Buffers for crba_ldlt_forward_dynamics, allocated once per model.
template <class S>
struct LdltWorkspace {
  explicit LdltWorkspace(const Model<S>& model)
      : ws(model), M(model.nv, model.nv), h(model.nv), zero(model.nv, S(0)), ldlt(model.nv) {}

  Workspace<S> ws;
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M;
  Eigen::Matrix<S, Eigen::Dynamic, 1> h;
  std::vector<S> zero;
  Eigen::LDLT<Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>> ldlt;
};

/// qdd = M(q)^-1 (tau - h(q, qd)) with M from crba, h from rnea and an LDL^T solve.
template <class S>
void crba_ldlt_forward_dynamics(const Model<S>& model, LdltWorkspace<S>& w,
                                std::span<const S> q, std::span<const S> qd,
                                std::span<const S> tau, std::span<S> qdd) {
  const int n = model.nv;
  crba<S>(model, w.ws, q, std::span<S>(w.M.data(), static_cast<std::size_t>(n) * n));
  rnea<S>(model, w.ws, q, qd, w.zero, std::span<S>(w.h.data(), n));
  w.ldlt.compute(w.M);
  Eigen::Map<Eigen::Matrix<S, Eigen::Dynamic, 1>> x(qdd.data(), n);
  x = w.ldlt.solve(Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, 1>>(tau.data(), n) - w.h);
}

}  // namespace dyngen::numerics
