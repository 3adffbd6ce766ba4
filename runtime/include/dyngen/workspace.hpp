// Per-call buffers of the algorithms, allocated once per model (never inside an algorithm).
#pragma once

#include <vector>

#include "dyngen/model.hpp"

namespace dyngen {

template <class S>
struct Workspace {
  explicit Workspace(const Model<S>& model)
      : Xup(model.nbodies), X0(model.nbodies), v(model.nbodies), a(model.nbodies), c(model.nbodies),
        f(model.nbodies), Ic(model.nbodies), IA(model.nbodies), pA(model.nbodies),
        U(model.nbodies), D(model.nbodies), Dinv(model.nbodies), u(model.nbodies),
        zero(model.nv, S(0)) {}

  std::vector<Xform<S>> Xup;              // [nbodies] parent to body transform
  std::vector<Xform<S>> X0;               // [nbodies] base to body (forward_kinematics)
  std::vector<Motion<S>> v;               // [nbodies] body velocity
  std::vector<Motion<S>> a;               // [nbodies] body acceleration (gravity included)
  std::vector<Motion<S>> c;               // [nbodies] velocity-product acceleration (ABA)
  std::vector<Force<S>> f;                // [nbodies] body force (RNEA)
  std::vector<RigidInertia<S>> Ic;        // [nbodies] composite inertia (CRBA)
  std::vector<ArticulatedInertia<S>> IA;  // [nbodies] articulated inertia (ABA)
  std::vector<Force<S>> pA;               // [nbodies] articulated bias force (ABA)
  std::vector<Force<S>> U;                // [nbodies] IA S (ABA)
  std::vector<S> D;                       // [nbodies] S^T IA S (ABA)
  std::vector<S> Dinv;                    // [nbodies] 1 / D (ABA)
  std::vector<S> u;                       // [nbodies] tau - S^T pA (ABA)
  std::vector<S> zero;                    // [nv] zeros: the v and a of gravity() and nle()
};

}  // namespace dyngen
