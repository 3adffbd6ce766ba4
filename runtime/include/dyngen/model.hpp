// The immutable robot model: bodies in topological order (parent[i] < i), one joint per body
// (1-DoF, a 3-DoF ball or a 6-DoF free joint), structure-of-arrays like MuJoCo's mjModel.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "dyngen/spatial.hpp"

namespace dyngen {

/// Joint kinds. Axis-aligned revolute joints have their own kinds so that the joint
/// rotation has exact zeros and ones (the general formula puts (1-c)+c on the diagonal).
///
/// Free: a 6-DoF joint (a floating base, or a URDF floating joint). Its 7 q entries are
/// [px, py, pz, qw, qx, qy, qz]: the child origin in parent coordinates and the unit
/// quaternion (w first) of the child's orientation in the parent. Its 6 v entries are
/// [vx, vy, vz, wx, wy, wz]: the linear velocity of the child origin and the angular velocity,
/// both in child coordinates; accelerations are their time derivatives, and tau is
/// [fx, fy, fz, nx, ny, nz], the force and the moment about the child origin, in child
/// coordinates.
///
/// Ball: a 3-DoF spherical joint. Its 4 q entries are the unit quaternion [qw, qx, qy, qz] of the
/// child's orientation in the parent (the free joint's last four); its 3 v entries the angular
/// velocity [wx, wy, wz] in child coordinates, and tau the moment [nx, ny, nz] there.
enum class JointType : std::uint8_t {
  RevoluteX, RevoluteY, RevoluteZ, Revolute, Prismatic, Free, Ball
};

inline const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::RevoluteX: return "RevoluteX";
    case JointType::RevoluteY: return "RevoluteY";
    case JointType::RevoluteZ: return "RevoluteZ";
    case JointType::Revolute: return "Revolute";
    case JointType::Prismatic: return "Prismatic";
    case JointType::Free: return "Free";
    case JointType::Ball: return "Ball";
  }
  return "?";
}

/// A 1-DoF rotation about an axis (not a ball joint's three).
inline bool is_revolute(JointType t) { return t <= JointType::Revolute; }

/// Entries of the joint in q.
inline int joint_nq(JointType t) { return t == JointType::Free ? 7 : t == JointType::Ball ? 4 : 1; }

/// Entries of the joint in v, a, tau and the rows of M.
inline int joint_nv(JointType t) { return t == JointType::Free ? 6 : t == JointType::Ball ? 3 : 1; }

/// Where the joint's unit quaternion (w, x, y, z) starts among its q entries; -1 if it has none.
inline int quaternion_offset(JointType t) {
  return t == JointType::Free ? 3 : t == JointType::Ball ? 0 : -1;
}

/// A named frame fixed to a body: every URDF link is one, on its own body or, when a fixed joint
/// merged it, on the body it merged into (a tool flange, a foot, a sensor).
template <class S>
struct Frame {
  std::string name;
  int body = -1;        // -1: the fixed base
  Xform<S> placement;   // from the body's coordinates to the frame's, as X_tree
};

/// A constraint on the robot's motion (constrained.hpp): frame A, on body_a at placement_a (from
/// the body's coordinates, as X_tree), held to frame B, on body_b at placement_b (-1: the base).
/// A 3d constraint holds A's origin to B's; a 6d one also holds its orientation. A contact holds
/// A where it touched the world, which the model does not know; a loop closure holds A to B,
/// whose position error Baumgarte's kp acts on. Its multiplier lambda acts on A (and minus it on
/// B): the force at A's origin, then for 6d the moment about it, in base axes.
template <class S>
struct Constraint {
  std::string name;
  int body_a = -1;
  Xform<S> placement_a;
  int body_b = -1;
  Xform<S> placement_b;
  bool six_d = false;
  bool loop = false;
};

/// Rows of a constraint: 3 (point) or 6 (surface, or a welded loop).
template <class S>
int constraint_rows(const Constraint<S>& c) {
  return c.six_d ? 6 : 3;
}

/// How the constrained algorithms solve (constrained.hpp): Baumgarte gains on the constraints'
/// velocity (kd, 1/s) and position error (kp, 1/s^2, loop closures), the restitution of impulses,
/// and the relative damping of the proximal solve.
template <class S>
struct ConstraintSettings {
  S kp{}, kd{}, restitution{};
  S damping = default_damping();

  /// 1e-10 for float and double (docs/design.md, "Constraints"); other scalars (the tracer's,
  /// MPFR's) take their settings from a double model by cast().
  static S default_damping() {
    if constexpr (std::is_arithmetic_v<S>)
      return S(1e-10);
    else
      return S{};
  }
};

template <class S>
struct Model {
  int nbodies = 0;                     // bodies, not counting the fixed base
  int nq = 0;                          // configuration size
  int nv = 0;                          // velocity size
  std::vector<int> parent;             // [nbodies] parent body, -1 for the base; parent[i] < i
  std::vector<JointType> joint_type;   // [nbodies]
  std::vector<Vec3<S>> joint_axis;     // [nbodies] unit axis, body coordinates
  std::vector<Xform<S>> X_tree;        // [nbodies] joint frame at q = 0 relative to parent
  std::vector<RigidInertia<S>> I;      // [nbodies] about the body origin, body coordinates
  std::vector<int> q_index;            // [nbodies] index of the joint's first entry in q
  std::vector<int> v_index;            // [nbodies] ... in v, a, tau and the rows of M
  Vec3<S> gravity;                     // gravitational acceleration, base coordinates
  std::vector<std::string> body_name;  // [nbodies]
  std::vector<std::string> joint_name; // [nbodies]
  std::vector<Frame<S>> frames;        // the frames whose placements and Jacobians are asked for
  /// [nv] rotor inertia (armature) of each degree of freedom, added to M's diagonal: RNEA adds
  /// armature a to tau, CRBA armature to M_kk, ABA to its pivot D. Empty when no joint has any.
  std::vector<S> armature;
  /// Mimic joints (URDF's <mimic>, Pinocchio 3's mimic joints): body i with mimic[i] = p >= 0
  /// has no coordinate of its own: its one-DoF joint follows q_i = mimic_multiplier[i] q_p +
  /// mimic_offset[i], v_i = mimic_multiplier[i] v_p, and it shares p's q_index and v_index, so
  /// that tau = G^T tau_joints and M = G^T M_joints G for the map G from the coordinates to the
  /// joints. All empty when no joint mimics another.
  std::vector<int> mimic;
  std::vector<S> mimic_multiplier, mimic_offset;
  std::vector<char> mimic_mirrors;  // [nbodies] 1: multiplier -1, offset 0 (q_i = -q_p)
  /// Contacts and loop closures (constrained.hpp), and the rows of their multipliers.
  std::vector<Constraint<S>> constraints;
  ConstraintSettings<S> constraint_settings;
  int nc = 0;

  /// The same model in another scalar type; each constant is converted with static_cast.
  template <class T>
  Model<T> cast() const {
    Model<T> m;
    m.nbodies = nbodies;
    m.nq = nq;
    m.nv = nv;
    m.parent = parent;
    m.joint_type = joint_type;
    m.q_index = q_index;
    m.v_index = v_index;
    m.body_name = body_name;
    m.joint_name = joint_name;
    m.gravity = cast_vec<T>(gravity);
    for (int i = 0; i < nbodies; ++i) {
      m.joint_axis.push_back(cast_vec<T>(joint_axis[i]));
      m.X_tree.push_back(cast_xform<T>(X_tree[i]));
      const Sym3<S>& J = I[i].I;
      m.I.push_back({c<T>(I[i].m), cast_vec<T>(I[i].h),
                     {c<T>(J.xx), c<T>(J.yy), c<T>(J.zz), c<T>(J.xy), c<T>(J.xz), c<T>(J.yz)}});
    }
    for (const Frame<S>& f : frames) m.frames.push_back({f.name, f.body, cast_xform<T>(f.placement)});
    for (const S& x : armature) m.armature.push_back(c<T>(x));
    m.mimic = mimic;
    m.mimic_mirrors = mimic_mirrors;
    for (const S& x : mimic_multiplier) m.mimic_multiplier.push_back(c<T>(x));
    for (const S& x : mimic_offset) m.mimic_offset.push_back(c<T>(x));
    for (const Constraint<S>& k : constraints)
      m.constraints.push_back({k.name, k.body_a, cast_xform<T>(k.placement_a), k.body_b,
                               cast_xform<T>(k.placement_b), k.six_d, k.loop});
    const ConstraintSettings<S>& cs = constraint_settings;
    m.constraint_settings = {c<T>(cs.kp), c<T>(cs.kd), c<T>(cs.restitution), c<T>(cs.damping)};
    m.nc = nc;
    return m;
  }

 private:
  template <class T>
  static T c(const S& x) {
    return static_cast<T>(x);
  }
  template <class T>
  static Vec3<T> cast_vec(const Vec3<S>& v) {
    return {c<T>(v.x), c<T>(v.y), c<T>(v.z)};
  }
  template <class T>
  static Xform<T> cast_xform(const Xform<S>& X) {
    const Mat3<S>& E = X.E;
    return {{c<T>(E.xx), c<T>(E.xy), c<T>(E.xz), c<T>(E.yx), c<T>(E.yy), c<T>(E.yz), c<T>(E.zx),
             c<T>(E.zy), c<T>(E.zz)},
            cast_vec<T>(X.r)};
  }
};

/// Whether body i's joint mimics another's (Model::mimic).
template <class S>
bool is_mimic(const Model<S>& model, int i) {
  return !model.mimic.empty() && model.mimic[i] >= 0;
}

/// Body i's joint position from its entry x of q: a mimic joint's mimic_multiplier x +
/// mimic_offset (x its primary's entry), x itself otherwise.
template <class S>
S joint_position(const Model<S>& model, int i, const S& x) {
  return is_mimic(model, i) ? model.mimic_multiplier[i] * x + model.mimic_offset[i] : x;
}

/// Whether body i is a mimic joint that turns by its own angle, mimic_multiplier q_p +
/// mimic_offset, whose sine and cosine those of q_p do not give (a law other than q_p and -q_p).
template <class S>
bool has_own_angle(const Model<S>& model, int i) {
  return is_mimic(model, i) && is_revolute(model.joint_type[i]) && !model.mimic_mirrors[i] &&
         !(model.mimic_multiplier[i] == S(1) && model.mimic_offset[i] == S(0));
}

/// The name of each entry of v (and of a, tau and the rows of M): the joint's name, or for a
/// free joint its name followed by :vx, :vy, :vz, :wx, :wy, :wz (a ball joint: :wx, :wy, :wz).
template <class S>
std::vector<std::string> velocity_names(const Model<S>& model) {
  static constexpr const char* suffixes[] = {":vx", ":vy", ":vz", ":wx", ":wy", ":wz"};
  std::vector<std::string> names;
  for (int i = 0; i < model.nbodies; ++i) {
    const JointType t = model.joint_type[i];
    if (is_mimic(model, i)) continue;  // no entry of its own
    if (t != JointType::Free && t != JointType::Ball) {
      names.push_back(model.joint_name[i]);
      continue;
    }
    for (int d = t == JointType::Ball ? 3 : 0; d < 6; ++d)
      names.push_back(model.joint_name[i] + suffixes[d]);
  }
  return names;
}

/// Makes the bodies i with mimic[i] = p >= 0 follow body p's joint (Model::mimic) in a model
/// whose every joint has its own coordinates: numbers the others' q and v again, drops the
/// mimic joints' armature entries, and gives each mimic joint its primary's indices.
template <class S>
void couple(Model<S>& model, const std::vector<int>& mimic, const std::vector<S>& multiplier,
            const std::vector<S>& offset) {
  std::vector<S> armature;
  model.nq = model.nv = 0;
  for (int i = 0; i < model.nbodies; ++i) {
    if (mimic[i] >= 0) continue;
    const int old = model.v_index[i];
    model.q_index[i] = model.nq, model.v_index[i] = model.nv;
    model.nq += joint_nq(model.joint_type[i]);
    model.nv += joint_nv(model.joint_type[i]);
    for (int d = 0; d < joint_nv(model.joint_type[i]) && !model.armature.empty(); ++d)
      armature.push_back(model.armature[old + d]);
  }
  for (int i = 0; i < model.nbodies; ++i)
    if (mimic[i] >= 0) model.q_index[i] = model.q_index[mimic[i]], model.v_index[i] = model.v_index[mimic[i]];
  model.armature = armature;
  model.mimic = mimic, model.mimic_multiplier = multiplier, model.mimic_offset = offset;
  model.mimic_mirrors.assign(mimic.size(), 0);
  for (std::size_t i = 0; i < mimic.size(); ++i)
    model.mimic_mirrors[i] = mimic[i] >= 0 && multiplier[i] == S(-1) && offset[i] == S(0);
}

/// One body of a model as plain numbers: what generated model tables hold.
struct BodyRecord {
  const char* body_name;
  const char* joint_name;
  int parent;
  JointType joint_type;
  double axis[3];
  double E[9];  // row-major
  double r[3];
  double mass;
  double h[3];
  double I[6];  // xx, yy, zz, xy, xz, yz
};

/// One frame of a model as plain numbers.
struct FrameRecord {
  const char* name;
  int body;
  double E[9];  // row-major
  double r[3];
};

/// A mimic joint of a model as plain numbers (Model::mimic).
struct MimicRecord {
  int body, primary;
  double multiplier, offset;
};

/// A constraint of a model as plain numbers (Model::constraints).
struct ConstraintRecord {
  const char* name;
  int body_a;
  double E_a[9], r_a[3];  // placement_a, E row-major
  int body_b;
  double E_b[9], r_b[3];
  int rows;  // 3 or 6
  int loop;  // 1: a loop closure, 0: a contact
};

/// Sets the model's constraints (Model::constraints, Model::nc) and their settings.
template <class S>
void set_constraints(Model<S>& model, std::vector<Constraint<S>> constraints,
                     const ConstraintSettings<S>& settings) {
  model.constraints = std::move(constraints);
  model.constraint_settings = settings;
  model.nc = 0;
  for (const Constraint<S>& c : model.constraints) model.nc += constraint_rows(c);
}

/// Rebuilds a model from its records (the inverse of model_records()); armature: by degree of
/// freedom (v's order), or empty.
inline Model<double> model_from_records(std::span<const BodyRecord> bodies,
                                        const double (&gravity)[3],
                                        std::span<const FrameRecord> frames = {},
                                        std::span<const double> armature = {},
                                        std::span<const MimicRecord> mimics = {},
                                        std::span<const ConstraintRecord> constraints = {},
                                        const ConstraintSettings<double>& settings = {}) {
  Model<double> m;
  m.nbodies = static_cast<int>(bodies.size());
  m.gravity = {gravity[0], gravity[1], gravity[2]};
  for (const BodyRecord& b : bodies) {
    m.q_index.push_back(m.nq);
    m.v_index.push_back(m.nv);
    m.nq += joint_nq(b.joint_type);
    m.nv += joint_nv(b.joint_type);
    m.parent.push_back(b.parent);
    m.joint_type.push_back(b.joint_type);
    m.joint_axis.push_back({b.axis[0], b.axis[1], b.axis[2]});
    m.X_tree.push_back({{b.E[0], b.E[1], b.E[2], b.E[3], b.E[4], b.E[5], b.E[6], b.E[7], b.E[8]},
                        {b.r[0], b.r[1], b.r[2]}});
    m.I.push_back({b.mass, {b.h[0], b.h[1], b.h[2]}, {b.I[0], b.I[1], b.I[2], b.I[3], b.I[4], b.I[5]}});
    m.body_name.emplace_back(b.body_name);
    m.joint_name.emplace_back(b.joint_name);
  }
  for (const FrameRecord& f : frames)
    m.frames.push_back({f.name, f.body,
                        {{f.E[0], f.E[1], f.E[2], f.E[3], f.E[4], f.E[5], f.E[6], f.E[7], f.E[8]},
                         {f.r[0], f.r[1], f.r[2]}}});
  if (!mimics.empty()) {
    std::vector<int> mimic(m.nbodies, -1);
    std::vector<double> multiplier(m.nbodies, 1), offset(m.nbodies, 0);
    for (const MimicRecord& r : mimics)
      mimic[r.body] = r.primary, multiplier[r.body] = r.multiplier, offset[r.body] = r.offset;
    couple(m, mimic, multiplier, offset);
  }
  m.armature.assign(armature.begin(), armature.end());
  std::vector<Constraint<double>> cs;
  const auto xform = [](const double(&E)[9], const double(&r)[3]) {
    return Xform<double>{{E[0], E[1], E[2], E[3], E[4], E[5], E[6], E[7], E[8]},
                         {r[0], r[1], r[2]}};
  };
  for (const ConstraintRecord& c : constraints)
    cs.push_back({c.name, c.body_a, xform(c.E_a, c.r_a), c.body_b, xform(c.E_b, c.r_b), c.rows == 6,
                  c.loop == 1});
  set_constraints(m, std::move(cs), settings);
  return m;
}

}  // namespace dyngen
