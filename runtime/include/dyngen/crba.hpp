// Composite rigid body algorithm: the joint-space mass matrix M(q) (RBDA Table 6.2).
#pragma once

#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// Mass matrix M(q), written full (both triangles), row-major: M[i * nv + j]. Entries of
/// joints on different branches are zero. No allocation.
template <class S>
void crba(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> M) {
  const int n = model.nv;

  // kinematics: Xup_i, and Ic_i = I_i
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Kinematics);
    ws.Xup[i] = joint_transform(model, i, q[model.q_index[i]]);
    ws.Ic[i] = model.I[i];
  }
  for (int k = 0; k < n * n; ++k) M[k] = S{};

  // backward pass: Ic_p += Xup^T Ic_i Xup; F = Ic_i S_i; M_ii = S_i^T F;
  // M_ij = M_ji = S_j^T F with F carried to each ancestor j
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::CompositeInertia);
    const int p = model.parent[i];
    if (p >= 0) ws.Ic[p] = ws.Ic[p] + apply_inertia_T(ws.Xup[i], ws.Ic[i]);
    const int qi = model.q_index[i];
    Force<S> F = mul(ws.Ic[i], joint_motion(model, i, S(1)));
    M[qi * n + qi] = joint_project(model, i, F);
    for (int j = i; model.parent[j] >= 0;) {
      F = apply_force_T(ws.Xup[j], F);
      j = model.parent[j];
      const int qj = model.q_index[j];
      M[qi * n + qj] = joint_project(model, j, F);
      M[qj * n + qi] = M[qi * n + qj];
    }
  }
}

}  // namespace dyngen
