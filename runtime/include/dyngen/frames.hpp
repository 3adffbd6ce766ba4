// Frames: where the model's named frames are (forward kinematics, RBDA sec. 4.2) and their
// Jacobians, the map from v to each frame's velocity (a column per joint on the frame's path to
// the base, RBDA sec. 8.4). Matrices are row-major; per frame f, R[9 f + 3 i + j] and
// p[3 f + i], and J[(6 f + row) nv + column] with the linear rows first, then the angular ones.
#pragma once

#include <span>

#include "dyngen/joint.hpp"
#include "dyngen/workspace.hpp"

namespace dyngen {

/// The axes a Jacobian's rows are expressed in: the base's (at the frame's origin, Pinocchio's
/// LOCAL_WORLD_ALIGNED) or the frame's own (LOCAL).
enum class JacobianAxes { World, Local };

namespace detail {

/// ws.X0[i] = X_i0, the base-to-body transform of every body at q.
template <class S>
void body_placements(const Model<S>& model, Workspace<S>& ws, std::span<const S> q) {
  for (int i = 0; i < model.nbodies; ++i) {
    const int p = model.parent[i];
    ws.Xup[i] = joint_transform(model, i, &q[model.q_index[i]]);
    ws.X0[i] = p < 0 ? ws.Xup[i] : compose(ws.Xup[i], ws.X0[p]);
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
    const Xform<S> X = detail::frame_transform(model, ws, f);
    const Mat3<S>& E = X.E;
    S* Rf = &R[9 * f];
    Rf[0] = E.xx, Rf[1] = E.yx, Rf[2] = E.zx;
    Rf[3] = E.xy, Rf[4] = E.yy, Rf[5] = E.zy;
    Rf[6] = E.xz, Rf[7] = E.yz, Rf[8] = E.zz;
    p[3 * f] = X.r.x, p[3 * f + 1] = X.r.y, p[3 * f + 2] = X.r.z;
  }
}

/// Each frame's Jacobian at q: J v = (velocity of the frame's origin, angular velocity), in the
/// base's axes or the frame's own. Column c of joint j on the frame's path to the base is j's
/// motion subspace column s in base coordinates, s0 = X_j0^-1 s (a motion at the base origin),
/// moved to the frame's origin p: (s0.lin + s0.ang x p, s0.ang); the other columns are zero.
template <class S>
void frame_jacobians(const Model<S>& model, Workspace<S>& ws, std::span<const S> q,
                     JacobianAxes axes, std::span<S> J) {
  detail::body_placements(model, ws, q);
  const int nv = model.nv;
  for (int f = 0; f < static_cast<int>(model.frames.size()); ++f) {
    S* Jf = &J[6 * static_cast<std::size_t>(f) * nv];
    for (int e = 0; e < 6 * nv; ++e) Jf[e] = S(0);
    const Xform<S> X = detail::frame_transform(model, ws, f);
    for (int j = model.frames[f].body; j >= 0; j = model.parent[j]) {
      for (int d = 0; d < joint_nv(model.joint_type[j]); ++d) {
        const Motion<S> s0 = apply_motion_inv(ws.X0[j], joint_column(model, j, d));
        Vec3<S> lin = s0.lin + cross(s0.ang, X.r), ang = s0.ang;
        if (axes == JacobianAxes::Local) lin = mul(X.E, lin), ang = mul(X.E, ang);
        const int c = model.v_index[j] + d;
        Jf[c] = lin.x, Jf[nv + c] = lin.y, Jf[2 * nv + c] = lin.z;
        Jf[3 * nv + c] = ang.x, Jf[4 * nv + c] = ang.y, Jf[5 * nv + c] = ang.z;
      }
    }
  }
}

}  // namespace dyngen
