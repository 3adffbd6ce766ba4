// Kinematics for integrators and for checking them: the time derivative of q, which differs
// from v only at free and ball joints (a quaternion has four entries and three rates), the
// projection of an integrated q back onto unit quaternions, body poses and velocities, and the
// energies and momentum that a simulation should conserve.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>

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

/// q (+) d: q moved by the tangent vector d (nv entries, in v's order): q + d for 1-DoF joints;
/// for a free joint its pose M = (R, p) times exp(d) with d = (linear, angular) in the body's own
/// frame: R exp([w]) and p + R V(w) d_lin (the SE(3) exponential; V = 1 + (1 - cos t)/t^2 [w] +
/// (t - sin t)/t^3 [w]^2, t = |w|), the quaternion times (cos(t/2), sin(t/2) w/t); for a ball
/// joint R exp([w]) alone. This is the perturbation of the derivatives' free and ball columns
/// (rnea_derivatives), and with d = v dt it integrates a constant body velocity exactly.
template <class S>
void integrate(const Model<S>& model, std::span<const S> q, std::span<const S> d,
               std::span<S> out) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  for (int i = 0; i < model.nbodies; ++i) {
    const S* qi = &q[model.q_index[i]];
    const S* di = &d[model.v_index[i]];
    S* o = &out[model.q_index[i]];
    const int k = quaternion_offset(model.joint_type[i]);
    if (k < 0) {
      o[0] = qi[0] + di[0];
      continue;
    }
    const Vec3<S> w{di[k], di[k + 1], di[k + 2]};
    const S t2 = dot(w, w), t = sqrt(t2);
    // (1 - cos t)/t^2, (t - sin t)/t^3 and sin(t/2)/t, by their series below t = 1e-4
    const bool small = t < S(1e-4);
    const S h = small ? S(0.5) - t2 / S(48) : sin(t / S(2)) / t;
    if (k > 0) {
      const Vec3<S> u{di[0], di[1], di[2]};
      const S b = small ? S(0.5) - t2 / S(24) : (S(1) - cos(t)) / t2;
      const S c = small ? S(1) / S(6) - t2 / S(120) : (t - sin(t)) / (t2 * t);
      const Vec3<S> wu = cross(w, u);
      const Vec3<S> Vu = u + scale(wu, b) + scale(cross(w, wu), c);
      const Mat3<S> R = quaternion_rotation(qi[3], qi[4], qi[5], qi[6]);
      const Vec3<S> p = Vec3<S>{qi[0], qi[1], qi[2]} + mul(R, Vu);
      o[0] = p.x, o[1] = p.y, o[2] = p.z;
    }
    // quat (x) (cos(t/2), h w)
    const S qw = qi[k];
    const Vec3<S> qv{qi[k + 1], qi[k + 2], qi[k + 3]};
    const S e0 = cos(t / S(2));
    const Vec3<S> e = scale(w, h);
    const Vec3<S> v = scale(e, qw) + scale(qv, e0) + cross(qv, e);
    o[k] = qw * e0 - dot(qv, e);
    o[k + 1] = v.x, o[k + 2] = v.y, o[k + 3] = v.z;
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
