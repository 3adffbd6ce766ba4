// RNEA, CRBA and ABA of a planar serial chain, written by hand in the rigid-body algorithms
// chapter's planar spatial vectors: motion [w, vx, vy], force [n, fx, fy] and the 3x3 inertia
// [[Io, -hy, hx], [-hy, m, 0], [hx, 0, m]] of mass m, first moment h = m c and rotational
// inertia Io, all about the joint. It is the competitor that dyngen's generated code is counted
// against (work_counts.cpp): every formula is reduced by hand for the plane (2x2 rotations, one
// sin and cos per revolute joint, no arithmetic on entries known to be zero, the still base
// taken as such, negations folded into subtractions) and products of model constants are made
// once, in the constructor. Templated on the scalar, so that op_counter.hpp's Counted can count
// its operations.
//
// The chains: each joint turns about its z axis or slides along its x axis, and sits on the
// previous link's x axis (the joint frames are not rotated at q = 0); gravity lies in the
// plane. These are the planar chains of tests/tools/make_chain and tests/models/planar5.yaml.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "dyngen/joint.hpp"
#include "dyngen/model.hpp"

namespace dyngen::bench {

template <class S>
class PlanarChain {
 public:
  /// The chain of a dyngen model; std::invalid_argument if the model is not such a chain.
  explicit PlanarChain(const Model<double>& model);

  int dofs() const { return static_cast<int>(links_.size()); }

  /// Inverse dynamics: tau = M(q) qdd + C(q, qd) qd + g(q).
  void rnea(const S* q, const S* qd, const S* qdd, S* tau);

  /// The mass matrix, row-major, both triangles.
  void crba(const S* q, S* M);

  /// Forward dynamics: qdd = M(q)^-1 (tau - C(q, qd) qd - g(q)).
  void aba(const S* q, const S* qd, const S* tau, S* qdd);

 private:
  /// [w, x, y]: a planar motion [w, vx, vy] or force [n, fx, fy]
  struct Planar {
    S w, x, y;
  };

  /// A composite inertia (CRBA): [Io, hx, -hy]; its mass is a constant, Link::subtree_mass.
  struct Composite {
    S Io, hx, minus_hy;
  };

  /// A symmetric 3x3 (the articulated inertia), upper triangle.
  struct Sym {
    S a00, a01, a02, a11, a12, a22;
  };

  struct Link {
    bool prismatic;
    S offset;               // L: from the previous joint, along the previous link's x axis
    S m, hx, hy, Io;        // the inertia about the joint
    S minus_hx, minus_hy;   // -hx, -hy
    S subtree_mass;         // of this link and those beyond it (CRBA)
    S subtree_mass_offset;  // subtree_mass * offset
  };

  /// The joint's cos and sin (revolute), or its distance d = L + q from the previous joint
  /// (prismatic): its transform, made once per call.
  void joint(int i, const S& q) {
    if (links_[i].prismatic)
      d_[i] = links_[i].offset + q;
    else
      joint_sincos(q, s_[i], c_[i]);  // the runtime's and the generated code's sin and cos
  }

  std::vector<Link> links_;
  S a0x_, a0y_;  // the base's acceleration: -gravity
  // per-call buffers
  std::vector<S> c_, s_, d_;
  std::vector<Planar> v_, a_, f_;
  std::vector<Composite> Ic_;
  // ABA: the velocity product c = v x S qd, [0, c1, -c2] with c1 = vy qd and c2 = vx qd for a
  // revolute joint, [0, 0, c2] with c2 = w qd for a prismatic one (the signs fold into sums)
  std::vector<S> c1_, c2_;
  std::vector<Planar> pA_;
  std::vector<Sym> IA_;
  // ABA: 1/D, u, and the two entries of U/D off S's (its entry along S is 1)
  std::vector<S> inv_D_, u_, Ud_first_, Ud_second_;
};

template <class S>
PlanarChain<S>::PlanarChain(const Model<double>& model) {
  const int n = model.nbodies;
  auto fail = [&](int i, const char* what) {
    throw std::invalid_argument("not a planar chain (body " + std::to_string(i) + "): " + what);
  };
  if (n == 0) throw std::invalid_argument("not a planar chain: no joints");
  if (model.gravity.z != 0) throw std::invalid_argument("not a planar chain: gravity along z");
  for (int i = 0; i < n; ++i) {
    const Vec3<double>& k = model.joint_axis[i];
    const Mat3<double>& E = model.X_tree[i].E;
    const Vec3<double>& r = model.X_tree[i].r;
    const RigidInertia<double>& I = model.I[i];
    if (model.parent[i] != i - 1) fail(i, "not serial");
    const bool revolute = model.joint_type[i] == JointType::RevoluteZ && k.z == 1;
    const bool prismatic =
        model.joint_type[i] == JointType::Prismatic && k.x == 1 && k.y == 0 && k.z == 0;
    if (!revolute && !prismatic) fail(i, "joint neither about +z nor along +x");
    if (E.xx != 1 || E.yy != 1 || E.zz != 1 || E.xy != 0 || E.xz != 0 || E.yx != 0 || E.yz != 0 ||
        E.zx != 0 || E.zy != 0)
      fail(i, "rotated joint frame");
    if (r.y != 0 || r.z != 0) fail(i, "joint off the previous link's x axis");
    if (I.h.z != 0 || I.I.xz != 0 || I.I.yz != 0) fail(i, "inertia leaves the plane");
    links_.push_back({prismatic, r.x, I.m, I.h.x, I.h.y, I.I.zz, -I.h.x, -I.h.y, 0, 0});
  }
  double mass = 0;
  for (int i = n - 1; i >= 0; --i) {
    mass += model.I[i].m;
    links_[i].subtree_mass = mass;
    links_[i].subtree_mass_offset = mass * model.X_tree[i].r.x;
  }
  a0x_ = -model.gravity.x;
  a0y_ = -model.gravity.y;
  c_.resize(n), s_.resize(n), d_.resize(n);
  v_.resize(n), a_.resize(n), f_.resize(n);
  Ic_.resize(n), pA_.resize(n);
  c1_.resize(n), c2_.resize(n);
  IA_.resize(n);
  inv_D_.resize(n), u_.resize(n), Ud_first_.resize(n), Ud_second_.resize(n);
}

template <class S>
void PlanarChain<S>::rnea(const S* q, const S* qd, const S* qdd, S* tau) {
  const int n = dofs();
  for (int i = 0; i < n; ++i) {
    const Link& l = links_[i];
    joint(i, q[i]);
    const S &c = c_[i], &s = s_[i], &d = d_[i];
    Planar &v = v_[i], &a = a_[i];
    S Ax, Ay;  // the linear acceleration of the joint's point (not the spatial one)
    if (i == 0) {
      // the base is still: v = S qd, and v x S qd = 0
      if (l.prismatic) {
        v = {S(0), qd[i], S(0)};
        a = {S(0), a0x_ + qdd[i], a0y_};
      } else {
        v = {qd[i], S(0), S(0)};
        a = {qdd[i], c * a0x_ + s * a0y_, c * a0y_ - s * a0x_};
      }
      Ax = a.x, Ay = a.y;
    } else {
      // v = X v_p + S qd, a = X a_p + S qdd + v x S qd
      const Planar &vp = v_[i - 1], &ap = a_[i - 1];
      if (l.prismatic) {
        v = {vp.w, vp.x + qd[i], vp.y + d * vp.w};
        a = {ap.w, ap.x + qdd[i], ap.y + d * ap.w + v.w * qd[i]};
      } else {
        const S vy = vp.y + l.offset * vp.w, ay = ap.y + l.offset * ap.w;
        v.w = vp.w + qd[i];
        v.x = c * vp.x + s * vy;
        v.y = c * vy - s * vp.x;
        a = {ap.w + qdd[i], c * ap.x + s * ay + v.y * qd[i], c * ay - s * ap.x - v.x * qd[i]};
      }
      Ax = a.x - v.w * v.y;
      Ay = a.y + v.w * v.x;
    }
    // f = I a + v x* I v, which is [Io a_w + h x A; m A + a_w z x h - w^2 h]
    const S w2 = v.w * v.w;
    f_[i] = {l.Io * a.w - l.hy * Ax + l.hx * Ay, l.m * Ax - l.hy * a.w - l.hx * w2,
             l.m * Ay + l.hx * a.w - l.hy * w2};
  }
  for (int i = n - 1; i >= 0; --i) {
    const Link& l = links_[i];
    const Planar& f = f_[i];
    tau[i] = l.prismatic ? f.x : f.w;
    if (i == 0) break;
    // f_p += X^T f
    Planar& fp = f_[i - 1];
    if (l.prismatic) {
      fp = {fp.w + (f.w + d_[i] * f.y), fp.x + f.x, fp.y + f.y};
    } else {
      const S fx = c_[i] * f.x - s_[i] * f.y, fy = s_[i] * f.x + c_[i] * f.y;
      fp = {fp.w + (f.w + l.offset * fy), fp.x + fx, fp.y + fy};
    }
  }
}

template <class S>
void PlanarChain<S>::crba(const S* q, S* M) {
  const int n = dofs();
  // M does not depend on the first joint's position: its transform is never made
  for (int i = 0; i < n; ++i) {
    if (i > 0) joint(i, q[i]);
    Ic_[i] = {links_[i].Io, links_[i].hx, links_[i].minus_hy};
  }
  for (int i = n - 1; i >= 0; --i) {
    const Link& l = links_[i];
    const Composite& I = Ic_[i];
    M[i * n + i] = l.prismatic ? l.subtree_mass : I.Io;
    if (i == 0) break;
    // F = Ic S in the parent's frame, and Ic_p += X^T Ic X, which share E^T h
    Planar F;
    Composite& Ip = Ic_[i - 1];
    if (l.prismatic) {
      F = {I.minus_hy, l.subtree_mass, S(0)};
      const S hx = I.hx + l.subtree_mass * d_[i];
      Ip = {Ip.Io + (I.Io + d_[i] * (I.hx + hx)), Ip.hx + hx, Ip.minus_hy + I.minus_hy};
    } else {
      const S &c = c_[i], &s = s_[i];
      const S hx = c * I.hx + s * I.minus_hy, minus_hy = c * I.minus_hy - s * I.hx;  // E^T h
      F = {I.Io + l.offset * hx, minus_hy, hx};
      const S hx_p = hx + l.subtree_mass_offset;
      Ip = {Ip.Io + (F.w + l.offset * hx_p), Ip.hx + hx_p, Ip.minus_hy + minus_hy};
    }
    // M_ij = S_j^T F, with F carried to each joint j below i
    for (int j = i - 1;; --j) {
      M[i * n + j] = M[j * n + i] = links_[j].prismatic ? F.x : F.w;
      if (j == 0) break;
      if (links_[j].prismatic) {
        F.w = F.w + d_[j] * F.y;
      } else {
        const S fx = c_[j] * F.x - s_[j] * F.y, fy = s_[j] * F.x + c_[j] * F.y;
        F = {F.w + links_[j].offset * fy, fx, fy};
      }
    }
  }
}

template <class S>
void PlanarChain<S>::aba(const S* q, const S* qd, const S* tau, S* qdd) {
  const int n = dofs();
  std::vector<Planar>& pA = pA_;
  // velocities, velocity products c = v x S qd and bias forces pA = v x* I v
  for (int i = 0; i < n; ++i) {
    const Link& l = links_[i];
    joint(i, q[i]);
    const S &c = c_[i], &s = s_[i], &d = d_[i];
    Planar& v = v_[i];
    if (i == 0) {
      // the base is still: v = S qd, c = 0
      if (l.prismatic) {
        v = {S(0), qd[i], S(0)};
        pA[i] = {S(0), S(0), S(0)};
      } else {
        v = {qd[i], S(0), S(0)};
        const S w2 = v.w * v.w;
        pA[i] = {S(0), l.minus_hx * w2, l.minus_hy * w2};
      }
      continue;
    }
    const Planar& vp = v_[i - 1];
    if (l.prismatic) {
      v = {vp.w, vp.x + qd[i], vp.y + d * vp.w};
      c2_[i] = v.w * qd[i];
    } else {
      const S vy = vp.y + l.offset * vp.w;
      v = {vp.w + qd[i], c * vp.x + s * vy, c * vy - s * vp.x};
      c1_[i] = v.y * qd[i];
      c2_[i] = v.x * qd[i];
    }
    // [w (h . v), -w (m vy + hx w), w (m vx - hy w)]
    const S mw = l.m * v.w, w2 = v.w * v.w;
    pA[i] = {v.w * (l.hx * v.x + l.hy * v.y), l.minus_hx * w2 - mw * v.y, mw * v.x - l.hy * w2};
  }

  // articulated inertias: U = IA S, D = S^T U, u = tau - S^T pA; the parent gets
  // X^T (IA - U U^T / D) X and X^T (pA + Ia c + U u / D). Ia has a zero row and column (S's),
  // and the entry of pa along S is tau.
  const Link& last = links_[n - 1];
  IA_[n - 1] = {last.Io, last.minus_hy, last.hx, last.m, S(0), last.m};
  for (int i = n - 1; i >= 0; --i) {
    const Link& l = links_[i];
    const Sym& A = IA_[i];
    const Planar& p = pA[i];
    const S &c = c_[i], &s = s_[i], &d = d_[i];
    inv_D_[i] = S(1) / (l.prismatic ? A.a11 : A.a00);
    u_[i] = tau[i] - (l.prismatic ? p.x : p.w);
    if (i == 0) break;
    const S& u = u_[i];
    const Link& lp = links_[i - 1];
    Planar& pp = pA[i - 1];
    if (l.prismatic) {
      // U = [a01, a11, a12]; what remains is the [0, 2] block
      const S Ud0 = A.a01 * inv_D_[i], Ud2 = A.a12 * inv_D_[i];
      Ud_first_[i] = Ud0, Ud_second_[i] = Ud2;
      const S E = A.a00 - A.a01 * Ud0, G = A.a02 - A.a01 * Ud2, H = A.a22 - A.a12 * Ud2;
      const S pa0 = p.w + G * c2_[i] + Ud0 * u, pa2 = p.y + H * c2_[i] + Ud2 * u;
      // X shifts by d along x: [E G; G H] -> [E + d (G + G'), G'; G', H], G' = G + d H
      const S G1 = G + d * H;
      IA_[i - 1] = {lp.Io + (E + d * (G + G1)), lp.minus_hy, lp.hx + G1, lp.m, S(0), lp.m + H};
      pp = {pp.w + (pa0 + d * pa2), pp.x + tau[i], pp.y + pa2};
    } else {
      // U = [a00, a01, a02]; what remains is the 2x2 block [a b; b e] of the linear part
      const S Ud1 = A.a01 * inv_D_[i], Ud2 = A.a02 * inv_D_[i];
      Ud_first_[i] = Ud1, Ud_second_[i] = Ud2;
      const S a = A.a11 - A.a01 * Ud1, b = A.a12 - A.a01 * Ud2, e = A.a22 - A.a02 * Ud2;
      const S &c1 = c1_[i], &c2 = c2_[i];
      const S pa1 = p.x + (a * c1 - b * c2) + Ud1 * u;
      const S pa2 = p.y + (b * c1 - e * c2) + Ud2 * u;
      // E^T [a b; b e] E through the double angle: cos 2q = (c - s)(c + s), sin 2q = 2 c s
      const S cs = c * s;
      const S C2 = (c - s) * (c + s), S2 = cs + cs;
      const S sum = a + e, half_diff = (a - e) * S(0.5);
      const S a1 = sum * S(0.5) + half_diff * C2 - b * S2;
      const S b1 = half_diff * S2 + b * C2;
      const S e1 = sum - a1;
      // then the shift by L along x: row and column 0 get [L^2 e1, L b1, L e1]
      const S Le1 = l.offset * e1;
      IA_[i - 1] = {lp.Io + l.offset * Le1,
                    lp.minus_hy + l.offset * b1,
                    lp.hx + Le1,
                    lp.m + a1,
                    b1,
                    lp.m + e1};
      const S fx = c * pa1 - s * pa2, fy = s * pa1 + c * pa2;
      pp = {pp.w + (tau[i] + l.offset * fy), pp.x + fx, pp.y + fy};
    }
  }

  // accelerations: a' = X a_p + c, qdd = (u - U^T a') / D, a = a' + S qdd; U/D has a 1 along
  // S, so a's entry along S is u/D - (the other two entries of U/D) . a'
  for (int i = 0; i < n; ++i) {
    const Link& l = links_[i];
    const S &c = c_[i], &s = s_[i], &d = d_[i];
    const S& u = u_[i];
    Planar& a = a_[i];
    if (i == 0) {
      const Sym& A = IA_[0];
      if (l.prismatic) {
        a = {S(0), a0x_, a0y_};
        qdd[0] = (u - A.a11 * a0x_ - A.a12 * a0y_) * inv_D_[0];
        a.x = a.x + qdd[0];
      } else {
        a = {S(0), c * a0x_ + s * a0y_, c * a0y_ - s * a0x_};
        qdd[0] = (u - A.a01 * a.x - A.a02 * a.y) * inv_D_[0];
        a.w = qdd[0];
      }
      continue;
    }
    const Planar& ap = a_[i - 1];
    if (l.prismatic) {
      const S ay = ap.y + d * ap.w + c2_[i];
      const S ax = u * inv_D_[i] - Ud_first_[i] * ap.w - Ud_second_[i] * ay;
      qdd[i] = ax - ap.x;
      a = {ap.w, ax, ay};
    } else {
      const S ay_p = ap.y + l.offset * ap.w;
      const S ax = c * ap.x + s * ay_p + c1_[i], ay = c * ay_p - s * ap.x - c2_[i];
      const S aw = u * inv_D_[i] - Ud_first_[i] * ax - Ud_second_[i] * ay;
      qdd[i] = aw - ap.w;
      a = {aw, ax, ay};
    }
  }
}

}  // namespace dyngen::bench
