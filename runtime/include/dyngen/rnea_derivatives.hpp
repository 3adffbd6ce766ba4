// Partial derivatives of inverse dynamics, d tau / d q and d tau / d v, analytically in base
// coordinates (after Carpentier & Mansard, "Analytical derivatives of rigid body dynamics
// algorithms", RSS 2018, with the inertia terms gathered into one variation per subtree).
//
// In base coordinates a change of q_j along its joint column s_j moves the whole subtree of
// joint j rigidly: every motion m of it changes by s_j x m, every force f by s_j x* f, every
// inertia I by s_j x* I - I s_j x. What does not move rigidly is the velocity and acceleration
// handed down from j's parent body p (v_p, a_p):
//   dv_k/dq_j = s_j x v_k + dv_j,              dv_j    = v_p x s_j
//   da_k/dq_j = s_j x a_k + alpha_j + dv_j x v_k, alpha_j = a_p x s_j + v_p x dv_j
//   da_k/dv_j = beta_j + s_j x v_k,            beta_j  = (v_p + v_j) x s_j
// for k in the subtree of j. A body's force f = I a + v x* I v then changes by its rigid part
// plus I delta_a + B delta_v (spatial.hpp's InertiaVariation B), and summed over a subtree:
//   d tau_i / dq_j = S_i^T (Ic_i alpha_j + Bc_i dv_j)               i in the subtree of j
//                  = S_i^T (Ic_j alpha_j + Bc_j dv_j + s_j x* F_j)  i an ancestor of j
//   d tau_i / dv_j = S_i^T (Ic_i beta_j + Bc_i s_j)                 i in the subtree of j
//                  = S_i^T (Ic_j beta_j + Bc_j s_j)                 i an ancestor of j
// with Ic, Bc and F the composite inertia, variation and force of a subtree; the rotation of
// S_i itself cancels against the rigid part of F_i ((s x S)^T F + S^T (s x* F) = 0).
#pragma once

#include <cstddef>
#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/kernels.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// d tau / dq and d tau / dv of rnea(q, v, a), row-major nv x nv: dtau_dq[i * nv + j] =
/// d tau_i / dq_j. The columns of a free joint are its tangent directions: q moved to q (+) d,
/// the body's pose M times exp(d) with d = (linear, angular) in the body's own frame, the
/// order of its v. Entries of joints on different branches are zero. No allocation.
template <class S>
void rnea_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<const S> qd, std::span<const S> qdd, std::span<S> dtau_dq,
                      std::span<S> dtau_dv) {
  const std::size_t n = static_cast<std::size_t>(model.nv);
  const Motion<S> a0 = base_acceleration(model);

  // forward pass, in base coordinates: X0_i, S_i, v_i = v_p + S_i qd_i,
  // a_i = a_p + S_i qdd_i + v_i x S_i qd_i, and each body's inertia Ic_i = X0^T I_i X0,
  // variation Bc_i and force F_i = I a + v x* I v, to be summed over subtrees below
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    ws.X0[i] = p < 0 ? ws.Xup[i] : compose(ws.Xup[i], ws.X0[p]);
    const Motion<S> vp = p < 0 ? Motion<S>{} : ws.ov[p];
    const Motion<S> ap = p < 0 ? a0 : ws.oa[p];
    const int dofs = joint_nv(model.joint_type[i]);
    Motion<S> vJ, aJ;
    for (int d = 0; d < dofs; ++d) {
      ws.s[k + d] = apply_motion_inv(ws.X0[i], joint_column(model, i, d));
      vJ = vJ + scale(ws.s[k + d], qd[k + d]);
      aJ = aJ + scale(ws.s[k + d], qdd[k + d]);
    }
    ws.ov[i] = vp + vJ;
    ws.oa[i] = ap + aJ + cross_motion(ws.ov[i], vJ);
    for (int d = 0; d < dofs; ++d) {
      const Motion<S>& s = ws.s[k + d];
      ws.dv[k + d] = cross_motion(vp, s);
      ws.alpha[k + d] = cross_motion(ap, s) + cross_motion(vp, ws.dv[k + d]);
      // for a one-column joint v_i x s = v_p x s, since s x s = 0
      ws.beta[k + d] = dofs == 1 ? ws.dv[k + d] + ws.dv[k + d] : cross_motion(vp + ws.ov[i], s);
    }
    ws.oIc[i] = apply_inertia_T(ws.X0[i], model.I[i]);
    ws.oBc[i] = variation(ws.oIc[i], ws.ov[i]);
    ws.oF[i] = mul(ws.oIc[i], ws.oa[i]) + cross_force(ws.ov[i], ws.oBc[i].p);
  }

  // backward pass: with body i's subtree summed, the forces its columns pair with (Ic s and
  // Bc^T s against its own and its ancestors' columns, P and Q against its ancestors' rows);
  // Ic_p += Ic_i, Bc_p += Bc_i, F_p += F_i (all in base coordinates: no transform)
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::Backward);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    for (int d = 0; d < joint_nv(model.joint_type[i]); ++d) {
      const int c = k + d;
      S* f = &ws.pair_force[24 * static_cast<std::size_t>(c)];
      put(f, mul(ws.oIc[i], ws.s[c]));
      put(f + 6, mul_T(ws.oBc[i], ws.s[c]));
      // a root has no ancestors' rows
      put(f + 12, p < 0 ? Force<S>{}
                        : mul(ws.oIc[i], ws.alpha[c]) + mul(ws.oBc[i], ws.dv[c]) +
                              cross_force(ws.s[c], ws.oF[i]));
      put(f + 18, p < 0 ? Force<S>{} : mul(ws.oIc[i], ws.beta[c]) + mul(ws.oBc[i], ws.s[c]));
    }
    if (p < 0) continue;
    ws.oIc[p] = ws.oIc[p] + ws.oIc[i];
    ws.oBc[p] = ws.oBc[p] + ws.oBc[i];
    ws.oF[p] = ws.oF[p] + ws.oF[i];
  }

  // the pairs of joints: d tau_r / d(q, v)_c for c on r's path to the root, and the reverse
  TraceHook<S>::enter(-1, Pass::Pairs);
  for (std::size_t c = 0; c < n; ++c) {
    S* m = &ws.pair_motion[24 * c];
    put(m, ws.s[c]), put(m + 6, ws.dv[c]), put(m + 12, ws.alpha[c]), put(m + 18, ws.beta[c]);
  }
  const int ints[] = {model.nv};
  const std::span<const int> tables[] = {ws.own_begin, ws.own_end, ws.previous};
  const std::span<const S> inputs[] = {ws.pair_motion, ws.pair_force};
  const std::span<S> outputs[] = {dtau_dq, dtau_dv};
  const std::string_view names[] = {"own_begin", "own_end", "previous", "motion",
                                    "force",     "dtau_dq", "dtau_dv"};
  run_kernel<S>({"derivative_pairs", ints, tables, inputs, outputs, names},
                [&](auto in, auto out) {
                  kernels::derivative_pairs(model.nv, ws.own_begin.data(), ws.own_end.data(),
                                            ws.previous.data(), in[0].data(), in[1].data(),
                                            out[0].data(), out[1].data());
                });
}

}  // namespace dyngen
