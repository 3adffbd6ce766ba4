// Recursive Newton-Euler algorithm: inverse dynamics tau = ID(q, qd, qdd) (RBDA Table 5.1).
#pragma once

#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// Inverse dynamics: tau = M(q) qdd + C(q, qd) qd + g(q). q has model.nq entries, the others
/// model.nv; no allocation.
template <class S>
void rnea(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<const S> qd,
          std::span<const S> qdd, std::span<S> tau) {
  const Motion<S> a0 = base_acceleration(model);

  // forward pass: v_i = Xup v_p + S qd_i, a_i = Xup a_p + S qdd_i + v_i x S qd_i,
  // f_i = I_i a_i + v_i x* I_i v_i
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    const Motion<S> vJ = joint_motion(model, i, &qd[k]);
    const Motion<S> aJ = joint_motion(model, i, &qdd[k]);
    if (p < 0) {
      ws.v[i] = vJ;  // the base does not move, and vJ x vJ = 0
      ws.a[i] = apply_motion(ws.Xup[i], a0) + aJ;
    } else {
      ws.v[i] = apply_motion(ws.Xup[i], ws.v[p]) + vJ;
      ws.a[i] = apply_motion(ws.Xup[i], ws.a[p]) + aJ + cross_motion(ws.v[i], vJ);
    }
    ws.f[i] = mul(model.I[i], ws.a[i]) + cross_force(ws.v[i], mul(model.I[i], ws.v[i]));
  }

  // backward pass: tau_i = S^T f_i, f_p += Xup^T f_i
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::Backward);
    joint_project(model, i, ws.f[i], &tau[model.v_index[i]]);
    const int p = model.parent[i];
    if (p >= 0) ws.f[p] = ws.f[p] + apply_force_T(ws.Xup[i], ws.f[i]);
  }
}

/// Generalised gravity g(q) = rnea(q, 0, 0): the torques that hold the robot still.
template <class S>
void gravity(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> g) {
  rnea<S>(model, ws, q, ws.zero, ws.zero, g);
}

/// Nonlinear effects h(q, v) = C(q, v) v + g(q) = rnea(q, v, 0): Coriolis, centrifugal and
/// gravity torques.
template <class S>
void nle(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<const S> qd,
         std::span<S> h) {
  rnea<S>(model, ws, q, qd, ws.zero, h);
}

}  // namespace dyngen
