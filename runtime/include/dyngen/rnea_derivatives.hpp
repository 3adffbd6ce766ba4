// Partial derivatives of inverse dynamics, d tau / d q and d tau / d v, analytically in the
// bodies' own coordinates (after Carpentier & Mansard, "Analytical derivatives of rigid body
// dynamics algorithms", RSS 2018, with the inertia terms gathered into one variation per
// subtree).
//
// A change of q_j along its joint column s_j moves joint j's subtree rigidly: in each body's
// own frame nothing of the subtree changes but the velocity and acceleration handed down from
// j's parent p (v_p, a_p, both in j's frame), which change by
//   dv_j = v_p x s_j,  alpha_j = a_p x s_j + v_p x dv_j          (per unit of q_j)
//   beta_j = (v_p + v_j) x s_j                                   (per unit of v_j)
// carried down the subtree as any motion is. A body's force f = I a + v x* I v then changes by
// I delta_a + B delta_v (spatial.hpp's InertiaVariation B), and summed over a subtree, with
// Ic, Bc and F the composite inertia, variation and force of a subtree in its root body's frame:
//   d tau_i / dq_j = (Ic_i S_i) . alpha_j + (Bc_i^T S_i) . dv_j           i in the subtree of j
//                  = S_i . (Ic_j alpha_j + Bc_j dv_j + s_j x* F_j)         i an ancestor of j
//   d tau_i / dv_j = (Ic_i S_i) . beta_j + (Bc_i^T S_i) . s_j              i in the subtree of j
//                  = S_i . (Ic_j beta_j + Bc_j s_j)                        i an ancestor of j
// where each product pairs a force with a motion in one frame: the forces of the deeper joint
// are carried up to the other's, X^T f per joint, as CRBA carries its columns of M
// (kernels::derivative_pairs). In the
// bodies' frames each joint's S is a constant of few non-zeros and each body's inertia a
// constant, so the generated code keeps the robot's zeros; Ic, Bc and F are carried up as
// CRBA carries Ic (Bc's symmetric part as an inertia of mass 0, its skew part as a force).
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

#include "dyngen/joint.hpp"
#include "dyngen/kernels.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// The pairs of joints are carried up joint by joint while all columns' paths to the root
/// total at most this many joints, and turned into base coordinates once per column beyond
/// it. Carried, the pairs run on S and the generator unrolls them with the robot's zeros,
/// which takes fewer operations on every test robot (docs/performance.md, "Derivatives"), but
/// the code grows with the paths; in base coordinates they are a kernel call for a deep robot,
/// which keeps atlas floating's derivatives (150 path joints) compiling in under a minute.
inline constexpr int max_carried_path_joints = 128;

/// Whether rnea_derivatives carries its pairs (above): the sum over joint columns of the
/// joints on the path from the column's body to the root, its own excluded.
template <class S>
bool carries_derivative_pairs(const Model<S>& model) {
  int path_joints = 0;
  for (int i = 0; i < model.nbodies; ++i)
    for (int j = model.parent[i]; j >= 0; j = model.parent[j])
      path_joints += joint_nv(model.joint_type[i]);
  return path_joints <= max_carried_path_joints;
}

/// X^T B X: a variation in child coordinates expressed in parent coordinates. The symmetric
/// part transforms as an inertia of mass 0, x -> x x* p as the force p (X^T (X x x* p) =
/// x x* X^T p).
template <class S>
InertiaVariation<S> apply_variation_T(const Xform<S>& X, const InertiaVariation<S>& B) {
  const RigidInertia<S> symmetric = apply_inertia_T(X, RigidInertia<S>{S(0), B.hdot, B.Idot});
  return {symmetric.h, symmetric.I, apply_force_T(X, B.p)};
}

/// d tau / dq and d tau / dv of rnea(q, v, a), row-major nv x nv: dtau_dq[i * nv + j] =
/// d tau_i / dq_j. The columns of a free joint are its tangent directions: q moved to q (+) d,
/// the body's pose M times exp(d) with d = (linear, angular) in the body's own frame, the
/// order of its v. Entries of joints on different branches are zero. No allocation.
template <class S>
void rnea_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<const S> qd, std::span<const S> qdd, std::span<S> dtau_dq,
                      std::span<S> dtau_dv) {
  const Motion<S> a0 = base_acceleration(model);

  // forward pass, in body coordinates: v_i = X v_p + S qd_i, a_i = X a_p + S qdd_i + v_i x S qd_i
  // (RBDA Table 5.1), the columns' dv, alpha and beta, and each body's inertia, variation
  // B_i = B(I_i, v_i) and force f_i = I a + v x* I v, to be summed over subtrees below
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    const Xform<S>& X = ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    const Motion<S> vp = p < 0 ? Motion<S>{} : apply_motion(X, ws.v[p]);
    const Motion<S> ap = apply_motion(X, p < 0 ? a0 : ws.a[p]);
    const int dofs = joint_nv(model.joint_type[i]);
    Motion<S> vJ, aJ;
    for (int d = 0; d < dofs; ++d) {
      ws.s[k + d] = joint_column(model, i, d);
      vJ = vJ + scale(ws.s[k + d], qd[k + d]);
      aJ = aJ + scale(ws.s[k + d], qdd[k + d]);
    }
    ws.v[i] = vp + vJ;
    ws.a[i] = ap + aJ + cross_motion(ws.v[i], vJ);
    for (int d = 0; d < dofs; ++d) {
      const Motion<S>& s = ws.s[k + d];
      ws.dv[k + d] = cross_motion(vp, s);
      ws.alpha[k + d] = cross_motion(ap, s) + cross_motion(vp, ws.dv[k + d]);
      // for a one-column joint v_i x s = v_p x s, since s x s = 0
      ws.beta[k + d] = dofs == 1 ? ws.dv[k + d] + ws.dv[k + d] : cross_motion(vp + ws.v[i], s);
    }
    ws.Ic[i] = model.I[i];
    ws.Bc[i] = variation(ws.Ic[i], ws.v[i]);
    ws.F[i] = mul(ws.Ic[i], ws.a[i]) + cross_force(ws.v[i], ws.Bc[i].p);
  }

  // backward pass: with body i's subtree summed, the forces its columns pair with (Ic s and
  // Bc^T s against its own and its ancestors' columns, P and Q against its ancestors' rows);
  // Ic_p += X^T Ic_i X, Bc_p += X^T Bc_i X, F_p += X^T F_i
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::Backward);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    for (int d = 0; d < joint_nv(model.joint_type[i]); ++d) {
      const int c = k + d;
      const Motion<S>& s = ws.s[c];
      S* f = &ws.pair_force[24 * static_cast<std::size_t>(c)];
      put(f, mul(ws.Ic[i], s));
      put(f + 6, mul_T(ws.Bc[i], s));
      // a root has no ancestors' rows
      put(f + 12, p < 0 ? Force<S>{}
                        : mul(ws.Ic[i], ws.alpha[c]) + mul(ws.Bc[i], ws.dv[c]) +
                              cross_force(s, ws.F[i]));
      put(f + 18, p < 0 ? Force<S>{} : mul(ws.Ic[i], ws.beta[c]) + mul(ws.Bc[i], s));
    }
    if (p < 0) continue;
    const Xform<S>& X = ws.Xup[i];
    ws.Ic[p] = ws.Ic[p] + apply_inertia_T(X, ws.Ic[i]);
    ws.Bc[p] = ws.Bc[p] + apply_variation_T(X, ws.Bc[i]);
    ws.F[p] = ws.F[p] + apply_force_T(X, ws.F[i]);
  }

  // the pairs of joints: each column's forces carried up its path to the root, one joint at a
  // time, and paired with the columns of its own joint and of each ancestor; on a deep robot
  // (max_carried_path_joints) each column's terms are turned into base coordinates once instead
  TraceHook<S>::enter(-1, Pass::Pairs);
  const bool carry = carries_derivative_pairs(model);
  for (int i = 0; i < model.nbodies; ++i) {
    const int p = model.parent[i];
    if (!carry) ws.X0[i] = p < 0 ? ws.Xup[i] : compose(ws.Xup[i], ws.X0[p]);
    const Xform<S>& X = ws.Xup[i];
    S* x = &ws.pair_X[12 * static_cast<std::size_t>(i)];
    const S e[12] = {X.E.xx, X.E.xy, X.E.xz, X.E.yx, X.E.yy, X.E.yz,
                     X.E.zx, X.E.zy, X.E.zz, X.r.x,  X.r.y,  X.r.z};
    for (int k = 0; k < 12; ++k) x[k] = carry ? e[k] : S(0);
    for (int c = model.v_index[i]; c < model.v_index[i] + joint_nv(model.joint_type[i]); ++c) {
      S* m = &ws.pair_motion[24 * static_cast<std::size_t>(c)];
      const Motion<S>* terms[] = {&ws.s[c], &ws.dv[c], &ws.alpha[c], &ws.beta[c]};
      for (int t = 0; t < 4; ++t)
        put(m + 6 * t, carry ? *terms[t] : apply_motion_inv(ws.X0[i], *terms[t]));
      if (carry) continue;
      S* f = &ws.pair_force[24 * static_cast<std::size_t>(c)];
      for (int t = 0; t < 4; ++t) {
        const S* g = f + 6 * t;  // as put wrote it
        const Force<S> term{{g[0], g[2], g[4]}, {g[1], g[3], g[5]}};
        put(f + 6 * t, apply_force_T(ws.X0[i], term));
      }
    }
  }
  // carried pairs run on S, so the generator unrolls them and keeps the robot's zeros
  if (carry) {
    kernels::derivative_pairs(model.nv, 1, ws.column_body.data(), ws.first_column.data(),
                              model.parent.data(), ws.pair_X.data(), ws.pair_motion.data(),
                              ws.pair_force.data(), dtau_dq.data(), dtau_dv.data());
    return;
  }
  const int ints[] = {model.nv, 0};
  const std::span<const int> tables[] = {ws.column_body, ws.first_column, model.parent};
  const std::span<const S> inputs[] = {ws.pair_X, ws.pair_motion, ws.pair_force};
  const std::span<S> outputs[] = {dtau_dq, dtau_dv};
  const std::string_view names[] = {"column_body", "first", "parent", "X",
                                    "motion",      "force", "dtau_dq", "dtau_dv"};
  run_kernel<S>({"derivative_pairs", ints, tables, inputs, outputs, names},
                [&](auto in, auto out) {
                  kernels::derivative_pairs(model.nv, 0, ws.column_body.data(),
                                            ws.first_column.data(), model.parent.data(),
                                            in[0].data(), in[1].data(), in[2].data(),
                                            out[0].data(), out[1].data());
                });
}

}  // namespace dyngen
