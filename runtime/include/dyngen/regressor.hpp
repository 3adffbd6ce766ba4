// The inertial-parameter regressor: RNEA's torques are linear in each body's standard inertial
// parameters, tau = Y(q, qd, qdd) pi + armature qdd (Atkeson, An and Hollerbach 1986; Khalil
// and Dombre, "Modeling, Identification and Control of Robots", ch. 12).
#pragma once

#include <span>

#include "dyngen/rnea.hpp"

namespace dyngen {

/// Standard parameters per body, in Pinocchio's order: m, m c (x, y, z), then the inertia about
/// the body's origin in its axes: Ixx, Ixy, Iyy, Ixz, Iyz, Izz.
inline constexpr int parameters_per_body = 10;

/// Body inertia I's standard parameters into pi[0..10).
template <class S>
void inertial_parameters(const RigidInertia<S>& I, S* pi) {
  pi[0] = I.m, pi[1] = I.h.x, pi[2] = I.h.y, pi[3] = I.h.z;
  pi[4] = I.I.xx, pi[5] = I.I.xy, pi[6] = I.I.yy, pi[7] = I.I.xz, pi[8] = I.I.yz, pi[9] = I.I.zz;
}

namespace detail {

/// The rigid inertia whose standard parameters are 1 at p and 0 elsewhere.
template <class S>
RigidInertia<S> unit_inertia(int p) {
  S pi[parameters_per_body]{};
  pi[p] = S(1);
  return {pi[0], {pi[1], pi[2], pi[3]}, {pi[4], pi[6], pi[9], pi[5], pi[7], pi[8]}};
}

}  // namespace detail

/// Y (model.nv x 10 model.nbodies, row-major: Y[k * 10 nbodies + 10 i + p]) with
/// rnea(q, qd, qdd) = Y pi + armature qdd, pi stacking the bodies' standard parameters
/// (inertial_parameters) in body order. Column 10 i + p is the torque that body i's parameter p
/// alone would need: the force of unit_inertia(p) moving as body i does (body_force is linear in
/// the inertia), projected onto each joint on its path to the root. No allocation.
template <class S>
void regressor(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
               std::span<const S> qd, std::span<const S> qdd, std::span<S> Y) {
  const Motion<S> a0 = base_acceleration(model);
  const int columns = parameters_per_body * model.nbodies;

  // forward pass: each body's motion, as RNEA's
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Forward);
    detail::classical_motion(model, ws, i, q, qd, qdd, a0);
  }

  // backward pass: body i's column p, Y[k, 10 i + p] = S_j^T X_j<-i^* f_ip for each joint j on
  // its path and k among j's entries (a mimic joint's added to its primary's)
  for (std::size_t e = 0; e < Y.size(); ++e) Y[e] = S(0);
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::Backward);
    for (int p = 0; p < parameters_per_body; ++p) {
      Force<S> f = detail::body_force(detail::unit_inertia<S>(p), ws.v[i].ang, ws.a[i].ang,
                                      ws.a[i].lin);
      for (int j = i; j >= 0; j = model.parent[j]) {
        S t[6];
        joint_project(model, j, f, t);
        for (int d = 0; d < joint_nv(model.joint_type[j]); ++d) {
          S& y = Y[static_cast<std::size_t>(model.v_index[j] + d) * columns +
                   parameters_per_body * i + p];
          y = y + t[d];
        }
        if (model.parent[j] >= 0) f = apply_force_T(ws.Xup[j], f);
      }
    }
  }
}

}  // namespace dyngen
