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

/// qdd = M^-1 (tau - h) for any CRBA and RNEA with the generated code's signatures,
/// crba(q, M) and rnea(q, qd, qdd, tau) on raw arrays (M row-major); buffers allocated once.
template <class S>
class LdltForwardDynamics {
 public:
  explicit LdltForwardDynamics(int nv)
      : M_(nv, nv), h_(nv), zero_(Vector::Zero(nv)), rhs_(nv), ldlt_(nv) {}

  template <class Crba, class Rnea>
  void operator()(Crba crba_fn, Rnea rnea_fn, const S* q, const S* qd, const S* tau, S* qdd) {
    const Eigen::Index n = h_.size();
    crba_fn(q, M_.data());
    rnea_fn(q, qd, zero_.data(), h_.data());
    ldlt_.compute(M_);
    rhs_ = Eigen::Map<const Vector>(tau, n) - h_;
    Eigen::Map<Vector>(qdd, n) = ldlt_.solve(rhs_);
  }

 private:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M_;
  Vector h_, zero_, rhs_;
  Eigen::LDLT<Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>> ldlt_;
};

/// Buffers for crba_ldlt_forward_dynamics, allocated once per model.
template <class S>
struct LdltWorkspace {
  explicit LdltWorkspace(const Model<S>& model) : ws(model), solve(model.nv) {}

  Workspace<S> ws;
  LdltForwardDynamics<S> solve;
};

/// qdd = M(q)^-1 (tau - h(q, qd)) with the runtime's crba and rnea and an LDL^T solve.
template <class S>
void crba_ldlt_forward_dynamics(const Model<S>& model, LdltWorkspace<S>& w,
                                std::span<const S> q, std::span<const S> qd,
                                std::span<const S> tau, std::span<S> qdd) {
  const std::size_t nq = model.nq, nv = model.nv;
  w.solve(
      [&](const S* q_, S* M) { crba<S>(model, w.ws, {q_, nq}, {M, nv * nv}); },
      [&](const S* q_, const S* qd_, const S* qdd_, S* tau_) {
        rnea<S>(model, w.ws, {q_, nq}, {qd_, nv}, {qdd_, nv}, {tau_, nv});
      },
      q.data(), qd.data(), tau.data(), qdd.data());
}

}  // namespace dyngen::numerics
