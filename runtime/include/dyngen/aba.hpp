// Articulated-body algorithm: forward dynamics qdd = FD(q, qd, tau) (RBDA Table 7.1).
#pragma once

#include <span>

#include "dyngen/crba.hpp"
#include "dyngen/joint.hpp"
#include "dyngen/rnea.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

namespace detail {

/// u = tau - S^T pA of a ball joint (S = [1; 0]); recomputed where needed, since pA_i is final
/// once the articulated inertia pass has left body i.
template <class S>
Vec3<S> ball_u(const Force<S>& pA, const S* tau) {
  return Vec3<S>{tau[0], tau[1], tau[2]} - pA.ang;
}

/// D = S^T IA S (+ the armature) of a ball joint whose first column is k: IA's angular block
template <class S>
Sym3<S> ball_D(const Model<S>& model, const ArticulatedInertia<S>& IA, int k) {
  if (model.armature.empty()) return IA.I;
  return IA.I + Sym3<S>{model.armature[k], model.armature[k + 1], model.armature[k + 2]};
}

/// The articulated inertia pass at a ball joint, whose three columns take IA's angular ones:
/// U = [I; H^T], D = I (+ the armature), Ia = IA - U D^-1 U^T, pa = pA + Ia c + U D^-1 u.
template <class S>
void ball_articulated(const Model<S>& model, Workspace<S>& ws, std::span<const S> tau, int i) {
  const int k = model.v_index[i];
  const int p = model.parent[i];
  const ArticulatedInertia<S>& IA = ws.IA[i];
  ws.Dinv_ball[i] = inverse(ball_D(model, IA, k));
  if (p < 0) return;
  const ArticulatedInertia<S> Ia = downdate_ball(IA, ws.Dinv_ball[i], !model.armature.empty());
  const Vec3<S> y = mul(ws.Dinv_ball[i], ball_u(ws.pA[i], &tau[k]));
  const Force<S> pa = ws.pA[i] + mul(Ia, ws.c[i]) + Force<S>{mul(IA.I, y), mul_T(IA.H, y)};
  ws.IA[p] = ws.IA[p] + apply_inertia_T(ws.Xup[i], Ia);
  ws.pA[p] = ws.pA[p] + apply_force_T(ws.Xup[i], pa);
}

/// qdd = D^-1 (u - U^T a') at a ball joint, with U^T a' = I a'_ang + H a'_lin; returns S qdd.
template <class S>
Motion<S> ball_acceleration(const Workspace<S>& ws, int i, const Vec3<S>& u, const Motion<S>& a1,
                            S* qdd) {
  const ArticulatedInertia<S>& IA = ws.IA[i];
  const Vec3<S> w = mul(ws.Dinv_ball[i], u - (mul(IA.I, a1.ang) + mul(IA.H, a1.lin)));
  qdd[0] = w.x, qdd[1] = w.y, qdd[2] = w.z;
  return {w, {}};
}

/// qdd = M^-1 (tau - h) by factorising CRBA's M: the forward dynamics of a robot with mimic
/// joints, for which ABA's recursion does not hold (a joint shares its primary's column), as in
/// Pinocchio 3. Needs the workspace's matrix buffers.
template <class S>
void forward_dynamics_by_mass_matrix(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                                     std::span<const S> qd, std::span<const S> tau,
                                     std::span<S> qdd) {
  const int n = model.nv;
  crba<S>(model, ws, q, ws.H);
  factor_ltdl<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv);
  nle<S>(model, ws, q, qd, ws.h);
  TraceHook<S>::enter(-1, Pass::Product);
  for (int k = 0; k < n; ++k) qdd[k] = tau[k] - ws.h[k];
  ltdl_solve<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv, qdd);
}

}  // namespace detail

/// Forward dynamics: qdd = M(q)^-1 (tau - C(q, qd) qd - g(q)). Requires every joint to move
/// some inertia (D_i > 0, and a positive definite articulated inertia below a free joint, and
/// its angular block below a ball joint); the
/// algorithm has no branch on values and divides by D_i. q has model.nq entries, the others
/// model.nv; no allocation.
template <class S>
void aba(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<const S> qd,
         std::span<const S> tau, std::span<S> qdd) {
  if (!model.mimic.empty()) return detail::forward_dynamics_by_mass_matrix(model, ws, q, qd, tau, qdd);
  const Motion<S> a0 = base_acceleration(model);

  // velocity pass in classical accelerations (rnea.hpp): a_i = [wd_i; ac_i], the acceleration of
  // the body's origin, so that a_i = Xup a_p + c_i + S qdd_i and f_i = I_i a_i + pA_i hold with
  // no linear velocity: with u = E w_p and [wJ; vJ] = S qd, w_i = u + wJ,
  // c_i = [w_i x wJ; E (w_p x (w_p x r)) + (w_i + u) x vJ], pA_i = [w_i x I w_i; w_i x (w_i x h)]
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Velocity);
    const int p = model.parent[i];
    const Xform<S>& X = ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    const Motion<S> vJ = joint_motion(model, i, &qd[model.v_index[i]]);
    Vec3<S>& w = ws.v[i].ang;
    if (p < 0) {  // the base does not move
      w = vJ.ang;
      ws.c[i] = {{}, cross(w, vJ.lin)};
    } else {
      const Vec3<S>& wp = ws.v[p].ang;
      const Vec3<S> u = mul(X.E, wp);
      w = u + vJ.ang;
      ws.c[i] = {cross(w, vJ.ang), mul(X.E, cross(wp, cross(wp, X.r))) + cross(w + u, vJ.lin)};
    }
    const RigidInertia<S>& I = model.I[i];
    ws.IA[i] = articulated(I);
    ws.pA[i] = {cross(w, mul(I.I, w)), cross(w, cross(w, I.h))};
  }

  // articulated inertia pass: U_i = IA_i S_i, D_i = S_i^T U_i (+ the armature),
  // u_i = tau_i - S_i^T pA_i; Ia = IA_i - U_i U_i^T / D_i, pa = pA_i + Ia c_i + U_i u_i / D_i,
  // with one division per joint (1 / D_i, reused by the acceleration pass) instead of seven,
  // IA_p += Xup^T Ia Xup, pA_p += Xup^T pa
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::ArticulatedInertia);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    if (model.joint_type[i] == JointType::Free) {
      // S spans every motion, so Ia = 0 and pa = S tau: the parent feels only the joint force
      if (p >= 0) ws.pA[p] = ws.pA[p] + apply_force_T(ws.Xup[i], joint_force(model, i, &tau[k]));
      continue;
    }
    if (model.joint_type[i] == JointType::Ball) {
      detail::ball_articulated(model, ws, tau, i);
      continue;
    }
    ws.U[i] = mul(ws.IA[i], joint_column(model, i, 0));
    joint_project(model, i, ws.U[i], &ws.D[i]);
    if (!model.armature.empty()) ws.D[i] = ws.D[i] + model.armature[k];
    ws.Dinv[i] = S(1) / ws.D[i];
    S STpA;
    joint_project(model, i, ws.pA[i], &STpA);
    ws.u[i] = tau[k] - STpA;
    if (p < 0) continue;
    const Force<S>& U = ws.U[i];
    const Force<S> Ud{scale(U.ang, ws.Dinv[i]), scale(U.lin, ws.Dinv[i])};
    const ArticulatedInertia<S> Ia = downdate(ws.IA[i], U, Ud);
    const S& u = ws.u[i];
    const Force<S> pa = ws.pA[i] + mul(Ia, ws.c[i]) +
                        Force<S>{scale(Ud.ang, u), scale(Ud.lin, u)};
    ws.IA[p] = ws.IA[p] + apply_inertia_T(ws.Xup[i], Ia);
    ws.pA[p] = ws.pA[p] + apply_force_T(ws.Xup[i], pa);
  }

  // acceleration pass: a' = Xup a_p + c_i, qdd_i = (u_i - U_i^T a') / D_i, a_i = a' + S qdd_i;
  // below a free joint a_i = IA_i^-1 (S tau_i - pA_i) and qdd_i = S^T (a_i - a') (the
  // floating base of RBDA sec. 9.3)
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Acceleration);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    const Motion<S> a1 = apply_motion(ws.Xup[i], p < 0 ? a0 : ws.a[p]) + ws.c[i];
    if (model.joint_type[i] == JointType::Free) {
      ws.a[i] = solve(ws.IA[i], joint_force(model, i, &tau[k]) - ws.pA[i]);
      const Motion<S> aJ = ws.a[i] - a1;
      qdd[k] = aJ.lin.x, qdd[k + 1] = aJ.lin.y, qdd[k + 2] = aJ.lin.z;
      qdd[k + 3] = aJ.ang.x, qdd[k + 4] = aJ.ang.y, qdd[k + 5] = aJ.ang.z;
      continue;
    }
    if (model.joint_type[i] == JointType::Ball) {
      const Vec3<S> u = detail::ball_u(ws.pA[i], &tau[k]);
      ws.a[i] = a1 + detail::ball_acceleration(ws, i, u, a1, &qdd[k]);
      continue;
    }
    const Force<S>& U = ws.U[i];
    qdd[k] = (ws.u[i] - (dot(U.ang, a1.ang) + dot(U.lin, a1.lin))) * ws.Dinv[i];
    ws.a[i] = a1 + joint_motion(model, i, &qdd[k]);
  }
}

}  // namespace dyngen
