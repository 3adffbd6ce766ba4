// How hard a robot's dynamics are for floating-point arithmetic, estimated over sampled
// states: the condition number of the mass matrix, the smallest ABA pivot D_i relative to the
// articulated inertia it is taken from, and the dynamic range of the model's numbers. All of it
// is computed in long double, so that the estimate is not limited by the double arithmetic it
// judges.
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "dyngen/aba.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/numerics/conditioning_estimate.hpp"
#include "dyngen/numerics/random.hpp"

namespace dyngen::numerics {

using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;

/// cond_2(M) of a symmetric positive definite matrix: lambda_max(M) * lambda_max(M^-1), with
/// M^-1 from an LDL^T factorisation, which keeps the small eigenvalues of graded matrices (a
/// heavy base with light tips) that an eigensolver on M would lose in lambda_max's rounding.
/// +inf when M is not numerically positive definite.
inline double condition_number(const MatrixL& M) {
  const Eigen::LDLT<MatrixL> ldlt(M);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      (ldlt.vectorD().array() <= 0).any())
    return std::numeric_limits<double>::infinity();
  const MatrixL Minv = ldlt.solve(MatrixL::Identity(M.rows(), M.cols()));
  const Eigen::SelfAdjointEigenSolver<MatrixL> eig(M, Eigen::EigenvaluesOnly);
  const Eigen::SelfAdjointEigenSolver<MatrixL> eig_inv(Minv, Eigen::EigenvaluesOnly);
  const long double cond = eig.eigenvalues().maxCoeff() * eig_inv.eigenvalues().maxCoeff();
  return std::isfinite(cond) && cond > 0 ? static_cast<double>(cond)
                                         : std::numeric_limits<double>::infinity();
}

namespace detail {

template <class S>
S max_abs(const ArticulatedInertia<S>& A) {
  using std::abs;
  S m = 0;
  for (const S& x : {A.I.xx, A.I.yy, A.I.zz, A.I.xy, A.I.xz, A.I.yz, A.H.xx, A.H.xy, A.H.xz,
                     A.H.yx, A.H.yy, A.H.yz, A.H.zx, A.H.zy, A.H.zz, A.M.xx, A.M.yy, A.M.zz,
                     A.M.xy, A.M.xz, A.M.yz})
    m = std::max(m, abs(x));
  return m;
}

}  // namespace detail

/// The pivots of the forward dynamics of a robot with mimic joints, which factorise M = L^T D L
/// (aba.hpp): D_k / M_kk of each column k at q.
template <class S>
std::vector<S> factorised_pivots(const Model<S>& model, Workspace<S>& ws, const std::vector<S>& q) {
  const int n = model.nv;
  std::vector<S> M(static_cast<std::size_t>(n) * n), Dinv(n), pivots(n);
  crba<S>(model, ws, q, M);
  for (int k = 0; k < n; ++k) pivots[k] = M[row_major(n, k, k)];
  factor_ltdl<S>(n, ws.column_parent.data(), M, Dinv);
  for (int k = 0; k < n; ++k) pivots[k] = 1 / Dinv[k] / pivots[k];
  return pivots;
}

namespace detail {

/// The smallest factorised pivot at q into c.pivot_min and c.pivot_joint.
inline void mimic_pivots(const Model<long double>& ml, Workspace<long double>& ws,
                         const std::vector<long double>& q, Conditioning& c) {
  c.factorised = true;
  const std::vector<long double> pivots = factorised_pivots(ml, ws, q);
  for (int i = 0; i < ml.nbodies; ++i)
    for (int d = 0; d < joint_nv(ml.joint_type[i]) && !is_mimic(ml, i); ++d) {
      const long double pivot = pivots[ml.v_index[i] + d];
      const double p = pivot > 0 ? static_cast<double>(pivot) : 0.0;  // NaN too
      if (p < c.pivot_min) c.pivot_min = p, c.pivot_joint = ml.joint_name[i];
    }
}

/// The smallest eigenvalue of a symmetric 3x3: a ball joint's D, the pivot block ABA inverts.
template <class S>
S smallest_eigenvalue(const Sym3<S>& A) {
  Eigen::Matrix<S, 3, 3> D;
  D << A.xx, A.xy, A.xz, A.xy, A.yy, A.yz, A.xz, A.yz, A.zz;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<S, 3, 3>>(D, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .minCoeff();
}

/// The smallest eigenvalue of [I H; H^T M]: the pivot that the LDL^T solve below a free joint
/// divides by, at its smallest.
template <class S>
S smallest_eigenvalue(const ArticulatedInertia<S>& A) {
  Eigen::Matrix<S, 6, 6> D;
  D << A.I.xx, A.I.xy, A.I.xz, A.H.xx, A.H.xy, A.H.xz,  //
      A.I.xy, A.I.yy, A.I.yz, A.H.yx, A.H.yy, A.H.yz,   //
      A.I.xz, A.I.yz, A.I.zz, A.H.zx, A.H.zy, A.H.zz,   //
      A.H.xx, A.H.yx, A.H.zx, A.M.xx, A.M.xy, A.M.xz,   //
      A.H.xy, A.H.yy, A.H.zy, A.M.xy, A.M.yy, A.M.yz,   //
      A.H.xz, A.H.yz, A.H.zz, A.M.xz, A.M.yz, A.M.zz;
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<S, 6, 6>>(D, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .minCoeff();
}

/// The largest eigenvalue of the symmetric positive definite operator y = A x (apply(x, y)), by
/// power iterations from x: Rayleigh quotients, which approach it from below. Stops when one
/// changes by less than 1e-3 relative, or after 60; +inf when A x is not finite.
template <class Apply>
long double largest_eigenvalue(Apply apply, std::vector<long double> x) {
  std::vector<long double> y(x.size());
  long double lambda = 0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    long double norm = 0;
    for (const long double xi : x) norm += xi * xi;
    norm = std::sqrt(norm);
    for (long double& xi : x) xi /= norm;
    apply(x, y);
    long double quotient = 0;
    for (std::size_t k = 0; k < x.size(); ++k) quotient += x[k] * y[k];
    if (!std::isfinite(quotient)) return std::numeric_limits<long double>::infinity();
    const bool converged = std::abs(quotient - lambda) <= 1e-3L * std::abs(quotient);
    lambda = quotient;
    if (converged) break;
    x.swap(y);
  }
  return lambda;
}

inline int count_float_unrepresentable(const Model<double>& model) {
  int count = 0;
  const auto check = [&](double x) {
    const double a = std::abs(x);
    if (a != 0 && (a < std::numeric_limits<float>::min() || a > std::numeric_limits<float>::max()))
      ++count;
  };
  for (int i = 0; i < model.nbodies; ++i) {
    const Mat3<double>& E = model.X_tree[i].E;
    for (double x : {E.xx, E.xy, E.xz, E.yx, E.yy, E.yz, E.zx, E.zy, E.zz}) check(x);
    const Vec3<double>& r = model.X_tree[i].r;
    const RigidInertia<double>& I = model.I[i];
    for (double x : {r.x, r.y, r.z, I.m, I.h.x, I.h.y, I.h.z, I.I.xx, I.I.yy, I.I.zz, I.I.xy,
                     I.I.xz, I.I.yz})
      check(x);
  }
  return count;
}

}  // namespace detail

/// cond_2(M(q)) = lambda_max(M) lambda_max(M^-1) from power iterations, M x by RNEA and M^-1 x
/// by ABA without gravity and velocity (ml0): O(nv) per iteration, no nv x nv matrix. A lower
/// bound; +inf when ABA divides by zero (M is singular).
inline double condition_number_by_iteration(const Model<long double>& ml0,
                                            Workspace<long double>& ws,
                                            const std::vector<long double>& q, Random& rng) {
  const std::size_t n = static_cast<std::size_t>(ml0.nv);
  const std::vector<long double> zero(n, 0.0L);
  std::vector<long double> start(n);
  for (long double& x : start) x = rng.uniform(-1, 1);
  const long double largest = detail::largest_eigenvalue(
      [&](const std::vector<long double>& x, std::vector<long double>& y) {
        rnea<long double>(ml0, ws, q, zero, x, y);
      },
      start);
  const long double inverse_largest = detail::largest_eigenvalue(
      [&](const std::vector<long double>& x, std::vector<long double>& y) {
        aba<long double>(ml0, ws, q, zero, x, y);
      },
      start);
  const long double cond = largest * inverse_largest;
  return std::isfinite(cond) && cond > 0 ? static_cast<double>(cond)
                                         : std::numeric_limits<double>::infinity();
}

/// Samples `samples` random states (random_state with `seed`) and measures the model's
/// conditioning at each; above dense_conditioning_limit velocity entries, at no more than
/// large_robot_samples states and with cond(M) from power iterations. ABA's pivots are measured
/// only if `with_aba` (ABA is undefined when a joint moves no inertia).
inline Conditioning estimate_conditioning(const Model<double>& model, int samples,
                                          std::uint64_t seed, bool with_aba = true) {
  Conditioning c;
  c.cond_M_lower_bound = model.nv > dense_conditioning_limit;
  c.samples = c.cond_M_lower_bound ? std::min(samples, large_robot_samples) : samples;
  c.float_unrepresentable = detail::count_float_unrepresentable(model);
  const Model<long double> ml = model.cast<long double>();
  Model<long double> ml0 = ml;
  ml0.gravity = {};
  Workspace<long double> ws(ml);
  Random rng(seed);
  std::vector<double> conds;
  long double inertia_max = 0, inertia_min = std::numeric_limits<long double>::infinity();
  for (int s = 0; s < c.samples; ++s) {
    const State state = random_state(model, rng);
    const std::vector<long double> q(state.q.begin(), state.q.end());
    const std::vector<long double> qd(state.qd.begin(), state.qd.end());
    const std::vector<long double> tau(state.tau.begin(), state.tau.end());
    std::vector<long double> qdd(ml.nv);
    if (c.cond_M_lower_bound) {
      conds.push_back(condition_number_by_iteration(ml0, ws, q, rng));
    } else {
      std::vector<long double> M(static_cast<std::size_t>(ml.nv) * ml.nv);
      crba<long double>(ml, ws, q, M);
      conds.push_back(condition_number(Eigen::Map<const MatrixL>(M.data(), ml.nv, ml.nv)));
    }

    if (!with_aba) continue;
    if (!ml.mimic.empty()) {
      detail::mimic_pivots(ml, ws, q, c);
      continue;
    }
    aba<long double>(ml, ws, q, qd, tau, qdd);
    for (int i = 0; i < ml.nbodies; ++i) {
      const long double size = detail::max_abs(ws.IA[i]);
      inertia_max = std::max(inertia_max, size);
      inertia_min = std::min(inertia_min, size);
      const JointType t = ml.joint_type[i];
      const long double D =
          t == JointType::Free   ? detail::smallest_eigenvalue(ws.IA[i])
          : t == JointType::Ball ? detail::smallest_eigenvalue(
                                       dyngen::detail::ball_D(ml, ws.IA[i], ml.v_index[i]))
                                 : ws.D[i];
      const double pivot = size > 0 ? static_cast<double>(D / size) : 0.0;
      if (pivot < c.pivot_min) c.pivot_min = pivot, c.pivot_joint = ml.joint_name[i];
    }
  }
  std::sort(conds.begin(), conds.end());
  if (!conds.empty()) {
    c.cond_M_median = conds[conds.size() / 2];
    c.cond_M_max = conds.back();
  }
  if (inertia_min > 0) c.inertia_range = static_cast<double>(inertia_max / inertia_min);
  else if (inertia_max > 0) c.inertia_range = std::numeric_limits<double>::infinity();
  return c;
}

}  // namespace dyngen::numerics
