// Spatial algebra with explicit scalar arithmetic in a fixed order.
//
// Every kernel spells out its operations so that runtime<double> and the symbolic trace
// (generator/) perform the same floating-point operations in the same order. Conventions
// follow Featherstone, "Rigid Body Dynamics Algorithms" (RBDA): spatial vectors are
// [angular; linear]; X = rot(E) * xlt(r), where E maps parent to child coordinates and r is
// the child origin in parent coordinates (RBDA sec. 2.8).
#pragma once

namespace dyngen {

template <class S>
struct Vec3 {
  S x{}, y{}, z{};
};

/// 3x3 matrix, row-major.
template <class S>
struct Mat3 {
  S xx{}, xy{}, xz{}, yx{}, yy{}, yz{}, zx{}, zy{}, zz{};
};

/// Symmetric 3x3 matrix (upper triangle).
template <class S>
struct Sym3 {
  S xx{}, yy{}, zz{}, xy{}, xz{}, yz{};
};

/// Spatial motion vector [w; v].
template <class S>
struct Motion {
  Vec3<S> ang, lin;
};

/// Spatial force vector [n; f].
template <class S>
struct Force {
  Vec3<S> ang, lin;
};

/// Plucker transform X = rot(E) xlt(r).
template <class S>
struct Xform {
  Mat3<S> E;
  Vec3<S> r;
};

/// Rigid-body inertia about the frame origin: mass m, first moment h = m c, rotational
/// inertia I about the origin. Composite inertias add component-wise (RBDA sec. 2.13).
template <class S>
struct RigidInertia {
  S m{};
  Vec3<S> h;
  Sym3<S> I;
};

/// Articulated-body inertia [I H; H^T M], symmetric 6x6 (RBDA sec. 7.1).
template <class S>
struct ArticulatedInertia {
  Sym3<S> I;
  Mat3<S> H;
  Sym3<S> M;
};

/// The linear map B x = v x* (I x) - I (v x x) + x x* (I v) of a rigid-body inertia I moving
/// with velocity v: the derivative of I's force I a + v x* I v along a change x of v, less I
/// times the change of a. Its symmetric part is dI/dt = v x* I - I v x, a rigid-body inertia of
/// mass 0 (hdot, Idot); the rest is x x* p with p = I v, skew. Variations add like inertias.
template <class S>
struct InertiaVariation {
  Vec3<S> hdot;
  Sym3<S> Idot;
  Force<S> p;
};

// ---- 3-vectors and 3x3 matrices -------------------------------------------------------

template <class S>
Vec3<S> operator+(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}

template <class S>
Vec3<S> operator-(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}

template <class S>
Vec3<S> scale(const Vec3<S>& a, const S& k) {
  return {a.x * k, a.y * k, a.z * k};
}

template <class S>
S dot(const Vec3<S>& a, const Vec3<S>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <class S>
Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// E v
template <class S>
Vec3<S> mul(const Mat3<S>& E, const Vec3<S>& v) {
  return {E.xx * v.x + E.xy * v.y + E.xz * v.z, E.yx * v.x + E.yy * v.y + E.yz * v.z,
          E.zx * v.x + E.zy * v.y + E.zz * v.z};
}

/// E^T v
template <class S>
Vec3<S> mul_T(const Mat3<S>& E, const Vec3<S>& v) {
  return {E.xx * v.x + E.yx * v.y + E.zx * v.z, E.xy * v.x + E.yy * v.y + E.zy * v.z,
          E.xz * v.x + E.yz * v.y + E.zz * v.z};
}

/// A v for symmetric A
template <class S>
Vec3<S> mul(const Sym3<S>& A, const Vec3<S>& v) {
  return {A.xx * v.x + A.xy * v.y + A.xz * v.z, A.xy * v.x + A.yy * v.y + A.yz * v.z,
          A.xz * v.x + A.yz * v.y + A.zz * v.z};
}

/// A B
template <class S>
Mat3<S> mul(const Mat3<S>& A, const Mat3<S>& B) {
  return {A.xx * B.xx + A.xy * B.yx + A.xz * B.zx, A.xx * B.xy + A.xy * B.yy + A.xz * B.zy,
          A.xx * B.xz + A.xy * B.yz + A.xz * B.zz, A.yx * B.xx + A.yy * B.yx + A.yz * B.zx,
          A.yx * B.xy + A.yy * B.yy + A.yz * B.zy, A.yx * B.xz + A.yy * B.yz + A.yz * B.zz,
          A.zx * B.xx + A.zy * B.yx + A.zz * B.zx, A.zx * B.xy + A.zy * B.yy + A.zz * B.zy,
          A.zx * B.xz + A.zy * B.yz + A.zz * B.zz};
}

/// E^T A E for symmetric A (a rotation of coordinates).
template <class S>
Sym3<S> rotate_T(const Mat3<S>& E, const Sym3<S>& A) {
  // columns of A E
  const Vec3<S> c0 = mul(A, Vec3<S>{E.xx, E.yx, E.zx});
  const Vec3<S> c1 = mul(A, Vec3<S>{E.xy, E.yy, E.zy});
  const Vec3<S> c2 = mul(A, Vec3<S>{E.xz, E.yz, E.zz});
  const Vec3<S> e0{E.xx, E.yx, E.zx}, e1{E.xy, E.yy, E.zy}, e2{E.xz, E.yz, E.zz};
  return {dot(e0, c0), dot(e1, c1), dot(e2, c2), dot(e0, c1), dot(e0, c2), dot(e1, c2)};
}

/// E^T A E for a general A.
template <class S>
Mat3<S> rotate_T(const Mat3<S>& E, const Mat3<S>& A) {
  const Mat3<S> AE = mul(A, E);
  const Vec3<S> e0{E.xx, E.yx, E.zx}, e1{E.xy, E.yy, E.zy}, e2{E.xz, E.yz, E.zz};
  const Vec3<S> c0{AE.xx, AE.yx, AE.zx}, c1{AE.xy, AE.yy, AE.zy}, c2{AE.xz, AE.yz, AE.zz};
  return {dot(e0, c0), dot(e0, c1), dot(e0, c2), dot(e1, c0), dot(e1, c1),
          dot(e1, c2), dot(e2, c0), dot(e2, c1), dot(e2, c2)};
}

// ---- transforms (RBDA sec. 2.8, Table 2.5) ---------------------------------------------

/// X m = [E w; E (v - r x w)]
template <class S>
Motion<S> apply_motion(const Xform<S>& X, const Motion<S>& m) {
  return {mul(X.E, m.ang), mul(X.E, m.lin - cross(X.r, m.ang))};
}

/// X^T f, a force in child coordinates expressed in parent coordinates:
/// [E^T n + r x E^T f; E^T f]
template <class S>
Force<S> apply_force_T(const Xform<S>& X, const Force<S>& f) {
  const Vec3<S> fp = mul_T(X.E, f.lin);
  return {mul_T(X.E, f.ang) + cross(X.r, fp), fp};
}

/// X^-1 m = [E^T w; E^T v + r x E^T w]: a motion in child coordinates expressed in parent
/// coordinates
template <class S>
Motion<S> apply_motion_inv(const Xform<S>& X, const Motion<S>& m) {
  const Vec3<S> w = mul_T(X.E, m.ang);
  return {w, mul_T(X.E, m.lin) + cross(X.r, w)};
}

/// X_ac = X_ab X_bc: E = E_ab E_bc, r = r_bc + E_bc^T r_ab
template <class S>
Xform<S> compose(const Xform<S>& X_ab, const Xform<S>& X_bc) {
  return {mul(X_ab.E, X_bc.E), X_bc.r + mul_T(X_bc.E, X_ab.r)};
}

/// X^T I X for a rigid-body inertia in child coordinates, giving parent coordinates
/// (RBDA eq. 2.66 in (m, h, I) form): h' = E^T h, hp = h' + m r,
/// Ip = E^T I E - r x h'x - hp x r x = E^T I E - h' r^T - r hp^T + (r.h' + r.hp) 1.
template <class S>
RigidInertia<S> apply_inertia_T(const Xform<S>& X, const RigidInertia<S>& I) {
  const Vec3<S>& r = X.r;
  const Vec3<S> h1 = mul_T(X.E, I.h);
  const Vec3<S> hp = h1 + scale(r, I.m);
  const Sym3<S> Ir = rotate_T(X.E, I.I);
  const S d = dot(r, h1) + dot(r, hp);
  return {I.m, hp,
          Sym3<S>{Ir.xx - h1.x * r.x - r.x * hp.x + d, Ir.yy - h1.y * r.y - r.y * hp.y + d,
                  Ir.zz - h1.z * r.z - r.z * hp.z + d, Ir.xy - h1.x * r.y - r.x * hp.y,
                  Ir.xz - h1.x * r.z - r.x * hp.z, Ir.yz - h1.y * r.z - r.y * hp.z}};
}

/// rows of A r x: row_i(A) x r
template <class S>
Mat3<S> mul_skew(const Mat3<S>& A, const Vec3<S>& r) {
  const Vec3<S> a0 = cross(Vec3<S>{A.xx, A.xy, A.xz}, r);
  const Vec3<S> a1 = cross(Vec3<S>{A.yx, A.yy, A.yz}, r);
  const Vec3<S> a2 = cross(Vec3<S>{A.zx, A.zy, A.zz}, r);
  return {a0.x, a0.y, a0.z, a1.x, a1.y, a1.z, a2.x, a2.y, a2.z};
}

/// rows of A r x for symmetric A
template <class S>
Mat3<S> mul_skew(const Sym3<S>& A, const Vec3<S>& r) {
  return mul_skew(Mat3<S>{A.xx, A.xy, A.xz, A.xy, A.yy, A.yz, A.xz, A.yz, A.zz}, r);
}

/// X^T IA X for an articulated inertia in child coordinates (RBDA eq. 7.43 with X from
/// Table 2.5): with I', H', M' rotated by E,
/// M_p = M', H_p = H' + r x M', I_p = I' - K - K^T - r x M' r x, where K = H' r x.
template <class S>
ArticulatedInertia<S> apply_inertia_T(const Xform<S>& X, const ArticulatedInertia<S>& A) {
  const Vec3<S>& r = X.r;
  const Sym3<S> I1 = rotate_T(X.E, A.I);
  const Mat3<S> H1 = rotate_T(X.E, A.H);
  const Sym3<S> M1 = rotate_T(X.E, A.M);
  const Mat3<S> K = mul_skew(H1, r);
  const Mat3<S> Q = mul_skew(M1, r);  // M' r x, so r x M' = -Q^T
  // r x M' r x = r x Q, column j = r x Q(:, j)
  const Vec3<S> R0 = cross(r, Vec3<S>{Q.xx, Q.yx, Q.zx});
  const Vec3<S> R1 = cross(r, Vec3<S>{Q.xy, Q.yy, Q.zy});
  const Vec3<S> R2 = cross(r, Vec3<S>{Q.xz, Q.yz, Q.zz});
  ArticulatedInertia<S> P;
  P.M = M1;
  P.H = {H1.xx - Q.xx, H1.xy - Q.yx, H1.xz - Q.zx, H1.yx - Q.xy, H1.yy - Q.yy,
         H1.yz - Q.zy, H1.zx - Q.xz, H1.zy - Q.yz, H1.zz - Q.zz};
  P.I = {I1.xx - K.xx - K.xx - R0.x, I1.yy - K.yy - K.yy - R1.y, I1.zz - K.zz - K.zz - R2.z,
         I1.xy - K.xy - K.yx - R1.x, I1.xz - K.xz - K.zx - R2.x, I1.yz - K.yz - K.zy - R2.y};
  return P;
}

// ---- products (RBDA sec. 2.9, 2.13) ----------------------------------------------------

/// I m for a rigid-body inertia: [I w + h x v; m v - h x w]
template <class S>
Force<S> mul(const RigidInertia<S>& I, const Motion<S>& m) {
  return {mul(I.I, m.ang) + cross(I.h, m.lin), scale(m.lin, I.m) - cross(I.h, m.ang)};
}

/// IA m for an articulated inertia: [I w + H v; H^T w + M v]
template <class S>
Force<S> mul(const ArticulatedInertia<S>& A, const Motion<S>& m) {
  return {mul(A.I, m.ang) + mul(A.H, m.lin), mul_T(A.H, m.ang) + mul(A.M, m.lin)};
}

/// The rigid-body inertia as an articulated inertia: [I h x; (h x)^T m 1].
template <class S>
ArticulatedInertia<S> articulated(const RigidInertia<S>& I) {
  const S zero{};
  return {I.I, Mat3<S>{zero, -I.h.z, I.h.y, I.h.z, zero, -I.h.x, -I.h.y, I.h.x, zero},
          Sym3<S>{I.m, I.m, I.m, zero, zero, zero}};
}

template <class S>
Motion<S> scale(const Motion<S>& m, const S& k) {
  return {scale(m.ang, k), scale(m.lin, k)};
}

/// The 6 numbers of a motion into out[0..5] as the kernels take them (kernels.hpp, inner6): the
/// angular and linear parts interleaved, w.x, v.x, w.y, v.y, w.z, v.z.
template <class S>
void put(S* out, const Motion<S>& m) {
  out[0] = m.ang.x, out[1] = m.lin.x, out[2] = m.ang.y;
  out[3] = m.lin.y, out[4] = m.ang.z, out[5] = m.lin.z;
}

/// The 6 numbers of a force into out[0..5], interleaved as a motion's (put above).
template <class S>
void put(S* out, const Force<S>& f) {
  out[0] = f.ang.x, out[1] = f.lin.x, out[2] = f.ang.y;
  out[3] = f.lin.y, out[4] = f.ang.z, out[5] = f.lin.z;
}

/// f . m, the power of a force on a motion
template <class S>
S inner(const Force<S>& f, const Motion<S>& m) {
  return dot(f.ang, m.ang) + dot(f.lin, m.lin);
}

/// v x m (RBDA eq. 2.31): [w x m_w; w x m_v + v x m_w]
template <class S>
Motion<S> cross_motion(const Motion<S>& v, const Motion<S>& m) {
  return {cross(v.ang, m.ang), cross(v.ang, m.lin) + cross(v.lin, m.ang)};
}

/// v x* f (RBDA eq. 2.32): [w x n + v x f; w x f]
template <class S>
Force<S> cross_force(const Motion<S>& v, const Force<S>& f) {
  return {cross(v.ang, f.ang) + cross(v.lin, f.lin), cross(v.ang, f.lin)};
}

template <class S>
Motion<S> operator+(const Motion<S>& a, const Motion<S>& b) {
  return {a.ang + b.ang, a.lin + b.lin};
}

template <class S>
Force<S> operator+(const Force<S>& a, const Force<S>& b) {
  return {a.ang + b.ang, a.lin + b.lin};
}

template <class S>
Force<S> operator-(const Force<S>& a, const Force<S>& b) {
  return {a.ang - b.ang, a.lin - b.lin};
}

template <class S>
RigidInertia<S> operator+(const RigidInertia<S>& a, const RigidInertia<S>& b) {
  return {a.m + b.m, a.h + b.h,
          Sym3<S>{a.I.xx + b.I.xx, a.I.yy + b.I.yy, a.I.zz + b.I.zz, a.I.xy + b.I.xy,
                  a.I.xz + b.I.xz, a.I.yz + b.I.yz}};
}

template <class S>
Sym3<S> operator+(const Sym3<S>& a, const Sym3<S>& b) {
  return {a.xx + b.xx, a.yy + b.yy, a.zz + b.zz, a.xy + b.xy, a.xz + b.xz, a.yz + b.yz};
}

template <class S>
Mat3<S> operator+(const Mat3<S>& a, const Mat3<S>& b) {
  return {a.xx + b.xx, a.xy + b.xy, a.xz + b.xz, a.yx + b.yx, a.yy + b.yy,
          a.yz + b.yz, a.zx + b.zx, a.zy + b.zy, a.zz + b.zz};
}

template <class S>
ArticulatedInertia<S> operator+(const ArticulatedInertia<S>& a, const ArticulatedInertia<S>& b) {
  return {a.I + b.I, a.H + b.H, a.M + b.M};
}


/// A - U Ud^T, with Ud = U / D: the articulated inertia a joint passes to its parent (RBDA
/// eq. 7.37 for a one-column joint, Ia = IA - U U^T / D).
template <class S>
ArticulatedInertia<S> downdate(const ArticulatedInertia<S>& A, const Force<S>& U,
                               const Force<S>& Ud) {
  ArticulatedInertia<S> Ia;
  Ia.I = {A.I.xx - U.ang.x * Ud.ang.x, A.I.yy - U.ang.y * Ud.ang.y, A.I.zz - U.ang.z * Ud.ang.z,
          A.I.xy - U.ang.x * Ud.ang.y, A.I.xz - U.ang.x * Ud.ang.z, A.I.yz - U.ang.y * Ud.ang.z};
  Ia.H = {A.H.xx - U.ang.x * Ud.lin.x, A.H.xy - U.ang.x * Ud.lin.y, A.H.xz - U.ang.x * Ud.lin.z,
          A.H.yx - U.ang.y * Ud.lin.x, A.H.yy - U.ang.y * Ud.lin.y, A.H.yz - U.ang.y * Ud.lin.z,
          A.H.zx - U.ang.z * Ud.lin.x, A.H.zy - U.ang.z * Ud.lin.y, A.H.zz - U.ang.z * Ud.lin.z};
  Ia.M = {A.M.xx - U.lin.x * Ud.lin.x, A.M.yy - U.lin.y * Ud.lin.y, A.M.zz - U.lin.z * Ud.lin.z,
          A.M.xy - U.lin.x * Ud.lin.y, A.M.xz - U.lin.x * Ud.lin.z, A.M.yz - U.lin.y * Ud.lin.z};
  return Ia;
}

template <class S>
Mat3<S> transpose(const Mat3<S>& A) {
  return {A.xx, A.yx, A.zx, A.xy, A.yy, A.zy, A.xz, A.yz, A.zz};
}

template <class S>
Mat3<S> operator-(const Mat3<S>& a, const Mat3<S>& b) {
  return {a.xx - b.xx, a.xy - b.xy, a.xz - b.xz, a.yx - b.yx, a.yy - b.yy,
          a.yz - b.yz, a.zx - b.zx, a.zy - b.zy, a.zz - b.zz};
}

/// A as a full 3x3 matrix
template <class S>
Mat3<S> full(const Sym3<S>& A) {
  return {A.xx, A.xy, A.xz, A.xy, A.yy, A.yz, A.xz, A.yz, A.zz};
}

/// The upper triangle of A, which the caller knows to be symmetric
template <class S>
Sym3<S> upper(const Mat3<S>& A) {
  return {A.xx, A.yy, A.zz, A.xy, A.xz, A.yz};
}

/// A^-1 of a positive definite symmetric 3x3 by its cofactors, with one reciprocal: a ball
/// joint's (S^T IA S)^-1 in ABA.
template <class S>
Sym3<S> inverse(const Sym3<S>& A) {
  const S cxx = A.yy * A.zz - A.yz * A.yz;
  const S cxy = A.xz * A.yz - A.xy * A.zz;
  const S cxz = A.xy * A.yz - A.xz * A.yy;
  const S r = S(1) / (A.xx * cxx + A.xy * cxy + A.xz * cxz);
  const S cyy = A.xx * A.zz - A.xz * A.xz;
  const S cyz = A.xy * A.xz - A.xx * A.yz;
  const S czz = A.xx * A.yy - A.xy * A.xy;
  return {cxx * r, cyy * r, czz * r, cxy * r, cxz * r, cyz * r};
}

/// A - U D^-1 U^T for a ball joint, whose S = [1; 0] takes A's angular columns U = [I; H^T],
/// with Dinv = (I + armature)^-1 (RBDA eq. 7.37 with three columns). Without armature the
/// angular rows vanish, as the joint passes on no moment: Ia = [0 0; 0 M - H^T I^-1 H].
template <class S>
ArticulatedInertia<S> downdate_ball(const ArticulatedInertia<S>& A, const Sym3<S>& Dinv,
                                    bool armature) {
  const Mat3<S> I = full(A.I);
  const Mat3<S> L = mul(full(Dinv), A.H);  // D^-1 H
  ArticulatedInertia<S> Ia{{}, {}, upper(full(A.M) - mul(transpose(A.H), L))};
  if (!armature) return Ia;
  Ia.I = upper(I - mul(I, mul(full(Dinv), I)));
  Ia.H = A.H - mul(I, L);
  return Ia;
}

template <class S>
InertiaVariation<S> operator+(const InertiaVariation<S>& a, const InertiaVariation<S>& b) {
  return {a.hdot + b.hdot, a.Idot + b.Idot, a.p + b.p};
}

/// B of a rigid-body inertia I = (m, h, I_o) moving with v = [w; u], all in one frame:
/// hdot = w x h + m u, Idot = K + K^T with K = w x I_o - h u^T + (u . h) 1.
template <class S>
InertiaVariation<S> variation(const RigidInertia<S>& I, const Motion<S>& v) {
  const Vec3<S>& w = v.ang;
  const Vec3<S>& u = v.lin;
  const Vec3<S>& h = I.h;
  const S uh = dot(u, h);
  // columns of w x I_o
  const Vec3<S> c0 = cross(w, Vec3<S>{I.I.xx, I.I.xy, I.I.xz});
  const Vec3<S> c1 = cross(w, Vec3<S>{I.I.xy, I.I.yy, I.I.yz});
  const Vec3<S> c2 = cross(w, Vec3<S>{I.I.xz, I.I.yz, I.I.zz});
  const Mat3<S> K{c0.x - h.x * u.x + uh, c1.x - h.x * u.y,      c2.x - h.x * u.z,
                  c0.y - h.y * u.x,      c1.y - h.y * u.y + uh, c2.y - h.y * u.z,
                  c0.z - h.z * u.x,      c1.z - h.z * u.y,      c2.z - h.z * u.z + uh};
  return {cross(w, h) + scale(u, I.m),
          Sym3<S>{K.xx + K.xx, K.yy + K.yy, K.zz + K.zz, K.xy + K.yx, K.xz + K.zx, K.yz + K.zy},
          mul(I, v)};
}

/// B x
template <class S>
Force<S> mul(const InertiaVariation<S>& B, const Motion<S>& x) {
  return mul(RigidInertia<S>{S(0), B.hdot, B.Idot}, x) + cross_force(x, B.p);
}

/// B^T x: the symmetric part as is, the skew part negated
template <class S>
Force<S> mul_T(const InertiaVariation<S>& B, const Motion<S>& x) {
  return mul(RigidInertia<S>{S(0), B.hdot, B.Idot}, x) - cross_force(x, B.p);
}

/// The rotation of a unit quaternion (w, x, y, z), taking body to parent coordinates; its
/// transpose is the E of the body's transform.
template <class S>
Mat3<S> quaternion_rotation(const S& w, const S& x, const S& y, const S& z) {
  const S xx = x * x, yy = y * y, zz = z * z;
  const S xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
  const S one(1), two(2);
  return {one - two * (yy + zz), two * (xy - wz),        two * (xz + wy),
          two * (xy + wz),        one - two * (xx + zz), two * (yz - wx),
          two * (xz - wy),        two * (yz + wx),        one - two * (xx + yy)};
}

template <class S>
Motion<S> operator-(const Motion<S>& a, const Motion<S>& b) {
  return {a.ang - b.ang, a.lin - b.lin};
}

/// x = A^-1 b for a positive definite articulated inertia: an LDL^T factorisation without
/// pivoting (stable for positive definite A), one reciprocal per pivot, in a fixed order.
/// The floating-base ABA solves with the root's articulated inertia (RBDA sec. 9.3).
template <class S>
Motion<S> solve(const ArticulatedInertia<S>& A, const Force<S>& b) {
  // A as a dense symmetric 6x6 in [angular; linear] order; only the lower triangle is read
  const S a[6][6] = {
      {A.I.xx, A.I.xy, A.I.xz, A.H.xx, A.H.xy, A.H.xz},
      {A.I.xy, A.I.yy, A.I.yz, A.H.yx, A.H.yy, A.H.yz},
      {A.I.xz, A.I.yz, A.I.zz, A.H.zx, A.H.zy, A.H.zz},
      {A.H.xx, A.H.yx, A.H.zx, A.M.xx, A.M.xy, A.M.xz},
      {A.H.xy, A.H.yy, A.H.zy, A.M.xy, A.M.yy, A.M.yz},
      {A.H.xz, A.H.yz, A.H.zz, A.M.xz, A.M.yz, A.M.zz}};
  S L[6][6]{}, d[6]{}, inv_d[6]{};
  for (int j = 0; j < 6; ++j) {
    S LD[6]{};  // L_jk d_k
    for (int k = 0; k < j; ++k) LD[k] = L[j][k] * d[k];
    S djj = a[j][j];
    for (int k = 0; k < j; ++k) djj = djj - L[j][k] * LD[k];
    d[j] = djj;
    inv_d[j] = S(1) / djj;
    for (int i = j + 1; i < 6; ++i) {
      S lij = a[i][j];
      for (int k = 0; k < j; ++k) lij = lij - L[i][k] * LD[k];
      L[i][j] = lij * inv_d[j];
    }
  }
  // L y = b, then L^T x = D^-1 y
  S x[6] = {b.ang.x, b.ang.y, b.ang.z, b.lin.x, b.lin.y, b.lin.z};
  for (int i = 1; i < 6; ++i)
    for (int k = 0; k < i; ++k) x[i] = x[i] - L[i][k] * x[k];
  for (int i = 0; i < 6; ++i) x[i] = x[i] * inv_d[i];
  for (int i = 4; i >= 0; --i)
    for (int k = i + 1; k < 6; ++k) x[i] = x[i] - L[k][i] * x[k];
  return {{x[0], x[1], x[2]}, {x[3], x[4], x[5]}};
}

}  // namespace dyngen
