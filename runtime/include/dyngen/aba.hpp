// Articulated-body algorithm: forward dynamics qdd = FD(q, qd, tau) (RBDA Table 7.1).
#pragma once

#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// Forward dynamics: qdd = M(q)^-1 (tau - C(q, qd) qd - g(q)). Requires every joint to move
/// some inertia (D_i > 0, and a positive definite articulated inertia below a free joint); the
/// algorithm has no branch on values and divides by D_i. q has model.nq entries, the others
/// model.nv; no allocation.
template <class S>
void aba(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<const S> qd,
         std::span<const S> tau, std::span<S> qdd) {
  const Motion<S> a0 = base_acceleration(model);

  // velocity pass: v_i = Xup v_p + vJ, c_i = v_i x vJ, IA_i = I_i, pA_i = v_i x* I_i v_i
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Velocity);
    const int p = model.parent[i];
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    const Motion<S> vJ = joint_motion(model, i, &qd[model.v_index[i]]);
    if (p < 0) {
      ws.v[i] = vJ;
      ws.c[i] = Motion<S>{};  // vJ x vJ = 0
    } else {
      ws.v[i] = apply_motion(ws.Xup[i], ws.v[p]) + vJ;
      ws.c[i] = cross_motion(ws.v[i], vJ);
    }
    ws.IA[i] = articulated(model.I[i]);
    ws.pA[i] = cross_force(ws.v[i], mul(model.I[i], ws.v[i]));
  }

  // articulated inertia pass: U_i = IA_i S_i, D_i = S_i^T U_i, u_i = tau_i - S_i^T pA_i;
  // Ia = IA_i - U_i U_i^T / D_i, pa = pA_i + Ia c_i + U_i u_i / D_i, with one division per
  // joint (1 / D_i, reused by the acceleration pass) instead of seven,
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
    ws.U[i] = mul(ws.IA[i], joint_column(model, i, 0));
    joint_project(model, i, ws.U[i], &ws.D[i]);
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
    const Motion<S> a1 = p < 0 ? apply_motion(ws.Xup[i], a0)
                               : apply_motion(ws.Xup[i], ws.a[p]) + ws.c[i];
    if (model.joint_type[i] == JointType::Free) {
      ws.a[i] = solve(ws.IA[i], joint_force(model, i, &tau[k]) - ws.pA[i]);
      const Motion<S> aJ = ws.a[i] - a1;
      qdd[k] = aJ.lin.x, qdd[k + 1] = aJ.lin.y, qdd[k + 2] = aJ.lin.z;
      qdd[k + 3] = aJ.ang.x, qdd[k + 4] = aJ.ang.y, qdd[k + 5] = aJ.ang.z;
      continue;
    }
    const Force<S>& U = ws.U[i];
    qdd[k] = (ws.u[i] - (dot(U.ang, a1.ang) + dot(U.lin, a1.lin))) * ws.Dinv[i];
    ws.a[i] = a1 + joint_motion(model, i, &qdd[k]);
  }
}

}  // namespace dyngen
