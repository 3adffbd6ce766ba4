// Joint model (RBDA sec. 4.4, Table 4.1): the joint transform and the motion subspace S.
// One switch on the joint type, which is model data, so a trace removes it. Each function
// takes the joint's own entries: q + q_index[i], v + v_index[i].
#pragma once

#include <cmath>

#include "dyngen/model.hpp"
#include "dyngen/sincos.hpp"

namespace dyngen {

/// s = sin(q), c = cos(q). float and double use dyngen::sincos (sincos.h), which the generated
/// code also calls, so that both agree to the bit; other scalars (the generator's symbolic one, MPFR,
/// long double) use their own sin and cos.
template <class S>
void joint_sincos(const S& q, S& s, S& c) {
  using std::cos;
  using std::sin;
  s = sin(q);
  c = cos(q);
}
inline void joint_sincos(double q, double& s, double& c) { sincos(q, s, c); }
inline void joint_sincos(float q, float& s, float& c) { sincos(q, s, c); }

/// a_0 = -a_grav: gravity enters the recursions as an upward acceleration of the base
template <class S>
Motion<S> base_acceleration(const Model<S>& model) {
  return {{}, {-model.gravity.x, -model.gravity.y, -model.gravity.z}};
}

/// s = sin(q), c = cos(q) of body i's angle q; a mirroring mimic joint's (Model::mimic_mirrors)
/// from its primary's entry qi[0]: sin(-x) = -sin(x), cos(-x) = cos(x), so that generated code
/// takes sin and cos of q's entries only.
template <class S>
void angle_sincos(const Model<S>& model, int i, const S* qi, const S& q, S& s, S& c) {
  if (!is_mimic(model, i) || !model.mimic_mirrors[i]) return joint_sincos(q, s, c);
  joint_sincos(qi[0], s, c);
  s = -s;
}

/// Xup = XJ(q) X_tree for body i (RBDA eq. 4.32 with Table 4.1's XJ).
template <class S>
Xform<S> joint_transform(const Model<S>& model, int i, const S* qi) {
  const Xform<S>& Xt = model.X_tree[i];
  const Mat3<S>& T = Xt.E;
  const Vec3<S>& k = model.joint_axis[i];
  const S q = joint_position(model, i, qi[0]);  // a mimic joint's from its primary's
  switch (model.joint_type[i]) {
    case JointType::RevoluteX: {
      // rot_x(q) E_tree; k.x = +-1 turns the rotation's sense
      S c, s;
      angle_sincos(model, i, qi, q, s, c);
      s = k.x * s;
      return {{T.xx, T.xy, T.xz, c * T.yx + s * T.zx, c * T.yy + s * T.zy, c * T.yz + s * T.zz,
               c * T.zx - s * T.yx, c * T.zy - s * T.yy, c * T.zz - s * T.yz},
              Xt.r};
    }
    case JointType::RevoluteY: {
      S c, s;
      angle_sincos(model, i, qi, q, s, c);
      s = k.y * s;
      return {{c * T.xx - s * T.zx, c * T.xy - s * T.zy, c * T.xz - s * T.zz, T.yx, T.yy, T.yz,
               s * T.xx + c * T.zx, s * T.xy + c * T.zy, s * T.xz + c * T.zz},
              Xt.r};
    }
    case JointType::RevoluteZ: {
      S c, s;
      angle_sincos(model, i, qi, q, s, c);
      s = k.z * s;
      return {{c * T.xx + s * T.yx, c * T.xy + s * T.yy, c * T.xz + s * T.yz, c * T.yx - s * T.xx,
               c * T.yy - s * T.xy, c * T.yz - s * T.xz, T.zx, T.zy, T.zz},
              Xt.r};
    }
    case JointType::Revolute: {
      // E = c 1 + (1 - c) k k^T - s k x (RBDA eq. 2.24, transposed)
      S c, s;
      angle_sincos(model, i, qi, q, s, c);
      const S t = S(1) - c;
      const Mat3<S> EJ{t * k.x * k.x + c,       t * k.x * k.y + s * k.z, t * k.x * k.z - s * k.y,
                       t * k.x * k.y - s * k.z, t * k.y * k.y + c,       t * k.y * k.z + s * k.x,
                       t * k.x * k.z + s * k.y, t * k.y * k.z - s * k.x, t * k.z * k.z + c};
      return {mul(EJ, T), Xt.r};
    }
    case JointType::Prismatic:
      // XJ = xlt(k q): r = r_tree + E_tree^T k q
      return {T, Xt.r + mul_T(T, scale(k, q))};
    case JointType::Free: {
      // XJ = rot(R^T) xlt(p) with R the rotation of the unit quaternion (w, x, y, z)
      const Vec3<S> p{qi[0], qi[1], qi[2]};
      const Mat3<S> RT = transpose(quaternion_rotation(qi[3], qi[4], qi[5], qi[6]));
      return {mul(RT, T), Xt.r + mul_T(T, p)};
    }
    case JointType::Ball:
      // XJ = rot(R^T): the free joint's rotation about the joint origin
      return {mul(transpose(quaternion_rotation(qi[0], qi[1], qi[2], qi[3])), T), Xt.r};
  }
  return Xt;
}

/// S qd, from the joint's velocity entries
template <class S>
Motion<S> joint_motion(const Model<S>& model, int i, const S* qd) {
  if (model.joint_type[i] == JointType::Free)
    return {{qd[3], qd[4], qd[5]}, {qd[0], qd[1], qd[2]}};
  if (model.joint_type[i] == JointType::Ball) return {{qd[0], qd[1], qd[2]}, {}};
  const Vec3<S> w = scale(model.joint_axis[i],
                          is_mimic(model, i) ? model.mimic_multiplier[i] * qd[0] : qd[0]);
  if (is_revolute(model.joint_type[i])) return {w, {}};
  return {{}, w};
}

/// Whether column d of S is a pure translation: a prismatic joint's, or one of a free joint's
/// first three (joint_motion's layout, linear before angular)
inline bool is_translation_column(JointType type, int d) {
  return type == JointType::Prismatic || (type == JointType::Free && d < 3);
}

/// Column d of S
template <class S>
Motion<S> joint_column(const Model<S>& model, int i, int d) {
  S e[6]{};
  e[d] = S(1);
  return joint_motion(model, i, e);
}

/// S^T f, into the joint's entries of out (a mimic joint's share of its primary's entry: the
/// caller adds it)
template <class S>
void joint_project(const Model<S>& model, int i, const Force<S>& f, S* out) {
  switch (model.joint_type[i]) {
    case JointType::Free:
      out[0] = f.lin.x, out[1] = f.lin.y, out[2] = f.lin.z;
      out[3] = f.ang.x, out[4] = f.ang.y, out[5] = f.ang.z;
      return;
    case JointType::Ball:
      out[0] = f.ang.x, out[1] = f.ang.y, out[2] = f.ang.z;
      return;
    case JointType::Prismatic:
      out[0] = dot(model.joint_axis[i], f.lin);
      break;
    default:
      out[0] = dot(model.joint_axis[i], f.ang);
  }
  // a mimic joint's column of S is its multiplier times the axis's
  if (is_mimic(model, i)) out[0] = model.mimic_multiplier[i] * out[0];
}

/// S tau: the joint's entries of tau as a spatial force (S maps them as it maps velocities)
template <class S>
Force<S> joint_force(const Model<S>& model, int i, const S* tau) {
  const Motion<S> m = joint_motion(model, i, tau);
  return {m.ang, m.lin};
}

}  // namespace dyngen
