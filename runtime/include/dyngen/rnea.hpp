// Recursive Newton-Euler algorithm: inverse dynamics tau = ID(q, qd, qdd) (RBDA Table 5.1).
#pragma once

#include <span>
#include <vector>

#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

namespace detail {

/// tau = G^T tau_joints: each mimic joint adds S^T f of its body, its multiplier included, to
/// its primary's entry, once the backward pass has written that entry.
template <class S>
void add_mimic_forces(const Model<S>& model, const std::vector<Force<S>>& f, std::span<S> tau) {
  if (model.mimic.empty()) return;
  for (int i = 0; i < model.nbodies; ++i) {
    if (!is_mimic(model, i)) continue;
    TraceHook<S>::enter(i, Pass::Backward);
    S t;
    joint_project(model, i, f[i], &t);
    tau[model.v_index[i]] = tau[model.v_index[i]] + t;
  }
}

/// RNEA's forward pass for body i (below): Xup[i], and the angular velocity w_i (ws.v[i].ang),
/// angular acceleration wd_i (ws.a[i].ang) and classical acceleration ac_i of the body's origin
/// (ws.a[i].lin), from its parent's.
template <class S>
void classical_motion(const Model<S>& model, Workspace<S>& ws, int i, std::span<const S> q,
                      std::span<const S> qd, std::span<const S> qdd, const Motion<S>& a0) {
  const int k = model.v_index[i];
  const int p = model.parent[i];
  const Xform<S>& X = ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
  const Motion<S> vJ = joint_motion(model, i, &qd[k]);
  const Motion<S> aJ = joint_motion(model, i, &qdd[k]);
  Vec3<S>& w = ws.v[i].ang;
  Vec3<S>& wd = ws.a[i].ang;
  Vec3<S>& ac = ws.a[i].lin;
  if (p < 0) {  // the base does not move
    w = vJ.ang;
    wd = aJ.ang;
    ac = mul(X.E, a0.lin) + aJ.lin + cross(w, vJ.lin);
  } else {
    const Vec3<S>& wp = ws.v[p].ang;
    const Vec3<S>& wdp = ws.a[p].ang;
    const Vec3<S> u = mul(X.E, wp);
    w = u + vJ.ang;
    wd = mul(X.E, wdp) + aJ.ang + cross(w, vJ.ang);
    const Vec3<S> acp = ws.a[p].lin + cross(wdp, X.r) + cross(wp, cross(wp, X.r));
    ac = mul(X.E, acp) + aJ.lin + cross(w + u, vJ.lin);
  }
}

/// f = [I wd + w x I w + h x ac; m ac + wd x h + w x (w x h)]: the force on a body of inertia I
/// that moves with w, wd and ac (classical_motion).
template <class S>
Force<S> body_force(const RigidInertia<S>& I, const Vec3<S>& w, const Vec3<S>& wd,
                    const Vec3<S>& ac) {
  return {mul(I.I, wd) + cross(w, mul(I.I, w)) + cross(I.h, ac),
          scale(ac, I.m) + cross(wd, I.h) + cross(w, cross(w, I.h))};
}

}  // namespace detail

/// Inverse dynamics: tau = M(q) qdd + C(q, qd) qd + g(q). q has model.nq entries, the others
/// model.nv; no allocation.
template <class S>
void rnea(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<const S> qd,
          std::span<const S> qdd, std::span<S> tau) {
  const Motion<S> a0 = base_acceleration(model);

  // forward pass with classical accelerations, so that the linear velocity never enters (Craig,
  // "Introduction to Robotics", eqs. 6.45-6.50; Khalil & Dombre, sec. 9.5): w_i, wd_i and the
  // acceleration ac_i of the body's origin, where RBDA's spatial a_i = [wd_i; ac_i - w_i x v_i].
  // With u = E w_p the parent's angular velocity in body axes and [wJ; vJ] = S qd:
  //   w_i = u + wJ,  wd_i = E wd_p + (S qdd)_ang + w_i x wJ,
  //   ac_i = E (ac_p + wd_p x r + w_p x (w_p x r)) + (S qdd)_lin + (w_i + u) x vJ,
  //   f_i = [I wd_i + w_i x I w_i + h x ac_i; m ac_i + wd_i x h + w_i x (w_i x h)],
  // RBDA's I_i a_i + v_i x* I_i v_i with the terms in v_i's linear part cancelled.
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    detail::classical_motion(model, ws, i, q, qd, qdd, a0);
    ws.f[i] = detail::body_force(model.I[i], ws.v[i].ang, ws.a[i].ang, ws.a[i].lin);
  }

  // backward pass: tau_i = S^T f_i (+ armature qdd_i), f_p += Xup^T f_i
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::Backward);
    const int k = model.v_index[i];
    if (!is_mimic(model, i)) joint_project(model, i, ws.f[i], &tau[k]);
    if (!model.armature.empty())
      for (int d = 0; d < joint_nv(model.joint_type[i]); ++d)
        tau[k + d] = tau[k + d] + model.armature[k + d] * qdd[k + d];
    const int p = model.parent[i];
    if (p >= 0) ws.f[p] = ws.f[p] + apply_force_T(ws.Xup[i], ws.f[i]);
  }
  detail::add_mimic_forces(model, ws.f, tau);
}

/// Generalised gravity g(q), what rnea(q, 0, 0) computes: the torques that hold the robot still.
/// At rest a subtree's force is its weight, so only its mass and first moment are carried up,
/// not a body force and its transform per body.
template <class S>
void gravity(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> g) {
  const Motion<S> a0 = base_acceleration(model);

  // forward pass: the base's upward acceleration a_i = E a_p in body axes
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    const int p = model.parent[i];
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    ws.a[i].lin = mul(ws.Xup[i].E, p < 0 ? a0.lin : ws.a[p].lin);
    ws.Ic[i] = model.I[i];
  }

  // backward pass: the subtree's mass m_i and first moment h_i about the body's origin; its
  // weight's force f_i = [h_i x a_i; m_i a_i], g_i = S^T f_i; m_p += m_i, h_p += m_i r + E^T h_i
  // (the first moment moved to the parent's origin, RBDA eq. 2.66)
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::Backward);
    const RigidInertia<S>& Ic = ws.Ic[i];
    const Vec3<S>& a = ws.a[i].lin;
    const Force<S> f{cross(Ic.h, a), scale(a, Ic.m)};
    if (is_mimic(model, i)) ws.f[i] = f;  // added to its primary's entry below
    else joint_project(model, i, f, &g[model.v_index[i]]);
    const int p = model.parent[i];
    if (p < 0) continue;
    const Xform<S>& X = ws.Xup[i];
    ws.Ic[p].m = ws.Ic[p].m + Ic.m;
    ws.Ic[p].h = ws.Ic[p].h + scale(X.r, Ic.m) + mul_T(X.E, Ic.h);
  }
  detail::add_mimic_forces(model, ws.f, g);
}

/// Nonlinear effects h(q, v) = C(q, v) v + g(q) = rnea(q, v, 0): Coriolis, centrifugal and
/// gravity torques.
template <class S>
void nle(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<const S> qd,
         std::span<S> h) {
  rnea<S>(model, ws, q, qd, ws.zero, h);
}

}  // namespace dyngen
