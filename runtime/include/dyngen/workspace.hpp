// Per-call buffers of the algorithms, allocated once per model (never inside an algorithm).
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include "dyngen/joint.hpp"
#include "dyngen/model.hpp"

namespace dyngen {

/// Entry (i, j) of a row-major n x n matrix, in std::size_t since i * n overflows int from
/// n = 46,341
inline std::size_t row_major(int n, int i, int j) {
  return static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j);
}

/// The model with each mimic joint on a coordinate of its own (Model::mimic cleared, a mimic
/// joint without armature): the joints whose derivatives rnea_derivatives maps to the
/// coordinates of a robot with mimic joints. A mirroring mimic joint (q_i = -q_p) turns about
/// its axis negated instead, so that its coordinate is q_p itself and its sine that of q_p,
/// as in the model (joint.hpp's angle_sincos).
template <class S>
Model<S> independent_joints(const Model<S>& model) {
  Model<S> m = model;
  for (int i = 0; i < m.nbodies; ++i)
    if (is_mimic(model, i) && model.mimic_mirrors[i])
      m.joint_axis[i] = scale(m.joint_axis[i], S(-1));
  m.mimic.clear(), m.mimic_multiplier.clear(), m.mimic_offset.clear(), m.mimic_mirrors.clear();
  m.nq = m.nv = 0;
  m.armature.clear();
  for (int i = 0; i < m.nbodies; ++i) {
    m.q_index[i] = m.nq, m.v_index[i] = m.nv;
    m.nq += joint_nq(m.joint_type[i]);
    m.nv += joint_nv(m.joint_type[i]);
    for (int d = 0; d < joint_nv(m.joint_type[i]) && !model.armature.empty(); ++d)
      m.armature.push_back(is_mimic(model, i) ? S(0) : model.armature[model.v_index[i] + d]);
  }
  return m;
}

template <class S>
struct Workspace {
  explicit Workspace(const Model<S>& model)
      : Xup(model.nbodies), X0(model.nbodies), v(model.nbodies), a(model.nbodies), c(model.nbodies),
        f(model.nbodies), Ic(model.nbodies), IA(model.nbodies), pA(model.nbodies),
        U(model.nbodies), D(model.nbodies), Dinv(model.nbodies), u(model.nbodies),
        Dinv_ball(model.nbodies),
        zero(model.nv, S(0)), Bc(model.nbodies), F(model.nbodies), s(model.nv), dv(model.nv),
        alpha(model.nv), beta(model.nv), pair_X(12 * static_cast<std::size_t>(model.nbodies)),
        pair_motion(24 * static_cast<std::size_t>(model.nv)), pair_force(pair_motion.size()),
        column_body(model.nv), first_column(model.nbodies + 1, model.nv),
        subtree_end(model.nbodies, 0), shares_column(model.nbodies, 0), qdd(model.nv) {
    for (int i = 0; i < model.nbodies; ++i)
      if (is_mimic(model, i)) shares_column[i] = shares_column[model.mimic[i]] = 1;
    // the columns of the joints in body i's subtree are [v_index[i], subtree_end[i])
    for (int i = model.nbodies - 1; i >= 0; --i) {
      subtree_end[i] = std::max(subtree_end[i], model.v_index[i] + joint_nv(model.joint_type[i]));
      if (model.parent[i] >= 0)
        subtree_end[model.parent[i]] = std::max(subtree_end[model.parent[i]], subtree_end[i]);
    }
    for (int i = 0; i < model.nbodies; ++i) {
      first_column[i] = model.v_index[i];
      for (int c = model.v_index[i]; c < model.v_index[i] + joint_nv(model.joint_type[i]); ++c)
        column_body[c] = i;
    }
    if (model.nv > max_matrix_nv) return;
    // each column's joint's end (for the rows of d tau below) and the column before it on its
    // path to the root
    std::vector<int> own_end(model.nv);
    column_parent.resize(static_cast<std::size_t>(model.nv));
    for (int i = 0; i < model.nbodies; ++i) {
      const int p = model.parent[i], k = model.v_index[i], end = k + joint_nv(model.joint_type[i]);
      for (int c = k; c < end; ++c) {
        own_end[c] = end;
        column_parent[c] =
            c > k ? c - 1 : p < 0 ? -1 : model.v_index[p] + joint_nv(model.joint_type[p]) - 1;
      }
    }
    // a mimic joint couples its primary's column to its own path, which need not be the
    // primary's: M is factorised as dense
    if (!model.mimic.empty())
      for (int c = 0; c < model.nv; ++c) column_parent[c] = c - 1;
    dtau_dq.resize(static_cast<std::size_t>(model.nv) * static_cast<std::size_t>(model.nv));
    dtau_dv.resize(dtau_dq.size());
    H.resize(dtau_dq.size());
    Linv.resize(dtau_dq.size());
    column_Dinv.resize(static_cast<std::size_t>(model.nv));
    h.resize(static_cast<std::size_t>(model.nv));
    const std::size_t nc = static_cast<std::size_t>(model.nc);
    Jc.resize(nc * static_cast<std::size_t>(model.nv));
    Wt.resize(Jc.size());
    A.resize(nc * nc);
    A_damped.resize(nc * nc);
    for (std::vector<S>* x : {&A_Dinv, &gamma, &Jv, &perr, &rc, &lam_step, &lam}) x->resize(nc);
    lam_map.resize(nc * nc);
    A_inverse.resize(nc * nc);
    lam_columns.resize(Jc.size());
    constrained_qdd.resize(static_cast<std::size_t>(model.nv));
    constraint_paths(model);
    // the rows of d tau that can be non-zero in column c: c's path to the root, then its
    // subtree; in d tau / dq none for a root joint's translations, which carry the whole robot
    // through uniform gravity and change no force in the bodies' frames (rnea_derivatives gives
    // +-0 there, and a sum over no rows the same bits as over those zeros)
    for (auto& begin : product_begin) begin.assign(1, 0);
    for (int i = 0; i < model.nbodies; ++i)
      for (int c = model.v_index[i]; c < model.v_index[i] + joint_nv(model.joint_type[i]); ++c) {
        const bool translation =
            model.parent[i] < 0 && is_translation_column(model.joint_type[i], c - model.v_index[i]);
        for (int d = 0; d < 2; ++d) {
          if (d == 1 || !translation) {
            for (int k = own_end[c] - 1; k >= 0; k = column_parent[k]) product_rows[d].push_back(k);
            for (int k = own_end[c]; k < subtree_end[i]; ++k) product_rows[d].push_back(k);
          }
          product_begin[d].push_back(static_cast<int>(product_rows[d].size()));
        }
      }
    if (!model.mimic.empty()) couple_buffers(model);
    has_matrix_buffers = true;
  }

  /// w_begin, w_columns, w_rows_begin and w_rows: where W^T = L^-T J^T can be non-zero. J's row
  /// is zero off the columns of the joints on its constraint's paths to the root, and L^-T
  /// carries it along the columns' parents only; with mimic joints (M factorised as dense),
  /// everywhere.
  void constraint_paths(const Model<S>& model) {
    const int n = model.nv;
    w_begin.assign(1, 0);
    std::vector<int> count(static_cast<std::size_t>(n), 0);
    for (const Constraint<S>& k : model.constraints) {
      std::vector<char> on(static_cast<std::size_t>(n), model.mimic.empty() ? 0 : 1);
      for (const int b : {k.body_a, k.body_b})
        for (int j = b; j >= 0; j = model.parent[j])
          for (int c = model.v_index[j]; c < model.v_index[j] + joint_nv(model.joint_type[j]); ++c)
            on[c] = 1;
      for (int c = n - 1; c >= 0; --c)
        if (on[c] && column_parent[c] >= 0) on[column_parent[c]] = 1;
      for (int r = 0; r < constraint_rows(k); ++r) {
        for (int c = 0; c < n; ++c)
          if (on[c]) w_columns.push_back(c), ++count[c];
        w_begin.push_back(static_cast<int>(w_columns.size()));
      }
    }
    w_rows_begin.assign(1, 0);
    for (int c = 0; c < n; ++c) w_rows_begin.push_back(w_rows_begin.back() + count[c]);
    w_rows.resize(w_columns.size());
    std::vector<int> next(w_rows_begin.begin(), w_rows_begin.end() - 1);
    for (int s = 0; s < model.nc; ++s)
      for (int e = w_begin[s]; e < w_begin[s + 1]; ++e) w_rows[next[w_columns[e]]++] = s;
  }

  /// A robot with mimic joints: every column's row of d tau may be non-zero (its columns couple
  /// branches), and its joints as independent ones, for rnea_derivatives.
  void couple_buffers(const Model<S>& model) {
    for (int d = 0; d < 2; ++d) {
      product_begin[d].assign(1, 0);
      product_rows[d].clear();
      for (int c = 0; c < model.nv; ++c) {
        for (int k = 0; k < model.nv; ++k) product_rows[d].push_back(k);
        product_begin[d].push_back(static_cast<int>(product_rows[d].size()));
      }
    }
    joints_model = std::make_unique<Model<S>>(independent_joints(model));
    joints = std::make_unique<Workspace>(*joints_model);
    const std::size_t nf = static_cast<std::size_t>(joints_model->nv);
    q_joints.resize(static_cast<std::size_t>(joints_model->nq));
    v_joints.resize(nf);
    a_joints.resize(nf);
    dq_joints.resize(nf * nf);
    dv_joints.resize(nf * nf);
  }

  /// Above this many degrees of freedom the workspace has no matrix buffers (they grow with
  /// nbodies * nv), and minv and aba_derivatives, which need them, cannot run (their size:
  /// docs/performance.md, "The generator's limits").
  static constexpr int max_matrix_nv = 1000;
  bool has_matrix_buffers = false;

  std::vector<Xform<S>> Xup;              // [nbodies] parent to body transform
  std::vector<Xform<S>> X0;               // [nbodies] base to body (forward_kinematics)
  std::vector<Motion<S>> v;               // [nbodies] body velocity (rnea, aba: angular only)
  std::vector<Motion<S>> a;               // [nbodies] body acceleration, gravity included
                                          // (rnea, aba: classical, rnea.hpp; rnea_derivatives:
                                          // spatial)
  std::vector<Motion<S>> c;               // [nbodies] velocity-product acceleration (ABA)
  std::vector<Force<S>> f;                // [nbodies] body force (RNEA)
  std::vector<RigidInertia<S>> Ic;        // [nbodies] composite inertia (CRBA, rnea_derivatives)
  std::vector<ArticulatedInertia<S>> IA;  // [nbodies] articulated inertia (ABA)
  std::vector<Force<S>> pA;               // [nbodies] articulated bias force (ABA)
  std::vector<Force<S>> U;                // [nbodies] IA S (ABA)
  std::vector<S> D;                       // [nbodies] S^T IA S (ABA)
  std::vector<S> Dinv;                    // [nbodies] 1 / D (ABA)
  std::vector<S> u;                       // [nbodies] tau - S^T pA (ABA)
  std::vector<Sym3<S>> Dinv_ball;         // [nbodies] (S^T IA S)^-1 of a ball joint (ABA)
  std::vector<S> zero;                    // [nv] zeros: the v and a of gravity() and nle()
  // rnea_derivatives, in the bodies' frames (in base coordinates past max_carried_path_joints,
  // rnea_derivatives.hpp): the composite variation and force of the subtree, beside v, a, Ic
  // and (base coordinates) X0 above; per joint column, S and its derivative terms dv, alpha,
  // beta
  std::vector<InertiaVariation<S>> Bc;        // [nbodies]
  std::vector<Force<S>> F;                    // [nbodies]
  std::vector<Motion<S>> s, dv, alpha, beta;  // [nv]
  // the arguments of kernels::derivative_pairs: per body its Xup (E, r: 12 numbers), per column
  // (s, dv, alpha, beta) and (Ic s, Bc^T s, P, Q), 24 numbers each; each column's body and each
  // body's first column (and nv after the last)
  std::vector<S> pair_X;                       // [12 nbodies]
  std::vector<S> pair_motion, pair_force;      // [24 nv]
  std::vector<int> column_body, first_column;  // [nv], [nbodies + 1]
  // the end of the columns of body i's subtree, which start at v_index[i]
  std::vector<int> subtree_end;          // [nbodies]
  // 1 where body i's column is shared with a mimic joint (its own, or its primary's): the
  // algorithms add its entries instead of writing them
  std::vector<char> shares_column;       // [nbodies]
  // minv and aba_derivatives: M factorised as L^T D L (crba.hpp), each column's parent column, 1 / D
  // and L^-1; h = nle, then tau - h; qdd = M^-1 (tau - h) and the derivatives of RNEA there
  std::vector<int> column_parent;        // [nv] if nv <= max_matrix_nv
  std::vector<S> H, Linv;                // [nv * nv] if nv <= max_matrix_nv
  std::vector<S> column_Dinv, h;         // [nv] if nv <= max_matrix_nv
  std::vector<S> qdd;                    // [nv]
  std::vector<S> dtau_dq, dtau_dv;       // [nv * nv] if nv <= max_matrix_nv
  // constrained.hpp, if nv <= max_matrix_nv: the constraints' Jacobian J and W^T = L^-T J^T
  // (nc x nv), their operational space inverse inertia A and A + mu factorised (nc x nc), its
  // 1 / pivots, Jdot v, J v, loops' position errors, the right side and a step of the solve
  std::vector<S> Jc, Wt, A, A_damped;
  std::vector<S> A_Dinv, gamma, Jv, perr, rc, lam_step;
  // contact_derivatives.hpp: the solution qdd (nv) and lam (nc), the solve's map T from right
  // side to lam and (A + mu)^-1 (nc x nc), and the columns' right sides (nc x nv)
  std::vector<S> constrained_qdd, lam, lam_map, A_inverse, lam_columns;
  // kernels::constrained_columns' columns where each row of W can be non-zero and, per column,
  // those rows (constraint_paths)
  std::vector<int> w_begin, w_columns;   // [nc + 1], [their count] if nv <= max_matrix_nv
  std::vector<int> w_rows_begin, w_rows;  // [nv + 1], [the same count] if nv <= max_matrix_nv
  // kernels::neg_product's rows of d tau that can be non-zero, per column, of d tau / dq [0]
  // and of d tau / dv [1]
  std::vector<int> product_begin[2];     // [nv + 1] if nv <= max_matrix_nv
  std::vector<int> product_rows[2];      // [sum of path and subtree lengths] if nv <= max_matrix_nv
  // a robot with mimic joints (if nv <= max_matrix_nv): its joints as independent ones, their
  // workspace, and their q, v, a and d tau / d(q, v)
  std::unique_ptr<Model<S>> joints_model;
  std::unique_ptr<Workspace> joints;
  std::vector<S> q_joints, v_joints, a_joints, dq_joints, dv_joints;
};

}  // namespace dyngen
