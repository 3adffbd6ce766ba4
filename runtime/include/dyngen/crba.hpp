// Composite rigid body algorithm: the joint-space mass matrix M(q) (RBDA Table 6.2).
#pragma once

#include <cstddef>
#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// Mass matrix M(q), written full (both triangles), row-major: M[i * nv + j]. Entries of
/// joints on different branches are zero. No allocation.
template <class S>
void crba(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> M) {
  const std::size_t n = static_cast<std::size_t>(model.nv);  // n * n overflows int at 46,341

  // kinematics: Xup_i, and Ic_i = I_i
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Kinematics);
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    ws.Ic[i] = model.I[i];
  }
  for (std::size_t k = 0; k < n * n; ++k) M[k] = S{};

  // backward pass: Ic_p += Xup^T Ic_i Xup; for each column d of S_i: F = Ic_i S_id,
  // M_ii[d] = S_i^T F; M_ij[d] = M_ji^T[d] = S_j^T F with F carried to each ancestor j
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::CompositeInertia);
    const int p = model.parent[i];
    if (p >= 0) ws.Ic[p] = ws.Ic[p] + apply_inertia_T(ws.Xup[i], ws.Ic[i]);
    for (int d = 0; d < joint_nv(model.joint_type[i]); ++d) {
      TraceHook<S>::enter(i, Pass::CompositeInertia);  // again after a column was carried up
      const std::size_t row = static_cast<std::size_t>(model.v_index[i] + d);
      Force<S> F = mul(ws.Ic[i], joint_column(model, i, d));
      joint_project(model, i, F, &M[row * n + model.v_index[i]]);
      for (int j = i; model.parent[j] >= 0;) {
        TraceHook<S>::enter(model.parent[j], Pass::Column);
        F = apply_force_T(ws.Xup[j], F);
        j = model.parent[j];
        const std::size_t vj = static_cast<std::size_t>(model.v_index[j]);
        joint_project(model, j, F, &M[row * n + vj]);
        for (int e = 0; e < joint_nv(model.joint_type[j]); ++e)
          M[(vj + e) * n + row] = M[row * n + vj + e];
      }
    }
  }
}

}  // namespace dyngen
