// Frames: where the model's named frames are (forward kinematics, RBDA sec. 4.2), their
// Jacobians, the map from v to each frame's velocity (a column per joint on the frame's path to
// the base, RBDA sec. 8.4), and their bias accelerations Jdot v; and the robot's centre of mass,
// its Jacobian and the centroidal momentum matrix. Matrices are row-major; per frame f,
// R[9 f + 3 i + j] and p[3 f + i], J[(6 f + row) nv + column] and Jdot_v[6 f + row], with the
// linear rows first, then the angular ones.
#pragma once

#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/kinematics.hpp"
#include "dyngen/trace_hook.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// The axes a Jacobian's rows are expressed in: the base's (at the frame's origin, Pinocchio's
/// LOCAL_WORLD_ALIGNED) or the frame's own (LOCAL).
enum class JacobianAxes { World, Local };

namespace detail {

/// e = x, or e += x where a mimic joint shares the column (Workspace::shares_column)
template <class S>
void put_entry(bool add, S& e, const S& x) {
  e = add ? e + x : x;
}

/// Zeros the columns that mimic joints share in a matrix of `rows` x nv, row-major, which
/// put_entry then adds to.
template <class S>
void clear_shared_columns(const Model<S>& model, const Workspace<S>& ws, int rows,
                          std::span<S> A) {
  for (int j = 0; j < model.nbodies; ++j)
    if (ws.shares_column[j])
      for (int row = 0; row < rows; ++row) A[row * model.nv + model.v_index[j]] = S(0);
}

/// ws.X0[i] = X_i0, the base-to-body transform of every body at q.
template <class S>
void body_placements(const Model<S>& model, Workspace<S>& ws, std::span<const S> q) {
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Kinematics);
    place_body(model, ws, q, i);
  }
}

/// X_f0 = X_fb X_b0, the base-to-frame transform, after body_placements.
template <class S>
Xform<S> frame_transform(const Model<S>& model, const Workspace<S>& ws, int f) {
  const Frame<S>& frame = model.frames[f];
  return frame.body < 0 ? frame.placement : compose(frame.placement, ws.X0[frame.body]);
}

}  // namespace detail

/// Each frame's rotation R (its axes as columns in base coordinates: R = E^T of X_f0) and origin
/// p (base coordinates) at q.
template <class S>
void frame_placements(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                      std::span<S> R, std::span<S> p) {
  detail::body_placements(model, ws, q);
  for (int f = 0; f < static_cast<int>(model.frames.size()); ++f) {
    TraceHook<S>::enter(model.frames[f].body, Pass::Frames);
    const Xform<S> X = detail::frame_transform(model, ws, f);
    const Mat3<S>& E = X.E;
    S* Rf = &R[9 * f];
    Rf[0] = E.xx, Rf[1] = E.yx, Rf[2] = E.zx;
    Rf[3] = E.xy, Rf[4] = E.yy, Rf[5] = E.zy;
    Rf[6] = E.xz, Rf[7] = E.yz, Rf[8] = E.zz;
    p[3 * f] = X.r.x, p[3 * f + 1] = X.r.y, p[3 * f + 2] = X.r.z;
  }
}

namespace detail {

/// Writes the Jacobian of a frame on body b, placed at X (base to frame), into J's rows (6 x nv
/// row-major, linear first; only the first `rows`), or with `subtract` takes it from them: in
/// base axes at the frame's origin or in its own. Column c of joint j on b's path to the base is
/// j's motion subspace column s in base coordinates, s0 = X_j0^-1 s (a motion at the base
/// origin), moved to the frame's origin p: (s0.lin + s0.ang x p, s0.ang); the other columns are
/// untouched, and those that mimic joints share are added to. After body_placements.
template <class S>
void put_frame_jacobian(const Model<S>& model, const Workspace<S>& ws, int b, const Xform<S>& X,
                        JacobianAxes axes, int rows, bool subtract, S* J) {
  const int nv = model.nv;
  for (int j = b; j >= 0; j = model.parent[j]) {
    TraceHook<S>::enter(j, Pass::JacobianColumns);
    for (int d = 0; d < joint_nv(model.joint_type[j]); ++d) {
      const Motion<S> s0 = apply_motion_inv(ws.X0[j], joint_column(model, j, d));
      Vec3<S> lin = s0.lin + cross(s0.ang, X.r), ang = s0.ang;
      if (axes == JacobianAxes::Local) lin = mul(X.E, lin), ang = mul(X.E, ang);
      const int c = model.v_index[j] + d;
      const S column[6] = {lin.x, lin.y, lin.z, ang.x, ang.y, ang.z};
      for (int row = 0; row < rows; ++row) {
        S& e = J[row * nv + c];
        if (subtract)
          e = e - column[row];
        else
          put_entry(ws.shares_column[j], e, column[row]);
      }
    }
  }
}

}  // namespace detail

/// Each frame's Jacobian at q: J v = (velocity of the frame's origin, angular velocity), in the
/// base's axes or the frame's own (detail::put_frame_jacobian); columns of joints off the
/// frame's path to the base are zero.
template <class S>
void frame_jacobians(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                     JacobianAxes axes, std::span<S> J) {
  detail::body_placements(model, ws, q);
  const int nv = model.nv;
  for (int f = 0; f < static_cast<int>(model.frames.size()); ++f) {
    S* Jf = &J[6 * static_cast<std::size_t>(f) * nv];
    for (int e = 0; e < 6 * nv; ++e) Jf[e] = S(0);
    TraceHook<S>::enter(model.frames[f].body, Pass::Frames);
    const Xform<S> X = detail::frame_transform(model, ws, f);
    detail::put_frame_jacobian(model, ws, model.frames[f].body, X, axes, 6, false, Jf);
  }
}

namespace detail {

/// The bodies' velocities ws.v and spatial accelerations ws.a at qdd (empty: 0), in base
/// coordinates, and their placements: a joint's motion vJ0 = X_i0^-1 vJ turns with its body,
/// v_i = v_p + vJ0, a_i = a_p + aJ0 + v_p x vJ0 (RBDA eq. 5.7, as v_i x vJ0 = v_p x vJ0).
template <class S>
void body_bias_accelerations(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                             std::span<const S> v, std::span<const S> qdd = {}) {
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Velocity);
    const int p = model.parent[i];
    place_body(model, ws, q, i);
    const int k = model.v_index[i];
    const Motion<S> vJ0 = apply_motion_inv(ws.X0[i], joint_motion(model, i, &v[k]));
    const Motion<S> aJ0 =
        qdd.empty() ? Motion<S>{} : apply_motion_inv(ws.X0[i], joint_motion(model, i, &qdd[k]));
    if (p < 0) {
      ws.v[i] = vJ0;
      ws.a[i] = qdd.empty() ? Motion<S>{} : aJ0;  // the base does not move
    } else {
      ws.v[i] = ws.v[p] + vJ0;
      ws.a[i] = qdd.empty() ? ws.a[p] + cross_motion(ws.v[p], vJ0)
                            : ws.a[p] + aJ0 + cross_motion(ws.v[p], vJ0);
    }
  }
}

/// The velocity of the origin p = X.r of a frame on body b, and its angular velocity, in base
/// axes, after body_bias_accelerations (the base, b = -1, does not move).
template <class S>
Motion<S> frame_velocity(const Workspace<S>& ws, int b, const Xform<S>& X) {
  if (b < 0) return {};
  const Motion<S>& v0 = ws.v[b];
  return {v0.ang, v0.lin + cross(v0.ang, X.r)};
}

/// The classical acceleration of that origin and the frame's angular acceleration at qdd = 0,
/// in base axes, after body_bias_accelerations: a.lin + a.ang x p + w x (v.lin + w x p).
template <class S>
Motion<S> frame_bias_acceleration(const Workspace<S>& ws, int b, const Xform<S>& X) {
  if (b < 0) return {};
  const Motion<S>& v0 = ws.v[b];
  const Motion<S>& a0 = ws.a[b];
  const Vec3<S> v_origin = v0.lin + cross(v0.ang, X.r);
  return {a0.ang, a0.lin + cross(a0.ang, X.r) + cross(v0.ang, v_origin)};
}

}  // namespace detail

/// Each frame's bias acceleration at q, v: the classical acceleration of its origin and its
/// angular acceleration at qdd = 0, 6 per frame (linear first), so that a frame's acceleration is
/// J qdd + this (Jdot v); in the base's axes or the frame's own
/// (detail::frame_bias_acceleration).
template <class S>
void frame_bias_accelerations(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                              std::span<const S> v, JacobianAxes axes, std::span<S> out) {
  detail::body_bias_accelerations(model, ws, q, v);
  for (int f = 0; f < static_cast<int>(model.frames.size()); ++f) {
    S* o = &out[6 * f];
    const int b = model.frames[f].body;
    TraceHook<S>::enter(b, Pass::Frames);
    const Xform<S> X = b < 0 ? Xform<S>{} : detail::frame_transform(model, ws, f);
    const Motion<S> a = detail::frame_bias_acceleration(ws, b, X);
    Vec3<S> lin = a.lin, ang = a.ang;
    if (axes == JacobianAxes::Local) lin = mul(X.E, lin), ang = mul(X.E, ang);
    o[0] = lin.x, o[1] = lin.y, o[2] = lin.z, o[3] = ang.x, o[4] = ang.y, o[5] = ang.z;
  }
}

namespace detail {

/// ws.Ic[i]: the inertia of body i's subtree in its own coordinates (CRBA's composite inertias,
/// RBDA eq. 6.4: Ic_p += Xup_i^T Ic_i Xup_i), after body_placements; returns the robot's
/// inertia in base coordinates, about the base origin. Carried up through the joints' own
/// transforms, which hold the model's constants, rather than through X_i0.
template <class S>
RigidInertia<S> composite_inertias(const Model<S>& model, Workspace<S>& ws) {
  for (int i = 0; i < model.nbodies; ++i) ws.Ic[i] = model.I[i];
  RigidInertia<S> total{};
  for (int i = model.nbodies - 1; i >= 0; --i) {
    TraceHook<S>::enter(i, Pass::CompositeInertia);
    const int p = model.parent[i];
    if (p >= 0) ws.Ic[p] = ws.Ic[p] + apply_inertia_T(ws.Xup[i], ws.Ic[i]);
    else total = total + apply_inertia_T(ws.X0[i], ws.Ic[i]);
  }
  return total;
}

}  // namespace detail

/// The centre of mass c (base coordinates) and its Jacobian Jc (3 x nv, row-major) at q. Column
/// of joint j: the linear momentum of j's subtree moving with the joint's column, over the
/// total mass M. It is the centre of the moving bodies: a fixed base and the links welded to it
/// are not in the model. A robot without mass has none.
template <class S>
void com(const Model<S>& model, Workspace<S>& ws, std::span<const S> q, std::span<S> c,
         std::span<S> Jc) {
  detail::body_placements(model, ws, q);
  const RigidInertia<S> total = detail::composite_inertias(model, ws);
  const S inverse_mass = S(1) / total.m;
  c[0] = total.h.x * inverse_mass, c[1] = total.h.y * inverse_mass, c[2] = total.h.z * inverse_mass;
  const int nv = model.nv;
  detail::clear_shared_columns(model, ws, 3, Jc);
  for (int j = 0; j < model.nbodies; ++j) {
    TraceHook<S>::enter(j, Pass::JacobianColumns);
    for (int d = 0; d < joint_nv(model.joint_type[j]); ++d) {
      const Force<S> Fj = mul(ws.Ic[j], joint_column(model, j, d));
      const Vec3<S> column = scale(mul_T(ws.X0[j].E, Fj.lin), inverse_mass);
      const int k = model.v_index[j] + d;
      const bool add = ws.shares_column[j];
      detail::put_entry(add, Jc[k], column.x);
      detail::put_entry(add, Jc[nv + k], column.y);
      detail::put_entry(add, Jc[2 * nv + k], column.z);
    }
  }
}

/// The centroidal momentum matrix A (6 x nv, row-major) and momentum h = A v at q, v (Orin,
/// Goswami & Lee 2013): the linear momentum and the angular momentum about the centre of mass,
/// in the base's axes (linear rows first). Column of joint j: the momentum of j's subtree moving
/// with the joint's column, Ic_j s, in base axes about the centre of mass: X_j0^T Ic_j s with
/// the moment taken about c instead of the base origin, E^T n + (r - c) x E^T f.
template <class S>
void centroidal(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                std::span<const S> v, std::span<S> A, std::span<S> h) {
  detail::body_placements(model, ws, q);
  const RigidInertia<S> total = detail::composite_inertias(model, ws);
  const Vec3<S> c = scale(total.h, S(1) / total.m);
  const int nv = model.nv;
  for (int e = 0; e < 6; ++e) h[e] = S(0);
  detail::clear_shared_columns(model, ws, 6, A);
  for (int j = 0; j < model.nbodies; ++j) {
    TraceHook<S>::enter(j, Pass::JacobianColumns);
    const Mat3<S>& E = ws.X0[j].E;
    const Vec3<S> arm = ws.X0[j].r - c;  // from the centre of mass to body j's origin
    for (int d = 0; d < joint_nv(model.joint_type[j]); ++d) {
      const Force<S> F = mul(ws.Ic[j], joint_column(model, j, d));
      const Vec3<S> linear = mul_T(E, F.lin);
      const Vec3<S> angular = mul_T(E, F.ang) + cross(arm, linear);
      const int k = model.v_index[j] + d;
      const S column[6] = {linear.x, linear.y, linear.z, angular.x, angular.y, angular.z};
      for (int row = 0; row < 6; ++row) {
        detail::put_entry(ws.shares_column[j], A[row * nv + k], column[row]);
        h[row] = h[row] + column[row] * v[k];
      }
    }
  }
}

}  // namespace dyngen
