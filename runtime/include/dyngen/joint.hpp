// Joint model (RBDA sec. 4.4, Table 4.1): the joint transform and the motion subspace S.
// One switch on the joint type, which is model data, so a trace removes it.
#pragma once

#include <cmath>

#include "dyngen/model.hpp"

namespace dyngen {

/// Xup = XJ(q) X_tree for body i (RBDA eq. 4.32 with Table 4.1's XJ).
template <class S>
Xform<S> joint_transform(const Model<S>& model, int i, const S& q) {
  using std::cos;
  using std::sin;
  const Xform<S>& Xt = model.X_tree[i];
  const Mat3<S>& T = Xt.E;
  const Vec3<S>& k = model.joint_axis[i];
  switch (model.joint_type[i]) {
    case JointType::RevoluteX: {
      // rot_x(q) E_tree; k.x = +-1 turns the rotation's sense
      const S c = cos(q), s = k.x * sin(q);
      return {{T.xx, T.xy, T.xz, c * T.yx + s * T.zx, c * T.yy + s * T.zy, c * T.yz + s * T.zz,
               c * T.zx - s * T.yx, c * T.zy - s * T.yy, c * T.zz - s * T.yz},
              Xt.r};
    }
    case JointType::RevoluteY: {
      const S c = cos(q), s = k.y * sin(q);
      return {{c * T.xx - s * T.zx, c * T.xy - s * T.zy, c * T.xz - s * T.zz, T.yx, T.yy, T.yz,
               s * T.xx + c * T.zx, s * T.xy + c * T.zy, s * T.xz + c * T.zz},
              Xt.r};
    }
    case JointType::RevoluteZ: {
      const S c = cos(q), s = k.z * sin(q);
      return {{c * T.xx + s * T.yx, c * T.xy + s * T.yy, c * T.xz + s * T.yz, c * T.yx - s * T.xx,
               c * T.yy - s * T.xy, c * T.yz - s * T.xz, T.zx, T.zy, T.zz},
              Xt.r};
    }
    case JointType::Revolute: {
      // E = c 1 + (1 - c) k k^T - s k x (RBDA eq. 2.24, transposed)
      const S c = cos(q), s = sin(q);
      const S t = S(1) - c;
      const Mat3<S> EJ{t * k.x * k.x + c,       t * k.x * k.y + s * k.z, t * k.x * k.z - s * k.y,
                       t * k.x * k.y - s * k.z, t * k.y * k.y + c,       t * k.y * k.z + s * k.x,
                       t * k.x * k.z + s * k.y, t * k.y * k.z - s * k.x, t * k.z * k.z + c};
      return {mul(EJ, T), Xt.r};
    }
    case JointType::Prismatic:
      // XJ = xlt(k q): r = r_tree + E_tree^T k q
      return {T, Xt.r + mul_T(T, scale(k, q))};
  }
  return Xt;
}

/// S qd
template <class S>
Motion<S> joint_motion(const Model<S>& model, int i, const S& qd) {
  const Vec3<S> w = scale(model.joint_axis[i], qd);
  if (is_revolute(model.joint_type[i])) return {w, {}};
  return {{}, w};
}

/// S^T f
template <class S>
S joint_project(const Model<S>& model, int i, const Force<S>& f) {
  if (is_revolute(model.joint_type[i])) return dot(model.joint_axis[i], f.ang);
  return dot(model.joint_axis[i], f.lin);
}

}  // namespace dyngen
