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
// (kernels::column_pairs). In the bodies' frames each joint's S is a constant of few
// non-zeros and each body's inertia a constant, so the generated code keeps the robot's
// zeros; Ic, Bc and F are carried up as CRBA carries Ic (Bc's symmetric part as an inertia of
// mass 0, its skew part as a force).
//
// A deep robot (max_carried_path_joints) does it all in base coordinates instead, as one
// frame: nothing is carried, every S, inertia and term is dense, and the pairs are plain inner
// products, which a kernel call keeps compact. There a change of q_j moves each motion m of
// the subtree by s_j x m as well, which the same formulas absorb (the rotation of S_i cancels
// against the rigid part of F_i: (s x S)^T F + S^T (s x* F) = 0).
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

#include "dyngen/joint.hpp"
#include "dyngen/kernels.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// rnea_derivatives works in the bodies' frames, its pairs carried up joint by joint, while
/// all columns' paths to the root total at most this many joints, and in base coordinates
/// beyond it. Carried, the pairs run on S and the generator unrolls them with the robot's
/// zeros, which takes fewer operations on every test robot (docs/performance.md,
/// "Derivatives"), but the code grows with the paths, and the bodies' sparsity patterns differ
/// where base coordinates make their sections alike and shareable: atlas floating's
/// derivatives (150 path joints) compile in about half the time in base coordinates.
inline constexpr int max_carried_path_joints = 128;

/// Whether rnea_derivatives works in the bodies' frames (above): the sum over joint columns of
/// the joints on the path from the column's body to the root, its own excluded.
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

template <class S>
void rnea_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<const S> qd, std::span<const S> qdd, std::span<S> dtau_dq,
                      std::span<S> dtau_dv);

namespace detail {

/// rnea_derivatives of a robot with mimic joints: its joints' derivatives at q_joints = G q +
/// offset, G v, G a, then G^T d tau_joints G (G from the coordinates to the joints; a mirroring
/// mimic joint's entry of G is 1, its axis negated in independent_joints).
template <class S>
void mimic_rnea_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                            std::span<const S> qd, std::span<const S> qdd, std::span<S> dtau_dq,
                            std::span<S> dtau_dv) {
  const Model<S>& joints = *ws.joints_model;
  TraceHook<S>::enter(-1, Pass::Product);
  const auto law = [&](int i, const S& x, bool position) {
    if (!is_mimic(model, i) || model.mimic_mirrors[i]) return x;
    return position ? joint_position(model, i, x) : model.mimic_multiplier[i] * x;
  };
  for (int i = 0; i < model.nbodies; ++i) {
    for (int e = 0; e < joint_nq(model.joint_type[i]); ++e)
      ws.q_joints[joints.q_index[i] + e] = law(i, q[model.q_index[i] + e], true);
    for (int d = 0; d < joint_nv(model.joint_type[i]); ++d) {
      ws.v_joints[joints.v_index[i] + d] = law(i, qd[model.v_index[i] + d], false);
      ws.a_joints[joints.v_index[i] + d] = law(i, qdd[model.v_index[i] + d], false);
    }
  }
  rnea_derivatives<S>(joints, *ws.joints, ws.q_joints, ws.v_joints, ws.a_joints, ws.dq_joints,
                      ws.dv_joints);
  TraceHook<S>::enter(-1, Pass::Product);
  const int n = model.nv, nf = joints.nv;
  for (std::size_t e = 0; e < dtau_dq.size(); ++e) dtau_dq[e] = S(0), dtau_dv[e] = S(0);
  for (int i = 0; i < model.nbodies; ++i)
    for (int d = 0; d < joint_nv(model.joint_type[i]); ++d)
      for (int j = 0; j < model.nbodies; ++j)
        for (int e = 0; e < joint_nv(model.joint_type[j]); ++e) {
          const std::size_t full = row_major(nf, joints.v_index[i] + d, joints.v_index[j] + e);
          const std::size_t out = row_major(n, model.v_index[i] + d, model.v_index[j] + e);
          dtau_dq[out] = dtau_dq[out] + law(i, law(j, ws.dq_joints[full], false), false);
          dtau_dv[out] = dtau_dv[out] + law(i, law(j, ws.dv_joints[full], false), false);
        }
}

}  // namespace detail

/// d tau / dq and d tau / dv of rnea(q, v, a), row-major nv x nv: dtau_dq[i * nv + j] =
/// d tau_i / dq_j. The columns of a free joint are its tangent directions: q moved to q (+) d,
/// the body's pose M times exp(d) with d = (linear, angular) in the body's own frame, the
/// order of its v. Entries of joints on different branches are zero. No allocation.
template <class S>
void rnea_derivatives(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<const S> qd, std::span<const S> qdd, std::span<S> dtau_dq,
                      std::span<S> dtau_dv) {
  if (!model.mimic.empty())
    return detail::mimic_rnea_derivatives(model, ws, q, qd, qdd, dtau_dq, dtau_dv);
  const Motion<S> a0 = base_acceleration(model);
  // in the bodies' frames, or (a deep robot) all in base coordinates, the rigid motion of a
  // subtree then being the same for every body of it
  const bool local = carries_derivative_pairs(model);

  // forward pass: v_i = v_p + S qd_i, a_i = a_p + S qdd_i + v_i x S qd_i (RBDA Table 5.1,
  // v_p and a_p moved into body i's frame by X_i, or S_i into base coordinates by X0_i), the
  // columns' dv, alpha and beta, and each body's inertia, variation B_i = B(I_i, v_i) and force
  // f_i = I a + v x* I v, to be summed over subtrees below
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    const int k = model.v_index[i];
    const int p = model.parent[i];
    const Xform<S>& X = ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    if (!local) ws.X0[i] = p < 0 ? X : compose(X, ws.X0[p]);
    const Motion<S> vp = p < 0 ? Motion<S>{} : local ? apply_motion(X, ws.v[p]) : ws.v[p];
    const Motion<S>& a_parent = p < 0 ? a0 : ws.a[p];
    const Motion<S> ap = local ? apply_motion(X, a_parent) : a_parent;
    const int dofs = joint_nv(model.joint_type[i]);
    Motion<S> vJ, aJ;
    for (int d = 0; d < dofs; ++d) {
      const Motion<S> column = joint_column(model, i, d);
      ws.s[k + d] = local ? column : apply_motion_inv(ws.X0[i], column);
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
    ws.Ic[i] = local ? model.I[i] : apply_inertia_T(ws.X0[i], model.I[i]);
    ws.Bc[i] = variation(ws.Ic[i], ws.v[i]);
    ws.F[i] = mul(ws.Ic[i], ws.a[i]) + cross_force(ws.v[i], ws.Bc[i].p);
  }

  // backward pass: with body i's subtree summed, the forces its columns pair with (Ic s and
  // Bc^T s against its own and its ancestors' columns, P and Q against its ancestors' rows);
  // Ic_p += X^T Ic_i X, Bc_p += X^T Bc_i X, F_p += X^T F_i (no transform in base coordinates)
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
    ws.Ic[p] = ws.Ic[p] + (local ? apply_inertia_T(X, ws.Ic[i]) : ws.Ic[i]);
    ws.Bc[p] = ws.Bc[p] + (local ? apply_variation_T(X, ws.Bc[i]) : ws.Bc[i]);
    ws.F[p] = ws.F[p] + (local ? apply_force_T(X, ws.F[i]) : ws.F[i]);
  }

  // the pairs of joints: d tau_r / d(q, v)_c for r on c's path to the root, and the reverse;
  // in the bodies' frames each column's forces are carried up its path one joint at a time
  TraceHook<S>::enter(-1, Pass::Pairs);
  for (int i = 0; i < model.nbodies; ++i) {
    const Xform<S>& X = ws.Xup[i];
    const S e[12] = {X.E.xx, X.E.xy, X.E.xz, X.E.yx, X.E.yy, X.E.yz,
                     X.E.zx, X.E.zy, X.E.zz, X.r.x,  X.r.y,  X.r.z};
    S* x = &ws.pair_X[12 * static_cast<std::size_t>(i)];
    for (int k = 0; k < 12; ++k) x[k] = local ? e[k] : S(0);
  }
  for (std::size_t c = 0; c < static_cast<std::size_t>(model.nv); ++c) {
    S* m = &ws.pair_motion[24 * c];
    put(m, ws.s[c]), put(m + 6, ws.dv[c]), put(m + 12, ws.alpha[c]), put(m + 18, ws.beta[c]);
  }
  // carried pairs run on S, so the generator unrolls them and keeps the robot's zeros, each
  // column's in its body's section
  if (local) {
    for (std::size_t e = 0; e < dtau_dq.size(); ++e) dtau_dq[e] = S(0), dtau_dv[e] = S(0);
    for (int c = 0; c < model.nv; ++c) {
      TraceHook<S>::enter(ws.column_body[c], Pass::Pairs);
      kernels::column_pairs(model.nv, 1, c, ws.column_body.data(), ws.first_column.data(),
                            model.parent.data(), ws.pair_X.data(), ws.pair_motion.data(),
                            ws.pair_force.data(), dtau_dq.data(), dtau_dv.data());
    }
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
