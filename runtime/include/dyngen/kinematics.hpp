// Kinematics for integrators and for checking them: the time derivative of q, which differs
// from v only at free and ball joints (a quaternion has four entries and three rates), the
// projection of an integrated q back onto unit quaternions (integrate itself is in
// configuration.hpp), body poses and velocities, and the energies and momentum that a
// simulation should conserve.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>

#include "dyngen/configuration.hpp"
#include "dyngen/joint.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// qdot = dq/dt at velocity v: v itself for 1-DoF joints; for a free joint the position rate
/// R v_lin (R the rotation of its quaternion); for free and ball joints the quaternion rate
/// 1/2 quat (0, w).
template <class S>
void configuration_rate(const Model<S>& model, std::span<const S> q, std::span<const S> v,
                        std::span<S> qdot) {
  for (int i = 0; i < model.nbodies; ++i) {
    const S* qi = &q[model.q_index[i]];
    const S* vi = &v[model.v_index[i]];
    S* out = &qdot[model.q_index[i]];
    const int o = quaternion_offset(model.joint_type[i]);
    if (o < 0) {
      out[0] = vi[0];
      continue;
    }
    const S &w = qi[o], &x = qi[o + 1], &y = qi[o + 2], &z = qi[o + 3];
    if (o > 0) {
      const Vec3<S> p_rate = mul(quaternion_rotation(w, x, y, z), Vec3<S>{vi[0], vi[1], vi[2]});
      out[0] = p_rate.x, out[1] = p_rate.y, out[2] = p_rate.z;
    }
    // quat (0, w) with the angular velocity w in body coordinates
    const S &wx = vi[o], &wy = vi[o + 1], &wz = vi[o + 2];
    out[o] = S(0.5) * (-x * wx - y * wy - z * wz);
    out[o + 1] = S(0.5) * (w * wx + y * wz - z * wy);
    out[o + 2] = S(0.5) * (w * wy + z * wx - x * wz);
    out[o + 3] = S(0.5) * (w * wz + x * wy - y * wx);
  }
}

/// Rescales each free and ball joint's quaternion to unit length (after an integration step).
template <class S>
void normalize_configuration(const Model<S>& model, std::span<S> q) {
  using std::sqrt;
  for (int i = 0; i < model.nbodies; ++i) {
    const int o = quaternion_offset(model.joint_type[i]);
    if (o < 0) continue;
    S* quat = &q[model.q_index[i] + o];
    const S norm = sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
    for (int k = 0; k < 4; ++k) quat[k] = quat[k] / norm;
  }
}

namespace detail {

/// ws.Xup[i] and ws.X0[i] = X_i0, body i's transform from its parent and from the base at q,
/// once its parent's X0 is known (bodies in topological order).
template <class S>
void place_body(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, int i) {
  const int p = model.parent[i];
  ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
  ws.X0[i] = p < 0 ? ws.Xup[i] : compose(ws.Xup[i], ws.X0[p]);
}

}  // namespace detail

/// Body poses ws.X0 (base to body) and velocities ws.v (body coordinates) at q, v.
template <class S>
void forward_kinematics(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                        std::span<const S> v) {
  for (int i = 0; i < model.nbodies; ++i) {
    const int p = model.parent[i];
    detail::place_body(model, ws, q, i);
    const Motion<S> vJ = joint_motion(model, i, &v[model.v_index[i]]);
    ws.v[i] = p < 0 ? vJ : apply_motion(ws.Xup[i], ws.v[p]) + vJ;
  }
}

/// Sum over bodies of 1/2 v_i . I_i v_i, after forward_kinematics at velocity v, and over the
/// rotors (the armature) of 1/2 armature_k v_k^2: 1/2 v^T M v.
template <class S>
S kinetic_energy(const Model<S>& model, const Workspace<S>& ws, std::span<const S> v) {
  S T{};
  for (int i = 0; i < model.nbodies; ++i) {
    const Force<S> h = mul(model.I[i], ws.v[i]);
    T = T + S(0.5) * (dot(ws.v[i].ang, h.ang) + dot(ws.v[i].lin, h.lin));
  }
  for (std::size_t k = 0; k < model.armature.size(); ++k)
    T = T + S(0.5) * model.armature[k] * v[k] * v[k];
  return T;
}

/// -sum over bodies of m_i gravity . c_i (zero at the base origin), after forward_kinematics:
/// m c = m r + E^T h in base coordinates.
template <class S>
S potential_energy(const Model<S>& model, const Workspace<S>& ws) {
  S V{};
  for (int i = 0; i < model.nbodies; ++i) {
    const Xform<S>& X = ws.X0[i];
    const Vec3<S> mc = scale(X.r, model.I[i].m) + mul_T(X.E, model.I[i].h);
    V = V - dot(model.gravity, mc);
  }
  return V;
}

/// Spatial momentum of all bodies in base coordinates, [angular about the base origin;
/// linear], after forward_kinematics.
template <class S>
Force<S> momentum(const Model<S>& model, const Workspace<S>& ws) {
  Force<S> total{};
  for (int i = 0; i < model.nbodies; ++i)
    total = total + apply_force_T(ws.X0[i], mul(model.I[i], ws.v[i]));
  return total;
}

}  // namespace dyngen
