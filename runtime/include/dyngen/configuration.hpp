// The configuration space's operators, with Pinocchio's conventions: integrate (q moved along a
// tangent vector) and difference (the tangent vector from one configuration to another). They
// differ from q + d and q1 - q0 only at free and ball joints, whose tangents are body-frame
// twists and rotation vectors; the exponential's and logarithm's coefficients come from lie.h.
#pragma once

#include <algorithm>
#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/lie.hpp"
#include "dyngen/trace_hook.hpp"

namespace dyngen {

namespace detail {

/// quat (x) (cos(t/2), sin(t/2)/t w), t = |w|: the rotation times exp([w]), w first.
template <class S>
void quaternion_exp(const S* quat, const Vec3<S>& w, const S& t2, S* out) {
  const S qw = quat[0];
  const Vec3<S> qv{quat[1], quat[2], quat[3]};
  const S e0 = half_cos(t2);
  const Vec3<S> e = scale(w, half_sinc(t2));
  const Vec3<S> v = scale(e, qw) + scale(qv, e0) + cross(qv, e);
  out[0] = qw * e0 - dot(qv, e);
  out[1] = v.x, out[2] = v.y, out[3] = v.z;
}

/// The rotation vector w of conj(quat0) (x) quat1, |w| <= pi (the shorter way round), with
/// |w|^2 in t2.
template <class S>
Vec3<S> quaternion_log(const S* quat0, const S* quat1, S& t2) {
  const Vec3<S> v0{quat0[1], quat0[2], quat0[3]}, v1{quat1[1], quat1[2], quat1[3]};
  const S rw = quat0[0] * quat1[0] + dot(v0, v1);
  const Vec3<S> rv = scale(v1, quat0[0]) - scale(v0, quat1[0]) - cross(v0, v1);
  const S s2 = dot(rv, rv);
  const S k = log_factor(s2, rw);
  t2 = k * k * s2;
  return scale(rv, k);
}

/// V(w) u = u + (1 - cos t)/t^2 w x u + (t - sin t)/t^3 w x (w x u): the translation of the
/// SE(3) exponential of (u, w), t^2 = |w|^2; (1 - cos t)/t^2 = 2 (sin(t/2)/t)^2 keeps every digit.
template <class S>
Vec3<S> se3_translation(const Vec3<S>& u, const Vec3<S>& w, const S& t2) {
  const S h = half_sinc(t2);
  const Vec3<S> wu = cross(w, u);
  return u + scale(wu, S(2) * h * h) + scale(cross(w, wu), exp_c(t2));
}

/// log(M0^-1 M1) of a free joint's poses a and b (position, then quaternion): the twist (u, w),
/// w = log(R0^T R1) the shorter way round and u = V(w)^-1 R0^T (p1 - p0), V^-1 = 1 - [w]/2 +
/// (1 - (t/2) cot(t/2))/t^2 [w]^2; |w|^2 in t2.
template <class S>
Motion<S> se3_log(const S* a, const S* b, S& t2) {
  const Vec3<S> w = quaternion_log(&a[3], &b[3], t2);
  const Vec3<S> dp{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Vec3<S> p = mul_T(quaternion_rotation(a[3], a[4], a[5], a[6]), dp);
  const Vec3<S> wp = cross(w, p);
  return {w, p - scale(wp, S(1) / S(2)) + scale(cross(w, wp), log_alpha(t2))};
}

/// [w], the cross-product matrix.
template <class S>
Mat3<S> skew(const Vec3<S>& w) {
  return {S(0), -w.z, w.y, w.z, S(0), -w.x, -w.y, w.x, S(0)};
}

template <class S>
Mat3<S> scaled(const Mat3<S>& A, const S& k) {
  return {A.xx * k, A.xy * k, A.xz * k, A.yx * k, A.yy * k, A.yz * k, A.zx * k, A.zy * k, A.zz * k};
}

/// 1 + a [w] + b [w]^2: the rotation exp([w]) (a = sin t/t, b = (1 - cos t)/t^2) and the right
/// Jacobians of exp (a = -(1 - cos t)/t^2, b = (t - sin t)/t^3) and of log (a = 1/2, b = alpha).
template <class S>
Mat3<S> so3_matrix(const Vec3<S>& w, const S& a, const S& b) {
  const Mat3<S> W = skew(w);
  const Mat3<S> one{S(1), S(0), S(0), S(0), S(1), S(0), S(0), S(0), S(1)};
  return one + scaled(W, a) + scaled(mul(W, W), b);
}

/// The coupling block of the SE(3) exponential's right Jacobian [[Jr(w), Q], [0, Jr(w)]] at the
/// twist (u, w) (Barfoot's Q(rho, phi) of the left Jacobian at (-u, -w)): -[u]/2 + c ([w][u] +
/// [u][w] - [w][u][w]) - d ([w]^2[u] + [u][w]^2 - 3 [w][u][w]) + e ([w][u][w]^2 +
/// [w]^2[u][w]), with c, d, e lie.h's exp_c, exp_d, exp_e.
template <class S>
Mat3<S> se3_coupling(const Vec3<S>& u, const Vec3<S>& w, const S& t2) {
  const Mat3<S> U = skew(u), W = skew(w);
  const Mat3<S> WU = mul(W, U), UW = mul(U, W), WW = mul(W, W), WUW = mul(WU, W);
  return scaled(U, S(-1) / S(2)) + scaled(WU + UW - WUW, exp_c(t2)) -
         scaled(mul(WW, U) + mul(U, WW) - scaled(WUW, S(3)), exp_d(t2)) +
         scaled(mul(WUW, W) + mul(WW, UW), exp_e(t2));
}

/// Writes A into rows r.., columns c.. of the row-major n x n matrix out.
template <class S>
void put_block(std::span<S> out, int n, int r, int c, const Mat3<S>& A) {
  const S rows[3][3] = {{A.xx, A.xy, A.xz}, {A.yx, A.yy, A.yz}, {A.zx, A.zy, A.zz}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[static_cast<std::size_t>((r + i) * n + c + j)] = rows[i][j];
}

/// The right Jacobian of the SE(3) logarithm at the twist (u, w) (sign -1: at (-u, -w)):
/// [[J, -J Q J], [0, J]] with J = 1 + [w]/2 + alpha [w]^2 the inverse of Jr(w), written at
/// (r, r) of out and scaled by sign.
template <class S>
void put_se3_log_jacobian(std::span<S> out, int n, int r, Vec3<S> u, Vec3<S> w, const S& t2,
                          const S& sign) {
  u = scale(u, sign), w = scale(w, sign);
  const Mat3<S> J = so3_matrix(w, S(1) / S(2), log_alpha(t2));
  const Mat3<S> JQJ = mul(mul(J, se3_coupling(u, w, t2)), J);
  put_block(out, n, r, r, scaled(J, sign));
  put_block(out, n, r, r + 3, scaled(JQJ, -sign));
  put_block(out, n, r + 3, r + 3, scaled(J, sign));
}
}  // namespace detail

/// q (+) d: q moved by the tangent vector d (nv entries, in v's order): q + d for 1-DoF joints;
/// for a free joint its pose M = (R, p) times exp(d) with d = (linear, angular) in the body's own
/// frame: R exp([w]) and p + R V(w) d_lin (the SE(3) exponential; V = 1 + (1 - cos t)/t^2 [w] +
/// (t - sin t)/t^3 [w]^2, t = |w|), the quaternion times (cos(t/2), sin(t/2) w/t); for a ball
/// joint R exp([w]) alone. This is the perturbation of the derivatives' free and ball columns
/// (rnea_derivatives), and with d = v dt it integrates a constant body velocity exactly.
template <class S>
void integrate(const Model<S>& model, std::span<const S> q, std::span<const S> d,
               std::span<S> out) {
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Configuration);
    const S* qi = &q[model.q_index[i]];
    const S* di = &d[model.v_index[i]];
    S* o = &out[model.q_index[i]];
    const int k = quaternion_offset(model.joint_type[i]);
    if (k < 0) {
      o[0] = qi[0] + di[0];
      continue;
    }
    const Vec3<S> w{di[k], di[k + 1], di[k + 2]};
    const S t2 = dot(w, w);
    if (k > 0) {  // p + R V(w) u
      const Vec3<S> Vu = detail::se3_translation(Vec3<S>{di[0], di[1], di[2]}, w, t2);
      const Vec3<S> p =
          Vec3<S>{qi[0], qi[1], qi[2]} + mul(quaternion_rotation(qi[3], qi[4], qi[5], qi[6]), Vu);
      o[0] = p.x, o[1] = p.y, o[2] = p.z;
    }
    detail::quaternion_exp(&qi[k], w, t2, &o[k]);
  }
}

/// The tangent vector d with integrate(q0, d) = q1 (nv entries): q1 - q0 for 1-DoF joints; for
/// a free joint log(M0^-1 M1), the SE(3) logarithm in q0's body frame: w = log(R0^T R1) and
/// V(w)^-1 R0^T (p1 - p0), V^-1 = 1 - [w]/2 + (1 - (t/2) cot(t/2))/t^2 [w]^2; for a ball joint
/// log(R0^T R1). Rotations go the shorter way round (|w| <= pi).
template <class S>
void difference(const Model<S>& model, std::span<const S> q0, std::span<const S> q1,
                std::span<S> out) {
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Configuration);
    const S* a = &q0[model.q_index[i]];
    const S* b = &q1[model.q_index[i]];
    S* o = &out[model.v_index[i]];
    const int k = quaternion_offset(model.joint_type[i]);
    if (k < 0) {
      o[0] = b[0] - a[0];
      continue;
    }
    S t2;
    if (k == 0) {
      const Vec3<S> w = detail::quaternion_log(a, b, t2);
      o[0] = w.x, o[1] = w.y, o[2] = w.z;
      continue;
    }
    const Motion<S> d = detail::se3_log(a, b, t2);
    o[0] = d.lin.x, o[1] = d.lin.y, o[2] = d.lin.z;
    o[3] = d.ang.x, o[4] = d.ang.y, o[5] = d.ang.z;
  }
}

/// The Jacobians of q_plus = integrate(q, v) (Pinocchio's dIntegrate), row-major nv x nv, block
/// diagonal: by q (a tangent step of q) and by v. 1-DoF joints: 1 and 1. A free joint: the
/// adjoint of exp(v)^-1, [[R^T, -R^T [p]], [0, R^T]] with (R, p) = exp(v), and the SE(3)
/// exponential's right Jacobian [[Jr(w), Q], [0, Jr(w)]]. A ball joint: R^T and Jr(w).
template <class S>
void integrate_derivatives(const Model<S>& model, std::span<const S> q, std::span<const S> v,
                           std::span<S> dq, std::span<S> dv) {
  static_cast<void>(q);  // the Jacobians in tangent coordinates do not depend on q
  const int n = model.nv;
  std::fill(dq.begin(), dq.end(), S(0));
  std::fill(dv.begin(), dv.end(), S(0));
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Configuration);
    const int j = model.v_index[i];
    const int k = quaternion_offset(model.joint_type[i]);
    if (k < 0) {
      dq[static_cast<std::size_t>(j * n + j)] = S(1);
      dv[static_cast<std::size_t>(j * n + j)] = S(1);
      continue;
    }
    const Vec3<S> w{v[j + k], v[j + k + 1], v[j + k + 2]};
    const S t2 = dot(w, w), h = half_sinc(t2), b = S(2) * h * h;
    const Vec3<S> e = scale(w, h);
    const Mat3<S> RT = transpose(quaternion_rotation(half_cos(t2), e.x, e.y, e.z));
    const Mat3<S> Jr = detail::so3_matrix(w, S(-b), exp_c(t2));
    detail::put_block(dq, n, j + k, j + k, RT);
    detail::put_block(dv, n, j + k, j + k, Jr);
    if (k == 0) continue;
    const Vec3<S> u{v[j], v[j + 1], v[j + 2]};
    const Vec3<S> p = detail::se3_translation(u, w, t2);
    detail::put_block(dq, n, j, j, RT);
    detail::put_block(dq, n, j, j + 3, detail::scaled(mul_skew(RT, p), S(-1)));
    detail::put_block(dv, n, j, j, Jr);
    detail::put_block(dv, n, j, j + 3, detail::se3_coupling(u, w, t2));
  }
}

/// The Jacobians of delta = difference(q, q_target) (Pinocchio's dDifference), row-major nv x
/// nv, block diagonal: by q and by q_target (tangent steps). 1-DoF joints: -1 and 1. Free and ball
/// joints, at their delta: -Jlog(-delta) and Jlog(delta), Jlog the right Jacobian of the
/// logarithm (SE(3)'s for a free joint, SO(3)'s 1 + [w]/2 + alpha [w]^2 for a ball joint).
template <class S>
void difference_derivatives(const Model<S>& model, std::span<const S> q,
                            std::span<const S> q_target, std::span<S> dq, std::span<S> dq_target) {
  const int n = model.nv;
  std::fill(dq.begin(), dq.end(), S(0));
  std::fill(dq_target.begin(), dq_target.end(), S(0));
  for (int i = 0; i < model.nbodies; ++i) {
    TraceHook<S>::enter(i, Pass::Configuration);
    const S* a = &q[model.q_index[i]];
    const S* b = &q_target[model.q_index[i]];
    const int j = model.v_index[i];
    const int k = quaternion_offset(model.joint_type[i]);
    if (k < 0) {
      dq[static_cast<std::size_t>(j * n + j)] = S(-1);
      dq_target[static_cast<std::size_t>(j * n + j)] = S(1);
      continue;
    }
    S t2;
    if (k == 0) {
      const Vec3<S> w = detail::quaternion_log(a, b, t2);
      const S alpha = log_alpha(t2);
      detail::put_block(dq, n, j, j,
                        detail::scaled(detail::so3_matrix(w, S(-1) / S(2), alpha), S(-1)));
      detail::put_block(dq_target, n, j, j, detail::so3_matrix(w, S(1) / S(2), alpha));
      continue;
    }
    const Motion<S> d = detail::se3_log(a, b, t2);
    detail::put_se3_log_jacobian(dq, n, j, d.lin, d.ang, t2, S(-1));
    detail::put_se3_log_jacobian(dq_target, n, j, d.lin, d.ang, t2, S(1));
  }
}

}  // namespace dyngen
