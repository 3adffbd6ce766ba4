// Dynamics under contacts and loop closures (Model::constraints): forward dynamics with the
// constraint forces, and the impulse at touchdown. Both solve the KKT system
//   [M  J^T] [ qdd ]   [tau - h]
//   [J   0 ] [-lam ] = [  c    ]
// by its Schur complement over M = L^T D L factorised along the tree (crba.hpp, RBDA sec. 6.5):
// W^T = L^-T J^T keeps a constraint's column on its path to the root, so that the operational
// space inverse inertia A = J M^-1 J^T = W D^-1 W^T couples two contacts only through the joints
// their paths share (a quadruped's feet: the base's six). lam solves A lam = c - J M^-1 (tau - h)
// by proximal iterations (A + mu) lam_{k+1} = r + mu lam_k from lam_0 = 0, with mu = damping
// times A's mean diagonal: redundant rows (four feet in 6d, 24 rows for 18 DoF) give a finite
// lam that tends to the minimum-norm one, with no branch on values (docs/design.md,
// "Constraints").
#pragma once

#include <span>
#include <utility>

#include "dyngen/configuration.hpp"
#include "dyngen/crba.hpp"
#include "dyngen/frames.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// The proximal iterations of the constrained solves: each one divides the error of lam along
/// an eigenvalue s of A by 1 + s / mu.
inline constexpr int proximal_iterations = 3;

namespace detail {

/// A loop's position error, frame A from frame B in base axes: p_A - p_B, then for the rotation
/// 1/2 vee(R_A R_B^T - R_B R_A^T) (theta times the axis to first order), R = E^T.
template <class S>
void position_error(const Xform<S>& XA, const Xform<S>& XB, S* e) {
  const Vec3<S> d = XA.r - XB.r;
  e[0] = d.x, e[1] = d.y, e[2] = d.z;
  const Mat3<S> R = mul(transpose(XA.E), XB.E);  // R_A R_B^T = E_A^T E_B
  e[3] = (R.zy - R.yz) / S(2), e[4] = (R.xz - R.zx) / S(2), e[5] = (R.yx - R.xy) / S(2);
}

/// A contact's reference placement from its rows of `anchors` (contact_dynamics_anchored): the
/// origin p, and for 6 rows the rotation exp([w]) of the vector w after it (base axes).
template <class S>
Xform<S> anchor_placement(const S* anchor, int rows) {
  Xform<S> X{{S(1), S(0), S(0), S(0), S(1), S(0), S(0), S(0), S(1)},
             {anchor[0], anchor[1], anchor[2]}};
  if (rows == 6) {  // R = 1 + sin t/t [w] + (1 - cos t)/t^2 [w]^2; E = R^T
    const Vec3<S> w{anchor[3], anchor[4], anchor[5]};
    const S t2 = dot(w, w), h = half_sinc(t2);
    X.E = transpose(so3_matrix(w, S(2) * h * half_cos(t2), S(2) * h * h));
  }
  return X;
}

/// Frames A and B of constraint k (base to frame) after body_placements: B of an anchored
/// contact (`anchor`: its rows of anchors, or null) is its reference, which does not move.
template <class S>
std::pair<Xform<S>, Xform<S>> constraint_frames(const Workspace<S>& ws, const Constraint<S>& k,
                                                const S* anchor) {
  const Xform<S> XA = k.body_a < 0 ? k.placement_a : compose(k.placement_a, ws.X0[k.body_a]);
  if (anchor && !k.loop) return {XA, anchor_placement(anchor, constraint_rows(k))};
  return {XA, k.body_b < 0 ? k.placement_b : compose(k.placement_b, ws.X0[k.body_b])};
}

/// Whether kp acts on constraint k's position error: a loop's, an anchored contact's.
template <class S>
bool positioned(const Constraint<S>& k, std::span<const S> anchors) {
  return k.loop || !anchors.empty();
}

/// ws.Jc (nc x nv, row-major) = J_A - J_B of each constraint in base axes at its frames'
/// origins (rows: linear, then angular), and ws.gamma = Jdot v, their classical accelerations
/// at qdd = 0; with v, also ws.Jv = J v and the position errors ws.perr of loops, and of
/// contacts from their reference placements where `anchors` (nc) gives them. After
/// body_bias_accelerations (or body_placements with v empty: J alone).
template <class S>
void constraint_jacobians(const Model<S>& model, Workspace<S>& ws, bool with_v,
                          std::span<const S> anchors = {}) {
  const int nv = model.nv;
  for (std::size_t e = 0; e < ws.Jc.size(); ++e) ws.Jc[e] = S(0);
  int row = 0;
  for (const Constraint<S>& k : model.constraints) {
    TraceHook<S>::enter(k.body_a, Pass::Frames);
    const int rows = constraint_rows(k);
    const auto [XA, XB] = constraint_frames(ws, k, anchors.empty() ? nullptr : &anchors[row]);
    S* J = &ws.Jc[static_cast<std::size_t>(row) * nv];
    put_frame_jacobian(model, ws, k.body_a, XA, JacobianAxes::World, rows, false, J);
    if (k.body_b >= 0)
      put_frame_jacobian(model, ws, k.body_b, XB, JacobianAxes::World, rows, true, J);
    TraceHook<S>::enter(k.body_a, Pass::Constraints);
    if (with_v) {
      const Motion<S> gA = frame_bias_acceleration(ws, k.body_a, XA);
      const Motion<S> gB = frame_bias_acceleration(ws, k.body_b, XB);
      const Motion<S> vA = frame_velocity(ws, k.body_a, XA), vB = frame_velocity(ws, k.body_b, XB);
      const Motion<S> g = gA - gB, w = vA - vB;
      const S gs[6] = {g.lin.x, g.lin.y, g.lin.z, g.ang.x, g.ang.y, g.ang.z};
      const S ws6[6] = {w.lin.x, w.lin.y, w.lin.z, w.ang.x, w.ang.y, w.ang.z};
      // the position error of a loop, or of a contact from its anchor where one is given
      S e[6] = {};
      if (positioned(k, anchors)) position_error(XA, XB, e);
      for (int r = 0; r < rows; ++r) {
        ws.gamma[row + r] = gs[r];
        ws.Jv[row + r] = ws6[r];
        ws.perr[row + r] = e[r];
      }
    }
    row += rows;
  }
}

/// x = L^-T x in place (the first half of ltdl_solve): from the deepest column up.
template <class S>
void ltdl_half_solve(int n, const int* parent, std::span<const S> L, S* x) {
  for (int k = n - 1; k >= 0; --k)
    for (int i = parent[k]; i >= 0; i = parent[i]) x[i] = x[i] - L[row_major(n, k, i)] * x[k];
}

/// x = L^-1 D^-1 x in place (the rest of ltdl_solve).
template <class S>
void ltdl_finish_solve(int n, const int* parent, std::span<const S> L, std::span<const S> Dinv,
                       S* x) {
  for (int k = 0; k < n; ++k) x[k] = x[k] * Dinv[k];
  for (int k = 0; k < n; ++k)
    for (int i = parent[k]; i >= 0; i = parent[i]) x[k] = x[k] - L[row_major(n, k, i)] * x[i];
}

/// mu = the damping times A's mean diagonal, after A is formed.
template <class S>
S proximal_damping(const Model<S>& model, const Workspace<S>& ws) {
  const int m = model.nc;
  S trace{};
  for (int r = 0; r < m; ++r) trace = trace + ws.A[row_major(m, r, r)];
  return model.constraint_settings.damping * trace / S(m);
}

/// x = (A + mu)^-1 x in place, by its L D L^T (operational_space): L y = x, y /= D, L^T x = y,
/// with L_ij = A_damped_ij / D_j.
template <class S>
void damped_solve(int m, const Workspace<S>& ws, S* x) {
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < i; ++k) x[i] = x[i] - ws.A_damped[row_major(m, i, k)] * ws.A_Dinv[k] * x[k];
  for (int i = 0; i < m; ++i) x[i] = x[i] * ws.A_Dinv[i];
  for (int i = m - 1; i >= 0; --i)
    for (int k = i + 1; k < m; ++k)
      x[i] = x[i] - ws.A_damped[row_major(m, k, i)] * ws.A_Dinv[i] * x[k];
}

/// After crba and factor_ltdl into ws.H: ws.Wt = L^-T J^T (nc rows of nv) and A = W D^-1 W^T
/// into ws.A (nc x nc), with ws.A_damped = A + mu factorised as LDL^T (unit lower triangle below
/// the diagonal, 1 / pivots in ws.A_Dinv).
template <class S>
void operational_space(const Model<S>& model, Workspace<S>& ws) {
  const int n = model.nv, m = model.nc;
  const auto entry = [&](int r, int s) {  // A_rs = sum over k of W_rk D_k^-1 W_sk
    S sum{};
    for (int k = 0; k < n; ++k)
      sum = sum + ws.Wt[row_major(n, r, k)] * ws.column_Dinv[k] * ws.Wt[row_major(n, s, k)];
    ws.A[row_major(m, r, s)] = ws.A[row_major(m, s, r)] = sum;
  };
  // each constraint's rows of W and its own block of A, at its link (a quadruped's feet do the
  // same operations, which the code computes in vector lanes), then the blocks between them
  int first = 0;
  for (const Constraint<S>& c : model.constraints) {
    TraceHook<S>::enter(c.body_a, Pass::Constraints);
    const int end = first + constraint_rows(c);
    for (int r = first; r < end; ++r) {
      for (int k = 0; k < n; ++k) ws.Wt[row_major(n, r, k)] = ws.Jc[row_major(n, r, k)];
      ltdl_half_solve<S>(n, ws.column_parent.data(), ws.H, &ws.Wt[row_major(n, r, 0)]);
      for (int s = first; s <= r; ++s) entry(r, s);
    }
    first = end;
  }
  TraceHook<S>::enter(-1, Pass::Constraints);
  first = 0;
  for (const Constraint<S>& c : model.constraints) {
    for (int r = first; r < first + constraint_rows(c); ++r)
      for (int s = 0; s < first; ++s) entry(r, s);
    first += constraint_rows(c);
  }
  const S mu = proximal_damping(model, ws);
  // A + mu = L D L^T, column by column, keeping L_ij D_j below the diagonal: L_ij is that times
  // 1 / D_j, the product the solves take too
  const auto L = [&](int i, int j) { return ws.A_damped[row_major(m, i, j)] * ws.A_Dinv[j]; };
  for (int j = 0; j < m; ++j) {
    S d = ws.A[row_major(m, j, j)] + mu;
    for (int k = 0; k < j; ++k) d = d - L(j, k) * ws.A_damped[row_major(m, j, k)];
    ws.A_Dinv[j] = S(1) / d;
    for (int i = j + 1; i < m; ++i) {
      S x = ws.A[row_major(m, i, j)];
      for (int k = 0; k < j; ++k) x = x - L(i, k) * ws.A_damped[row_major(m, j, k)];
      ws.A_damped[row_major(m, i, j)] = x;
    }
  }
}

/// lam with A lam = r by the proximal iterations, after operational_space: lam_{k+1} = lam_k +
/// (A + mu)^-1 (r - A lam_k) from lam_0 = 0.
template <class S>
void proximal_solve(const Model<S>& model, Workspace<S>& ws, std::span<const S> r,
                    std::span<S> lam) {
  TraceHook<S>::enter(-1, Pass::Constraints);
  const int m = model.nc;
  for (int i = 0; i < m; ++i) lam[i] = S(0);
  for (int it = 0; it < proximal_iterations; ++it) {
    S* x = ws.lam_step.data();
    for (int i = 0; i < m; ++i) {
      S res = r[i];
      for (int j = 0; j < m && it > 0; ++j) res = res - ws.A[row_major(m, i, j)] * lam[j];
      x[i] = res;
    }
    damped_solve(m, ws, x);
    for (int i = 0; i < m; ++i) lam[i] = lam[i] + x[i];
  }
}

/// x = L^-1 D^-1 (y + W^T lam) = M^-1 (b + J^T lam) for y = L^-T b.
template <class S>
void constrained_solution(const Model<S>& model, Workspace<S>& ws, std::span<const S> y,
                          std::span<const S> lam, std::span<S> x) {
  TraceHook<S>::enter(-1, Pass::Constraints);
  const int n = model.nv, m = model.nc;
  for (int k = 0; k < n; ++k) {
    S sum = y[k];
    for (int r = 0; r < m; ++r) sum = sum + ws.Wt[row_major(n, r, k)] * lam[r];
    x[k] = sum;
  }
  ltdl_finish_solve<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv, x.data());
}

/// M (ws.H) factorised as L^T D L, the constraints' J and A at q, and with v their Jdot v, J v
/// and position errors (contacts' from anchors, where given).
template <class S>
void prepare_constraints(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                         std::span<const S> v, std::span<const S> anchors = {}) {
  crba<S>(model, ws, q, ws.H);
  factor_ltdl<S>(model.nv, ws.column_parent.data(), ws.H, ws.column_Dinv);
  body_bias_accelerations(model, ws, q, v);
  constraint_jacobians(model, ws, true, anchors);
  operational_space(model, ws);
}

}  // namespace detail

/// Forward dynamics under the model's constraints: qdd and the multipliers lam (nc: per
/// constraint 3 or 6, the force on frame A at its origin then the moment, base axes) with
/// M qdd + h = tau + J^T lam and J qdd + Jdot v = -kd J v - kp e (Baumgarte; e a loop's position
/// error, and a contact's from its reference placement in `anchors` when given: nc entries, per
/// contact its origin, then for 6 rows the rotation vector of its axes, base coordinates; a
/// loop's entries are not read). Needs the workspace's matrix buffers; no allocation.
template <class S>
void contact_dynamics(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<const S> v, std::span<const S> tau, std::span<S> qdd,
                      std::span<S> lam, std::span<const S> anchors = {}) {
  const int n = model.nv, m = model.nc;
  detail::prepare_constraints(model, ws, q, v, anchors);
  nle<S>(model, ws, q, v, ws.h);
  TraceHook<S>::enter(-1, Pass::Constraints);
  // y = L^-T (tau - h); r = c - J M^-1 (tau - h) = c - W D^-1 y
  for (int k = 0; k < n; ++k) ws.qdd[k] = tau[k] - ws.h[k];
  detail::ltdl_half_solve<S>(n, ws.column_parent.data(), ws.H, ws.qdd.data());
  const ConstraintSettings<S>& cs = model.constraint_settings;
  for (int r = 0; r < m; ++r) {
    S c = -ws.gamma[r] - cs.kd * ws.Jv[r] - cs.kp * ws.perr[r];
    for (int k = 0; k < n; ++k) c = c - ws.Wt[row_major(n, r, k)] * ws.column_Dinv[k] * ws.qdd[k];
    ws.rc[r] = c;
  }
  detail::proximal_solve<S>(model, ws, ws.rc, lam);
  detail::constrained_solution<S>(model, ws, ws.qdd, lam, qdd);
}

/// The impulse at touchdown: v_plus and the impulses p (nc, as contact_dynamics' lam, in N s)
/// with M (v_plus - v_minus) = J^T p and J v_plus = -e J v_minus (e = the restitution; 0:
/// perfectly inelastic). Needs the workspace's matrix buffers; no allocation.
template <class S>
void impulse_dynamics(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<const S> v_minus, std::span<S> v_plus, std::span<S> p) {
  const int n = model.nv, m = model.nc;
  detail::prepare_constraints(model, ws, q, v_minus);
  TraceHook<S>::enter(-1, Pass::Constraints);
  const S e1 = S(1) + model.constraint_settings.restitution;
  for (int r = 0; r < m; ++r) ws.rc[r] = -e1 * ws.Jv[r];
  detail::proximal_solve<S>(model, ws, ws.rc, p);
  for (int k = 0; k < n; ++k) ws.qdd[k] = S(0);
  detail::constrained_solution<S>(model, ws, ws.qdd, p, v_plus);
  for (int k = 0; k < n; ++k) v_plus[k] = v_minus[k] + v_plus[k];
}

}  // namespace dyngen
