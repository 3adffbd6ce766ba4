// The inverse of the mass matrix by the articulated-body recursion (after Carpentier,
// "Analytical inverse of the joint space inertia matrix", 2018, Pinocchio's computeMinverse):
// ABA at zero velocity and gravity with tau = e_c gives column c of M^-1, and the nv unit
// torques share the articulated inertias, so the passes run once with nv right-hand sides.
#pragma once

#include <cstddef>
#include <span>

#include "dyngen/aba.hpp"
#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

namespace detail {

/// u = e_c - S^T pA_i of a ball joint at body i (first column k) for column c of M^-1: zero
/// outside the subtree's columns
template <class S>
Vec3<S> ball_minv_u(const Model<S>& model, const Workspace<S>& ws, int i, int c) {
  if (c >= ws.subtree_end[i]) return {};
  const int k = model.v_index[i];
  S e[3]{};
  if (c < k + 3) e[c - k] = S(1);
  return ball_u(ws.pA_columns[row_major(model.nv, i, c)], e);
}

/// aba's ball_articulated with tau = e_c at zero velocity and gravity, for each column c of the
/// subtree: pA_p += Xup^T (pA_i + U D^-1 u)
template <class S>
void ball_minv_articulated(const Model<S>& model, Workspace<S>& ws, int i) {
  const int n = model.nv, k = model.v_index[i], p = model.parent[i];
  const ArticulatedInertia<S>& IA = ws.IA[i];
  ws.Dinv_ball[i] = inverse(ball_D(model, IA, k));
  if (p < 0) return;
  for (int c = k; c < ws.subtree_end[i]; ++c) {
    const Vec3<S> y = mul(ws.Dinv_ball[i], ball_minv_u(model, ws, i, c));
    const Force<S> pa = ws.pA_columns[row_major(n, i, c)] + Force<S>{mul(IA.I, y), mul_T(IA.H, y)};
    ws.pA_columns[row_major(n, p, c)] =
        ws.pA_columns[row_major(n, p, c)] + apply_force_T(ws.Xup[i], pa);
  }
  const bool armature = !model.armature.empty();
  ws.IA[p] = ws.IA[p] + apply_inertia_T(ws.Xup[i], downdate_ball(IA, ws.Dinv_ball[i], armature));
}

}  // namespace detail

/// M(q)^-1, row-major nv x nv, both triangles (the upper one computed, the lower copied). The
/// same preconditions as aba: every joint moves some inertia. Needs the workspace's matrix
/// buffers (Workspace::has_matrix_buffers, nv <= Workspace::max_matrix_nv). No allocation.
template <class S>
void minv(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> Minv) {
  const int n = model.nv;
  if (!model.mimic.empty()) {  // no recursion with shared columns: M factorised, as in aba
    crba<S>(model, ws, q, ws.H);
    factor_ltdl<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv);
    ltdl_inverse<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv, ws.Linv, Minv);
    return;
  }
  // per body and column (Workspace::pA_columns), or per row and column of M^-1
  const auto at = [n](int row, int column) { return row_major(n, row, column); };
  // kinematics: Xup_i, IA_i = I_i, pA_i = 0 for every unit torque
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Velocity);
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    ws.IA[i] = articulated(model.I[i]);
    for (int c = model.v_index[i]; c < n; ++c) ws.pA_columns[at(i, c)] = Force<S>{};
  }

  // articulated inertia pass, as in aba with tau = e_c: u_i = e_c - S^T pA_i,
  // pA_p += Xup^T (pA_i + U_i u_i / D_i) for the columns c of the subtree (the others have
  // u_i = 0 and pA_i = 0); below a free joint only its own torques reach the parent
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::ArticulatedInertia);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    const int end = ws.subtree_end[i];
    if (model.joint_type[i] == JointType::Free) {
      if (p < 0) continue;
      for (int d = 0; d < 6; ++d) {
        S e[6]{};
        e[d] = S(1);
        ws.pA_columns[at(p, k + d)] =
            ws.pA_columns[at(p, k + d)] + apply_force_T(ws.Xup[i], joint_force(model, i, e));
      }
      continue;
    }
    if (model.joint_type[i] == JointType::Ball) {
      detail::ball_minv_articulated(model, ws, i);
      continue;
    }
    ws.U[i] = mul(ws.IA[i], joint_column(model, i, 0));
    joint_project(model, i, ws.U[i], &ws.D[i]);
    if (!model.armature.empty()) ws.D[i] = ws.D[i] + model.armature[k];
    ws.Dinv[i] = S(1) / ws.D[i];
    for (int c = k; c < end; ++c) {
      S STpA;
      joint_project(model, i, ws.pA_columns[at(i, c)], &STpA);
      ws.u_columns[at(i, c)] = (c == k ? S(1) : S(0)) - STpA;
    }
    if (p < 0) continue;
    const Force<S>& U = ws.U[i];
    const Force<S> Ud{scale(U.ang, ws.Dinv[i]), scale(U.lin, ws.Dinv[i])};
    for (int c = k; c < end; ++c) {
      const S& u = ws.u_columns[at(i, c)];
      const Force<S> pa = ws.pA_columns[at(i, c)] + Force<S>{scale(Ud.ang, u), scale(Ud.lin, u)};
      ws.pA_columns[at(p, c)] = ws.pA_columns[at(p, c)] + apply_force_T(ws.Xup[i], pa);
    }
    const ArticulatedInertia<S> Ia = downdate(ws.IA[i], U, Ud);
    ws.IA[p] = ws.IA[p] + apply_inertia_T(ws.Xup[i], Ia);
  }

  // acceleration pass for the columns c >= v_index[i] of row i (the upper triangle):
  // a' = Xup a_p, qdd_i = (u_i - U_i^T a') / D_i, a_i = a' + S qdd_i; below a free joint
  // a_i = IA_i^-1 (S e_c - pA_i) and qdd_i = S^T (a_i - a')
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Acceleration);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    const int dofs = joint_nv(model.joint_type[i]);
    for (int c = k; c < n; ++c) {
      const Motion<S> a1 = p < 0 ? Motion<S>{} : apply_motion(ws.Xup[i], ws.a_columns[at(p, c)]);
      if (model.joint_type[i] == JointType::Free) {
        S e[6]{};
        if (c < k + 6) e[c - k] = S(1);
        const Motion<S> a = solve(ws.IA[i], joint_force(model, i, e) - ws.pA_columns[at(i, c)]);
        ws.a_columns[at(i, c)] = a;
        const Motion<S> aJ = a - a1;
        const S column[6] = {aJ.lin.x, aJ.lin.y, aJ.lin.z, aJ.ang.x, aJ.ang.y, aJ.ang.z};
        for (int d = 0; d < dofs; ++d)
          if (c >= k + d) Minv[at(k + d, c)] = column[d];
        continue;
      }
      if (model.joint_type[i] == JointType::Ball) {
        S qdd[3];
        ws.a_columns[at(i, c)] =
            a1 + detail::ball_acceleration(ws, i, detail::ball_minv_u(model, ws, i, c), a1, qdd);
        for (int d = 0; d < dofs; ++d)
          if (c >= k + d) Minv[at(k + d, c)] = qdd[d];
        continue;
      }
      // u_i is zero outside the subtree's columns
      const S u = c < ws.subtree_end[i] ? ws.u_columns[at(i, c)] : S(0);
      const Force<S>& U = ws.U[i];
      const S qdd = (u - (dot(U.ang, a1.ang) + dot(U.lin, a1.lin))) * ws.Dinv[i];
      Minv[at(k, c)] = qdd;
      ws.a_columns[at(i, c)] = a1 + joint_motion(model, i, &qdd);
    }
  }
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < r; ++c) Minv[at(r, c)] = Minv[at(c, r)];
}

}  // namespace dyngen
