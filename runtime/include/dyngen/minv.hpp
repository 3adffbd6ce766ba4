// The inverse of the mass matrix: CRBA's M, factorised as L^T D L along the tree's branches
// (Featherstone, RBDA 6.5: L keeps M's sparsity, a joint's row touching its ancestors only), then
// M^-1 = L^-1 D^-1 L^-T. Traced, this takes fewer operations than Carpentier's articulated-body
// recursion (Pinocchio's computeMinverse) on every robot measured, and the generated code less
// time (docs/performance.md, "The inverse mass matrix"). aba_derivatives takes its M^-1 the
// same way, and forward dynamics with mimic joints their factorisation.
#pragma once

#include <span>

#include "dyngen/crba.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// M(q)^-1, row-major nv x nv, exactly symmetric. The same preconditions as aba: every joint
/// moves some inertia, so M is positive definite. Needs the workspace's matrix buffers
/// (Workspace::has_matrix_buffers, nv <= Workspace::max_matrix_nv). No allocation.
template <class S>
void minv(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> Minv) {
  const int n = model.nv;
  crba<S>(model, ws, q, ws.H);
  factor_ltdl<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv);
  ltdl_inverse<S>(n, ws.column_parent.data(), ws.H, ws.column_Dinv, ws.Linv, Minv);
}

}  // namespace dyngen
