// Partial derivatives of contact_dynamics (constrained.hpp). Differentiating its KKT system
//   M qdd - J^T lam = tau - h,   J qdd = -(Jdot v + kd J v + kp e)
// at the solution, with qdd and lam held, gives for x in (q, v):
//   M dqdd - J^T dlam = R1 = -d rnea(q, v, qdd) / dx + d(J^T lam) / dx
//   J dqdd            = R2 = -d(J a + Jdot v + kd J v + kp e) / dx at a = qdd
// (for tau: R1 = 1, R2 = 0), the same system as the dynamics' own, solved column by column by
// the same Schur complement (kernels::constrained_columns: compact loops where the unrolled
// columns would fill the instruction cache, over the rows and columns where W can be non-zero):
// y = L^-T R1, dlam = T (R2 - W D^-1 y), dqdd = L^-1 D^-1 (y + W^T dlam), with T the map from
// the right side to lam of contact_dynamics' proximal iterations (A^-1 to (mu / s)^3). For tau
// the columns are the inverse's own blocks, in closed form (tau_columns: half the work of the
// columns, the product being symmetric). d rnea / dx comes from rnea_derivatives; the
// constraints' terms from the motion of each column s_k of the constraint's path in base
// coordinates (after Carpentier & Mansard, RSS 2018, sec. III): moving q_k turns everything
// downstream of s_k's joint about s_k,
//   dv_b = s_k x (v_b - v_p),  da_b = s_k x (a_b - a_p) - (s_k x v_p) x (v_b - v_p),
//   ds_j = s_k x s_j,  dp = s_k.lin + s_k.ang x p,
// and v_k adds dv_b = s_k, da_b = v_k' x s_k + s_k x (v_b - v_p) (p: the joint's parent body,
// k': its own body, b: the constraint's, p the frame's origin).
#pragma once

#include <span>
#include <string_view>

#include "dyngen/constrained.hpp"
#include "dyngen/kernels.hpp"
#include "dyngen/rnea_derivatives.hpp"

namespace dyngen {

namespace detail {

/// The classical acceleration of a frame's origin p on body b (linear, then angular, with kd
/// times its velocity added) varied by dv, da of the body's motion and dp of p.
template <class S>
Motion<S> vary_frame_acceleration(const Workspace<S>& ws, int b, const Vec3<S>& p,
                                  const Motion<S>& dv, const Motion<S>& da, const Vec3<S>& dp,
                                  const S& kd) {
  const Motion<S>& v = ws.v[b];
  const Motion<S>& a = ws.a[b];
  const Vec3<S> vp = v.lin + cross(v.ang, p);
  const Vec3<S> dvp = dv.lin + cross(dv.ang, p) + cross(v.ang, dp);
  // a.lin + a.ang x p + w x (v.lin + w x p)
  const Vec3<S> dap =
      da.lin + cross(da.ang, p) + cross(a.ang, dp) + cross(dv.ang, vp) + cross(v.ang, dvp);
  return {da.ang + scale(dv.ang, kd), dap + scale(dvp, kd)};
}

/// 1/2 vee(D - D^T) for D = [w] R (side A turned by w) or -R [w] (side B): the variation of
/// position_error's rotation part, R = R_A R_B^T.
template <class S>
Vec3<S> vary_rotation_error(const Mat3<S>& R, const Vec3<S>& w, bool side_a) {
  const Vec3<S> c0{R.xx, R.yx, R.zx}, c1{R.xy, R.yy, R.zy}, c2{R.xz, R.yz, R.zz};
  Mat3<S> D;
  if (side_a) {  // columns w x R_j
    const Vec3<S> d0 = cross(w, c0), d1 = cross(w, c1), d2 = cross(w, c2);
    D = {d0.x, d1.x, d2.x, d0.y, d1.y, d2.y, d0.z, d1.z, d2.z};
  } else {  // -R [w] = ([w] R^T)^T: rows w x (row j of R)
    const Vec3<S> r0{R.xx, R.xy, R.xz}, r1{R.yx, R.yy, R.yz}, r2{R.zx, R.zy, R.zz};
    const Vec3<S> d0 = cross(w, r0), d1 = cross(w, r1), d2 = cross(w, r2);
    D = {d0.x, d0.y, d0.z, d1.x, d1.y, d1.z, d2.x, d2.y, d2.z};
  }
  return {(D.zy - D.yz) / S(2), (D.xz - D.zx) / S(2), (D.yx - D.xy) / S(2)};
}

/// One side of a constraint (frame X on body b, sign +1 for A, -1 for B) adds its terms at
/// fixed qdd and lam (rows r0.., `rows` of them) to R1q = d(J^T lam)/dq and subtracts them from
/// R2q, R2v (nc x nv); `positioned`: kp acts on its position error (a loop, an anchored
/// contact). After body_bias_accelerations at qdd.
template <class S>
void add_constraint_side(const Model<S>& model, const Workspace<S>& ws, const Constraint<S>& k,
                         int b, const Xform<S>& X, bool side_a, bool positioned, int r0,
                         std::span<const S> lam, const Mat3<S>& R, std::span<S> R1q,
                         std::span<S> R2q, std::span<S> R2v) {
  const int n = model.nv, rows = constraint_rows(k);
  const ConstraintSettings<S>& cs = model.constraint_settings;
  const S sign = side_a ? S(1) : S(-1);
  const Vec3<S>& p = X.r;
  const Vec3<S> f_lin{lam[r0], lam[r0 + 1], lam[r0 + 2]};
  const Vec3<S> f_ang = rows == 6 ? Vec3<S>{lam[r0 + 3], lam[r0 + 4], lam[r0 + 5]} : Vec3<S>{};
  const Force<S> f{cross(p, f_lin) + f_ang, f_lin};  // lam as a force at the base origin
  const Motion<S>& vb = ws.v[b];
  const Motion<S>& ab = ws.a[b];
  for (int jk = b; jk >= 0; jk = model.parent[jk]) {
    TraceHook<S>::enter(jk, Pass::Constraints);
    const int par = model.parent[jk];
    const Motion<S> vp = par < 0 ? Motion<S>{} : ws.v[par], ap = par < 0 ? Motion<S>{} : ws.a[par];
    for (int d = 0; d < joint_nv(model.joint_type[jk]); ++d) {
      const int ck = model.v_index[jk] + d;
      const Motion<S> sk = apply_motion_inv(ws.X0[jk], joint_column(model, jk, d));
      const Vec3<S> dp = sk.lin + cross(sk.ang, p);
      // d(J^T lam)_j / dq_k = sign s_j . ((dp x f_lin, 0) - [j downstream of k] s_k x* f)
      const Force<S> moved{cross(dp, f_lin), Vec3<S>{}};
      const Force<S> turned = moved - cross_force(sk, f);
      bool downstream = true;
      for (int jj = b; jj >= 0; jj = model.parent[jj]) {
        for (int e = 0; e < joint_nv(model.joint_type[jj]); ++e) {
          const Motion<S> sj = apply_motion_inv(ws.X0[jj], joint_column(model, jj, e));
          const S term = downstream ? inner(turned, sj) : dot(sj.ang, moved.ang);
          S& entry = R1q[row_major(n, model.v_index[jj] + e, ck)];
          entry = entry + sign * term;
        }
        if (jj == jk) downstream = false;
      }
      const Motion<S> dvq = cross_motion(sk, vb - vp);
      const Motion<S> daq = cross_motion(sk, ab - ap) - cross_motion(cross_motion(sk, vp), vb - vp);
      const Motion<S> dav = cross_motion(ws.v[jk], sk) + cross_motion(sk, vb - vp);
      const Motion<S> gq = vary_frame_acceleration(ws, b, p, dvq, daq, dp, cs.kd);
      const Motion<S> gv = vary_frame_acceleration(ws, b, p, sk, dav, Vec3<S>{}, cs.kd);
      Motion<S> eq{};  // the position error, kp e
      if (positioned) eq = {vary_rotation_error(R, sk.ang, side_a), scale(dp, sign)};
      const S dq[6] = {gq.lin.x, gq.lin.y, gq.lin.z, gq.ang.x, gq.ang.y, gq.ang.z};
      const S dv[6] = {gv.lin.x, gv.lin.y, gv.lin.z, gv.ang.x, gv.ang.y, gv.ang.z};
      const S de[6] = {eq.lin.x, eq.lin.y, eq.lin.z, eq.ang.x, eq.ang.y, eq.ang.z};
      for (int r = 0; r < rows; ++r) {
        S& q_entry = R2q[row_major(n, r0 + r, ck)];
        S& v_entry = R2v[row_major(n, r0 + r, ck)];
        q_entry = positioned ? q_entry - sign * dq[r] - cs.kp * de[r] : q_entry - sign * dq[r];
        v_entry = v_entry - sign * dv[r];
      }
    }
  }
}

/// ws.lam_map = T, the map from right side to lam of proximal_solve's iterations: with B =
/// (A + mu)^-1 and A B = 1 - mu B, lam_{k+1} = lam_k + B (r - A lam_k) = B r + mu B lam_k, so
/// T_1 = B and T_{k+1} = B + mu B T_k (B + mu B^2 + mu^2 B^3 for 3). B's columns by its
/// factor; each T_{k+1}, a polynomial in the symmetric B, is symmetric: column j's rows up to j,
/// mirrored into row j (whose columns before j are done, and T_k's column j is not yet read).
template <class S>
void proximal_map(const Model<S>& model, Workspace<S>& ws) {
  const int m = model.nc;
  const S mu = proximal_damping(model, ws);
  for (int j = 0; j < m; ++j) {  // B's column j
    S* x = ws.lam_step.data();
    for (int i = 0; i < m; ++i) x[i] = S(i == j ? 1 : 0);
    damped_solve(m, ws, x);
    for (int i = 0; i < m; ++i)
      ws.A_inverse[row_major(m, i, j)] = ws.lam_map[row_major(m, i, j)] = x[i];
  }
  for (int it = 1; it < proximal_iterations; ++it)
    for (int j = 0; j < m; ++j) {
      S* x = ws.lam_step.data();
      for (int i = 0; i <= j; ++i) {
        S sum{};
        for (int k = 0; k < m; ++k)
          sum = sum + ws.A_inverse[row_major(m, i, k)] * ws.lam_map[row_major(m, k, j)];
        x[i] = ws.A_inverse[row_major(m, i, j)] + mu * sum;
      }
      for (int i = 0; i <= j; ++i)
        ws.lam_map[row_major(m, i, j)] = ws.lam_map[row_major(m, j, i)] = x[i];
    }
}

/// The columns of tau (R1 = 1, R2 = 0) in closed form: with Y = J M^-1 (Y^T's columns L^-1
/// D^-1 W^T, after ltdl_finish_solve), dlam/dtau = -T Y and dqdd/dtau = M^-1 - Y^T T Y
/// (kernels::inverse_blocks; symmetric, as T is).
template <class S>
void tau_columns(const Model<S>& model, Workspace<S>& ws, std::span<S> dqdd_dtau,
                 std::span<S> dlam_dtau) {
  const int n = model.nv, m = model.nc;
  const int* parent = ws.column_parent.data();
  ltdl_inverse<S>(n, parent, ws.H, ws.column_Dinv, ws.Linv, ws.dtau_dq);  // M^-1
  TraceHook<S>::enter(-1, Pass::Product);
  S* Y = ws.lam_columns.data();
  for (int s = 0; s < m; ++s) {
    for (int k = 0; k < n; ++k) Y[row_major(n, s, k)] = ws.Wt[row_major(n, s, k)];
    ltdl_finish_solve<S>(n, parent, ws.H, ws.column_Dinv, &Y[row_major(n, s, 0)]);
  }
  const int ints[] = {n, m};
  const std::string_view names[] = {"T", "Y", "Minv", "dqdd", "dlam"};
  const std::span<const S> inputs[] = {ws.lam_map, ws.lam_columns, ws.dtau_dq};
  const std::span<S> outputs[] = {dqdd_dtau, dlam_dtau};
  run_kernel<S>({"inverse_blocks", ints, {}, inputs, outputs, names}, [&](auto in, auto out) {
    kernels::inverse_blocks(n, m, in[0].data(), in[1].data(), in[2].data(), out[0].data(),
                            out[1].data());
  });
}

/// The columns of the system above, in place: on entry dqdd holds R1 and dlam R2, on return the
/// derivatives (kernels::constrained_columns).
template <class S>
void constrained_columns(const Model<S>& model, Workspace<S>& ws, std::span<S> dqdd,
                         std::span<S> dlam) {
  TraceHook<S>::enter(-1, Pass::Product);
  const int n = model.nv, m = model.nc;
  const int ints[] = {n, m};
  const std::span<const int> tables[] = {ws.column_parent, ws.w_begin, ws.w_columns,
                                         ws.w_rows_begin, ws.w_rows};
  const std::string_view names[] = {"parent", "w_begin", "w_columns", "w_rows_begin",
                                    "w_rows", "L", "Dinv", "Wt", "T", "R1", "R2", "dqdd",
                                    "dlam", "r"};
  const std::span<const S> inputs[] = {ws.H, ws.column_Dinv, ws.Wt, ws.lam_map, dqdd, dlam};
  const std::span<S> outputs[] = {dqdd, dlam, ws.lam_columns};
  run_kernel<S>({"constrained_columns", ints, tables, inputs, outputs, names},
                [&](auto in, auto out) {
                  kernels::constrained_columns(n, m, ws.column_parent.data(), ws.w_begin.data(),
                                               ws.w_columns.data(), ws.w_rows_begin.data(),
                                               ws.w_rows.data(), in[0].data(),
                                               in[1].data(), in[2].data(), in[3].data(),
                                               in[4].data(), in[5].data(), out[0].data(),
                                               out[1].data(), out[2].data());
                });
}

}  // namespace detail

/// d qdd / d(q, v, tau) and d lam / d(q, v, tau) of contact_dynamics(q, v, tau): nv x nv and
/// nc x nv, row-major (dqdd_dq[i * nv + j] = d qdd_i / dq_j, dlam_dq[r * nv + j] = d lam_r /
/// dq_j); the columns of free and ball joints are tangent directions, as in rnea_derivatives.
/// Redundant constraints are differentiated through the damped solve (T), exact in the limit
/// of independent rows. With `anchors`, those of contact_dynamics with them (the contacts'
/// position errors under kp). Needs the workspace's matrix buffers; no allocation.
template <class S>
void contact_dynamics_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                                  std::span<const S> v, std::span<const S> tau,
                                  std::span<S> dqdd_dq, std::span<S> dqdd_dv,
                                  std::span<S> dqdd_dtau, std::span<S> dlam_dq,
                                  std::span<S> dlam_dv, std::span<S> dlam_dtau,
                                  std::span<const S> anchors = {}) {
  contact_dynamics<S>(model, ws, q, v, tau, ws.constrained_qdd, ws.lam, anchors);
  TraceHook<S>::enter(-1, Pass::Constraints);
  detail::proximal_map(model, ws);
  rnea_derivatives<S>(model, ws, q, v, ws.constrained_qdd, ws.dtau_dq, ws.dtau_dv);
  detail::body_bias_accelerations<S>(model, ws, q, v, ws.constrained_qdd);
  TraceHook<S>::enter(-1, Pass::Constraints);
  for (std::size_t e = 0; e < dqdd_dq.size(); ++e) dqdd_dq[e] = -ws.dtau_dq[e];
  for (std::size_t e = 0; e < dqdd_dv.size(); ++e) dqdd_dv[e] = -ws.dtau_dv[e];
  for (std::size_t e = 0; e < dlam_dq.size(); ++e) dlam_dq[e] = S(0), dlam_dv[e] = S(0);
  int r0 = 0;
  for (const Constraint<S>& k : model.constraints) {
    TraceHook<S>::enter(k.body_a, Pass::Constraints);
    const auto [XA, XB] =
        detail::constraint_frames(ws, k, anchors.empty() ? nullptr : &anchors[r0]);
    const Mat3<S> R = mul(transpose(XA.E), XB.E);  // R_A R_B^T, as position_error
    const bool positioned = detail::positioned(k, anchors);
    if (k.body_a >= 0)
      detail::add_constraint_side<S>(model, ws, k, k.body_a, XA, true, positioned, r0, ws.lam, R,
                                     dqdd_dq, dlam_dq, dlam_dv);
    if (k.body_b >= 0)
      detail::add_constraint_side<S>(model, ws, k, k.body_b, XB, false, positioned, r0, ws.lam,
                                     R, dqdd_dq, dlam_dq, dlam_dv);
    r0 += constraint_rows(k);
  }
  detail::constrained_columns<S>(model, ws, dqdd_dq, dlam_dq);
  detail::constrained_columns<S>(model, ws, dqdd_dv, dlam_dv);
  detail::tau_columns<S>(model, ws, dqdd_dtau, dlam_dtau);
}

}  // namespace dyngen
