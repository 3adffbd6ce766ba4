// Composite rigid body algorithm: the joint-space mass matrix M(q) (RBDA Table 6.2).
#pragma once

#include <cstddef>
#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

namespace detail {

/// M = G^T M_joints G where a mimic joint shares a column: the entries S_j^T F of joint j's
/// columns (from vj) and the row's are added to M[row][vj + e], and with `mirror` (j an
/// ancestor) to M[vj + e][row] too, which adds twice what a joint and its mimic on one path
/// make on the diagonal.
template <class S>
void add_mimic_entry(const Model<S>& model, int j, const Force<S>& F, std::size_t row,
                     std::size_t vj, std::span<S> M, bool mirror) {
  const std::size_t n = static_cast<std::size_t>(model.nv);
  S t[6];
  joint_project(model, j, F, t);
  for (int e = 0; e < joint_nv(model.joint_type[j]); ++e) {
    const std::size_t col = vj + static_cast<std::size_t>(e);
    M[row * n + col] = M[row * n + col] + t[e];
    if (mirror) M[col * n + row] = M[col * n + row] + t[e];
  }
}

}  // namespace detail

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
  // M_ii[d] = S_i^T F (+ the armature on the diagonal); M_ij[d] = M_ji^T[d] = S_j^T F with F carried to each ancestor j
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::CompositeInertia);
    const int p = model.parent[i];
    if (p >= 0) ws.Ic[p] = ws.Ic[p] + apply_inertia_T(ws.Xup[i], ws.Ic[i]);
    for (int d = 0; d < joint_nv(model.joint_type[i]); ++d) {
      TraceHook<S>::enter(i, Pass::CompositeInertia);  // again after a column was carried up
      const std::size_t row = static_cast<std::size_t>(model.v_index[i] + d);
      Force<S> F = mul(ws.Ic[i], joint_column(model, i, d));
      if (ws.shares_column[i]) detail::add_mimic_entry(model, i, F, row, row, M, false);
      else joint_project(model, i, F, &M[row * n + model.v_index[i]]);
      if (!model.armature.empty() && !is_mimic(model, i))
        M[row * n + row] = M[row * n + row] + model.armature[row];
      for (int j = i; model.parent[j] >= 0;) {
        TraceHook<S>::enter(model.parent[j], Pass::Column);
        F = apply_force_T(ws.Xup[j], F);
        j = model.parent[j];
        const std::size_t vj = static_cast<std::size_t>(model.v_index[j]);
        if (ws.shares_column[i] || ws.shares_column[j]) {
          detail::add_mimic_entry(model, j, F, row, vj, M, true);
          continue;
        }
        joint_project(model, j, F, &M[row * n + vj]);
        for (int e = 0; e < joint_nv(model.joint_type[j]); ++e)
          M[(vj + e) * n + row] = M[row * n + vj + e];
      }
    }
  }
}

/// M = L^T D L in place (RBDA Table 6.3, with D apart): eliminating the deepest joint first
/// keeps M's zeros, L_kj being non-zero only for j on k's path to the root. parent[k] is the
/// column before k on that path (-1 at the root). M's lower triangle becomes L below the
/// diagonal (unit diagonal implied); Dinv[k] = 1 / D_k, which equals ABA's D of that column.
template <class S>
void factor_ltdl(int n, const int* parent, std::span<S> M, std::span<S> Dinv) {
  TraceHook<S>::enter(-1, Pass::Factor);
  const auto at = [n](int i, int j) { return row_major(n, i, j); };
  for (int k = n - 1; k >= 0; --k) {
    Dinv[k] = S(1) / M[at(k, k)];
    for (int i = parent[k]; i >= 0; i = parent[i]) {
      const S a = M[at(k, i)] * Dinv[k];
      for (int j = i; j >= 0; j = parent[j]) M[at(i, j)] = M[at(i, j)] - a * M[at(k, j)];
      M[at(k, i)] = a;
    }
  }
}

/// x = M^-1 b in place from factor_ltdl's L and Dinv (RBDA Table 6.4 with D apart): L^T y = b
/// from the deepest joint up, y D^-1, then L x = y from the root down.
template <class S>
void ltdl_solve(int n, const int* parent, std::span<const S> L, std::span<const S> Dinv,
                std::span<S> x) {
  TraceHook<S>::enter(-1, Pass::Factor);
  const auto at = [n](int i, int j) { return row_major(n, i, j); };
  for (int k = n - 1; k >= 0; --k)
    for (int i = parent[k]; i >= 0; i = parent[i]) x[i] = x[i] - L[at(k, i)] * x[k];
  for (int k = 0; k < n; ++k) x[k] = x[k] * Dinv[k];
  for (int k = 0; k < n; ++k)
    for (int i = parent[k]; i >= 0; i = parent[i]) x[k] = x[k] - L[at(k, i)] * x[i];
}

/// M^-1 = L^-1 D^-1 L^-T from factor_ltdl's L and Dinv, written full and exactly symmetric.
/// L^-1 keeps L's pattern (Linv_ij non-zero for j on i's path), so an entry (i, j) sums over
/// the joints on both paths only. Linv is n x n scratch, its entries off L's pattern
/// untouched. No allocation.
template <class S>
void ltdl_inverse(int n, const int* parent, std::span<const S> L, std::span<const S> Dinv,
                  std::span<S> Linv, std::span<S> Minv) {
  TraceHook<S>::enter(-1, Pass::Factor);
  const auto at = [n](int i, int j) { return row_major(n, i, j); };
  // L Linv = 1, row by row: Linv_ik = -sum over m from i's parent up to k of L_im Linv_mk;
  // the entries off i's path are zero and never read
  for (int i = 0; i < n; ++i) {
    Linv[at(i, i)] = S(1);
    for (int k = parent[i]; k >= 0; k = parent[k]) {
      S sum = S(0);
      for (int m = parent[i]; m != parent[k]; m = parent[m])
        sum = sum - L[at(i, m)] * Linv[at(m, k)];
      Linv[at(i, k)] = sum;
    }
  }
  // Minv_ij = sum over the joints k on both paths of Linv_ik Dinv_k Linv_jk, from the paths'
  // lowest common joint up (none: joints of different trees, 0)
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      int k = i;
      for (int l = j; k != l;) {
        if (k > l)
          k = parent[k];
        else
          l = parent[l];
      }
      S sum = S(0);
      for (; k >= 0; k = parent[k]) sum = sum + Linv[at(i, k)] * Dinv[k] * Linv[at(j, k)];
      Minv[at(i, j)] = sum;
      Minv[at(j, i)] = sum;
    }
}

}  // namespace dyngen
