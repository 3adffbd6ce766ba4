// Builds a Model<double> from links and joints: orders bodies topologically, merges links
// attached by fixed joints into their parent body, and computes every model constant (frame
// rotations, first moments, inertias about body origins). The generator and users share it,
// so both paths see the same numbers. Knows nothing of file formats.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "dyngen/model.hpp"

namespace dyngen {

struct ModelError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A link's inertia as URDF gives it: mass, centre of mass c and the inertia tensor about c,
/// expressed in a frame rotated by R (columns: inertial axes in link coordinates).
struct LinkSpec {
  std::string name;
  double mass = 0;
  Vec3<double> com;
  Mat3<double> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Sym3<double> I_com;
};

/// Floating: a 6-DoF free joint (JointType::Free). Planar: motion in the plane normal to the
/// axis, built as a prismatic joint along one in-plane direction u, one along w = axis x u and
/// a revolute joint about the axis, the first two on massless bodies named after the joint.
/// Ball: a 3-DoF spherical joint about the child frame's origin (JointType::Ball).
enum class JointKind { Revolute, Prismatic, Fixed, Floating, Planar, Ball };

/// A joint: the child frame sits at xyz in the parent frame, rotated by R (columns: child axes
/// in parent coordinates); the axis is in child coordinates.
struct JointSpec {
  std::string name;
  JointKind kind = JointKind::Fixed;
  std::string parent, child;
  Vec3<double> xyz;
  Mat3<double> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3<double> axis{1, 0, 0};
  /// Rotor inertia (MuJoCo's armature) of each of the joint's degrees of freedom, kg m^2 about a
  /// revolute axis (each axis of a ball joint), kg along a prismatic one; a free joint has none.
  double armature = 0;
  /// A mimic joint (URDF's <mimic>) names the joint it follows, q = multiplier q_mimic + offset;
  /// it then has no coordinate of its own (Model::mimic).
  std::string mimic{};
  double multiplier = 1, offset = 0;
};

/// R from roll, pitch, yaw about fixed x, y, z axes: R = Rz(yaw) Ry(pitch) Rx(roll).
inline Mat3<double> rotation_from_rpy(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  return {cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
          sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
          -sp,     cp * sr,                cp * cr};
}

/// R from a unit quaternion (x, y, z, w).
inline Mat3<double> rotation_from_quaternion(double x, double y, double z, double w) {
  return {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
          2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
          2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
}

/// Inertia of a link about its own origin, in link coordinates:
/// I_o = R I_c R^T + m (|c|^2 1 - c c^T), h = m c (parallel axis theorem).
inline RigidInertia<double> link_inertia(const LinkSpec& link) {
  const Mat3<double>& R = link.R;
  const Mat3<double> RT{R.xx, R.yx, R.zx, R.xy, R.yy, R.zy, R.xz, R.yz, R.zz};
  const Sym3<double> Ic = rotate_T(RT, link.I_com);
  const double m = link.mass;
  const Vec3<double>& c = link.com;
  return {m, scale(c, m),
          {Ic.xx + m * (c.y * c.y + c.z * c.z), Ic.yy + m * (c.x * c.x + c.z * c.z),
           Ic.zz + m * (c.x * c.x + c.y * c.y), Ic.xy - m * c.x * c.y, Ic.xz - m * c.x * c.z,
           Ic.yz - m * c.y * c.z}};
}

/// The exponent e with 2^e <= v's largest component < 2^(e+1); 0 when v is zero or not finite.
/// Scaling v by 2^-e is exact and leaves squares that neither overflow nor underflow, and an
/// ordinary vector's length and direction the same bits.
inline int largest_exponent(const Vec3<double>& v) {
  const double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return largest > 0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
}

/// |v| without overflow or underflow in its squares: (1e-200, 0, 0) has length 1e-200.
inline double scaled_length(const Vec3<double>& v) {
  const int e = largest_exponent(v);
  const Vec3<double> s{std::ldexp(v.x, -e), std::ldexp(v.y, -e), std::ldexp(v.z, -e)};
  return std::ldexp(std::sqrt(dot(s, s)), e);
}

/// The largest magnitude of a model constant (mass, first moment, inertia, joint offset,
/// gravity). RNEA, CRBA and ABA multiply up to five of them together (a torque is a moment arm
/// times a mass times a distance times an acceleration) and sum such products over the robot:
/// with each constant at most 1e50, and chains of up to 1e5 links, they stay inside double's
/// range (1.8e308) with room for the states' own numbers.
inline constexpr double max_model_constant = 1e50;

namespace detail {

inline std::string number_text(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

/// "what (x, y, z) unit" followed by why the numbers are refused, if they are.
inline void check_constants(const std::string& what, std::initializer_list<double> xs,
                            const char* unit, double max_magnitude) {
  std::string values;
  bool finite = true, in_range = true;
  for (const double x : xs) {
    values += (values.empty() ? "" : ", ") + number_text(x);
    finite = finite && std::isfinite(x);
    in_range = in_range && std::abs(x) <= max_magnitude;
  }
  if (xs.size() > 1) values = "(" + values + ")";
  if (*unit) values += std::string(" ") + unit;
  if (!finite) throw ModelError(what + " " + values + " is not finite");
  if (!in_range)
    throw ModelError(what + " " + values + " exceeds " + number_text(max_magnitude) +
                     " in magnitude, beyond which RNEA, CRBA and ABA can overflow");
}

/// A mass or moment of inertia, which ABA divides by: zero, or a normal number.
inline void check_divisor(const std::string& what, double x, const char* unit) {
  if (x != 0 && std::abs(x) < std::numeric_limits<double>::min())
    throw ModelError(what + " " + number_text(x) + " " + unit + " is subnormal (below " +
                     number_text(std::numeric_limits<double>::min()) +
                     ", double's smallest normal number): products with it lose their digits, "
                     "and ABA's divisions by it overflow");
}

}  // namespace detail

/// Throws ModelError when gravity has a component that is not finite or above `max_magnitude`.
inline void check_gravity(const Vec3<double>& g, double max_magnitude = max_model_constant) {
  detail::check_constants("gravity", {g.x, g.y, g.z}, "m/s^2", max_magnitude);
}

/// Throws ModelError naming the body or joint and the field of the first model constant that
/// the algorithms cannot compute with: one that is not finite or exceeds `max_magnitude`, or a
/// mass or moment of inertia that is not zero but below double's normal range (ABA divides by
/// them, and 1 / a subnormal number overflows).
inline void check_model_numbers(const Model<double>& model,
                                double max_magnitude = max_model_constant) {
  check_gravity(model.gravity, max_magnitude);
  for (int i = 0; i < model.nbodies; ++i) {
    const std::string link = "link '" + model.body_name[i] + "': ";
    const std::string joint = "joint '" + model.joint_name[i] + "': ";
    const RigidInertia<double>& I = model.I[i];
    const Sym3<double>& J = I.I;
    const Xform<double>& X = model.X_tree[i];
    const Vec3<double>& k = model.joint_axis[i];
    detail::check_constants(link + "the mass", {I.m}, "kg", max_magnitude);
    detail::check_constants(link + "the first moment (mass times centre of mass)",
                            {I.h.x, I.h.y, I.h.z}, "kg m", max_magnitude);
    detail::check_constants(link + "the inertia about the link origin (xx, yy, zz, xy, xz, yz)",
                            {J.xx, J.yy, J.zz, J.xy, J.xz, J.yz}, "kg m^2", max_magnitude);
    detail::check_constants(joint + "the origin's position in the parent body",
                            {X.r.x, X.r.y, X.r.z}, "m", max_magnitude);
    const Mat3<double>& E = X.E;
    detail::check_constants(joint + "the origin's rotation",
                            {E.xx, E.xy, E.xz, E.yx, E.yy, E.yz, E.zx, E.zy, E.zz}, "",
                            max_magnitude);
    detail::check_constants(joint + "the axis", {k.x, k.y, k.z}, "", max_magnitude);
    detail::check_divisor(link + "the mass", I.m, "kg");
    detail::check_divisor(link + "the moment of inertia xx about the link origin", J.xx, "kg m^2");
    detail::check_divisor(link + "the moment of inertia yy about the link origin", J.yy, "kg m^2");
    detail::check_divisor(link + "the moment of inertia zz about the link origin", J.zz, "kg m^2");
    if (model.armature.empty()) continue;
    const double armature = model.armature[model.v_index[i]];
    const char* unit = model.joint_type[i] == JointType::Prismatic ? "kg" : "kg m^2";
    detail::check_constants(joint + "the armature", {armature}, unit, max_magnitude);
    detail::check_divisor(joint + "the armature", armature, unit);
    if (armature < 0)
      throw ModelError(joint + "the armature " + detail::number_text(armature) + " " + unit +
                       " is negative: a rotor inertia adds to M's diagonal");
  }
}

/// The kind of a revolute joint about unit axis k: its own kind only on an exact +-x, +-y, +-z.
inline JointType revolute_type(const Vec3<double>& k) {
  if (k.y == 0 && k.z == 0) return JointType::RevoluteX;
  if (k.x == 0 && k.z == 0) return JointType::RevoluteY;
  if (k.x == 0 && k.y == 0) return JointType::RevoluteZ;
  return JointType::Revolute;
}

/// What snap() found and changed.
struct SnapReport {
  int entries = 0;  // constants examined
  int exact = 0;    // already exactly 0 or +-1
  int snapped = 0;  // within the tolerance, now exact
  double largest_change = 0;  // relative to the entry's scale (1 for rotations and axes)
};

/// Snaps model constants that are within `tol` of exact values, so that the generated code
/// can drop the multiplications by 0 and 1 they stand for (URDF rotations come through
/// quaternions and rounded decimals, so an exact right angle arrives as 1e-17 and 0.99999...):
/// rotation and joint-axis entries within tol of 0 or +-1 (a free joint has no axis); products of inertia within tol times
/// the body's largest moment of 0; components of joint offsets and first moments within tol
/// times their vector's length of 0. A revolute joint whose axis becomes a coordinate axis gets
/// that axis's kind. This changes the model, by at most `tol` relative per constant.
inline SnapReport snap(Model<double>& model, double tol) {
  SnapReport report;
  // x to target when within tol * scale; true if x is (now) exactly the target
  const auto to = [&](double& x, double target, double scale) {
    if (x == target) {
      ++report.exact;
      return true;
    }
    if (!(std::abs(x - target) <= tol * scale)) return false;
    report.largest_change = std::max(report.largest_change, std::abs(x - target) / scale);
    ++report.snapped;
    x = target;
    return true;
  };
  const auto unit_entry = [&](double& x) {
    ++report.entries;
    to(x, 0, 1) || to(x, 1, 1) || to(x, -1, 1);
  };
  const auto small_entry = [&](double& x, double scale) {
    ++report.entries;
    to(x, 0, scale);
  };
  const auto vector = [&](Vec3<double>& v) {
    const double length = std::sqrt(dot(v, v));
    for (double* x : {&v.x, &v.y, &v.z}) small_entry(*x, length);
  };
  for (int i = 0; i < model.nbodies; ++i) {
    Mat3<double>& E = model.X_tree[i].E;
    for (double* x : {&E.xx, &E.xy, &E.xz, &E.yx, &E.yy, &E.yz, &E.zx, &E.zy, &E.zz})
      unit_entry(*x);
    vector(model.X_tree[i].r);
    vector(model.I[i].h);
    Sym3<double>& J = model.I[i].I;
    const double moment = std::max({J.xx, J.yy, J.zz});
    for (double* x : {&J.xy, &J.xz, &J.yz}) small_entry(*x, moment);
    if (quaternion_offset(model.joint_type[i]) >= 0) continue;  // no axis
    Vec3<double>& k = model.joint_axis[i];
    for (double* x : {&k.x, &k.y, &k.z}) unit_entry(*x);
    if (!is_revolute(model.joint_type[i])) continue;
    model.joint_type[i] = revolute_type(k);
  }
  return report;
}

class ModelBuilder {
 public:
  void add_link(const LinkSpec& link) {
    if (link_index_.count(link.name)) throw ModelError("link '" + link.name + "' is defined twice");
    link_index_[link.name] = static_cast<int>(links_.size());
    links_.push_back(link);
  }

  void add_joint(const JointSpec& joint) {
    if (!is_rotation(joint.R))
      throw ModelError("joint '" + joint.name + "': the origin rotation is not a rotation matrix");
    if (!joint_index_.emplace(joint.name, joints_.size()).second)
      throw ModelError("joint '" + joint.name + "' is defined twice");
    joints_.push_back(joint);
    if (joint.armature != 0) set_armature(joint.name, joint.armature);
  }

  /// Sets a moving joint's armature (JointSpec::armature).
  void set_armature(const std::string& joint_name, double armature) {
    const auto it = joint_index_.find(joint_name);
    if (it == joint_index_.end())
      throw ModelError("cannot give joint '" + joint_name + "' an armature: no joint of that name");
    JointSpec& joint = joints_[it->second];
    if (joint.kind == JointKind::Fixed || joint.kind == JointKind::Floating)
      throw ModelError("joint '" + joint_name + "' is " +
                       (joint.kind == JointKind::Fixed ? "fixed" : "floating") +
                       ": only a revolute, prismatic, planar or ball joint has an armature");
    joint.armature = armature;
  }

  /// Makes joint `joint_name` follow q = multiplier q_primary + offset (JointSpec::mimic).
  void set_mimic(const std::string& joint_name, const std::string& primary, double multiplier,
                 double offset) {
    const auto it = joint_index_.find(joint_name);
    if (it == joint_index_.end())
      throw ModelError("cannot make joint '" + joint_name + "' a mimic joint: no joint of that name");
    JointSpec& joint = joints_[it->second];
    joint.mimic = primary, joint.multiplier = multiplier, joint.offset = offset;
  }

  /// Turns a joint into a fixed one, at q = 0.
  void lock(const std::string& joint_name) {
    const auto it = joint_index_.find(joint_name);
    if (it == joint_index_.end())
      throw ModelError("cannot lock joint '" + joint_name + "': no joint of that name");
    joints_[it->second].kind = JointKind::Fixed;
  }

  const std::vector<LinkSpec>& links() const { return links_; }
  const std::vector<JointSpec>& joints() const { return joints_; }

  /// The model rooted at the one link without a parent joint. That link is fixed to the world,
  /// or with floating_base it is body 0, on a free joint named "floating_base" whose frame is
  /// the root link's.
  Model<double> build(const Vec3<double>& gravity, bool floating_base = false) const {
    const int nlinks = static_cast<int>(links_.size());
    std::vector<int> parent_joint(nlinks, -1);
    std::vector<std::vector<int>> child_joints(nlinks);
    for (int j = 0; j < static_cast<int>(joints_.size()); ++j) {
      const JointSpec& joint = joints_[j];
      const int p = find_link(joint.parent, joint.name, "parent");
      const int c = find_link(joint.child, joint.name, "child");
      if (parent_joint[c] >= 0)
        throw ModelError("link '" + joint.child + "' has two parent joints, '" +
                         joints_[parent_joint[c]].name + "' and '" + joint.name +
                         "' (the tree has a loop)");
      parent_joint[c] = j;
      child_joints[p].push_back(j);
    }
    std::vector<int> roots;
    for (int l = 0; l < nlinks; ++l)
      if (parent_joint[l] < 0) roots.push_back(l);
    if (roots.size() != 1) {
      std::string names;
      for (std::size_t k = 0; k < roots.size() && k < 10; ++k)
        names += (names.empty() ? "'" : ", '") + links_[roots[k]].name + "'";
      if (roots.size() > 10) names += " and " + std::to_string(roots.size() - 10) + " more";
      throw ModelError(roots.empty() ? "no root link: every link has a parent (the tree has a loop)"
                                     : "more than one root link: " + names);
    }

    Model<double> model;
    model.gravity = gravity;
    int root_body = -1;
    if (floating_base) {
      root_body = add_body(model, -1, identity(), JointType::Free, {0, 0, 0}, "floating_base",
                           links_[roots[0]].name, link_inertia(links_[roots[0]]), 0);
    }
    const int visited = visit(model, child_joints, roots[0], root_body);
    if (visited != nlinks)
      throw ModelError("some links are not connected to the root link '" + links_[roots[0]].name +
                       "' (the tree has a loop)");
    couple_mimics(model);
    if (std::all_of(model.armature.begin(), model.armature.end(),
                    [](double x) { return x == 0; }))
      model.armature.clear();
    check_model_numbers(model);
    return model;
  }

 private:
  // Depth-first from the root link, which belongs to body `root_body` (-1: the fixed base), with
  // an explicit stack (a chain of many links would overflow the call stack). Bodies are
  // numbered in preorder, so parent < child; links on fixed joints add their inertia to their
  // body, in the same order. Returns the links visited.
  int visit(Model<double>& model, const std::vector<std::vector<int>>& child_joints, int root,
            int root_body) const {
    struct Visit {
      int link, body;
      Xform<double> X_link_body;  // the link's frame from its body's
      std::size_t next = 0;       // its next child joint
    };
    std::vector<Visit> stack{{root, root_body, identity()}};
    model.frames.push_back({links_[root].name, root_body, identity()});
    int visited = 1;
    while (!stack.empty()) {
      Visit& top = stack.back();
      if (top.next == child_joints[top.link].size()) {
        stack.pop_back();
        continue;
      }
      const JointSpec& joint = joints_[child_joints[top.link][top.next++]];
      const int body = top.body;
      const int c = link_index_.at(joint.child);
      const Xform<double> X_child_body = compose(Xform<double>{transpose(joint.R), joint.xyz},
                                                 top.X_link_body);
      ++visited;
      if (joint.kind == JointKind::Fixed) {
        // a massless frame adds nothing, and is not moved (0 times an offset beyond double's
        // range would be NaN, blamed on the body's inertia)
        if (body >= 0 && !is_massless(links_[c]))
          model.I[body] = model.I[body] + apply_inertia_T(X_child_body, link_inertia(links_[c]));
        model.frames.push_back({links_[c].name, body, X_child_body});
        stack.push_back({c, body, X_child_body});
      } else if (joint.kind == JointKind::Planar) {
        const Vec3<double> n = unit_axis(joint);
        const Vec3<double> u = in_plane_direction(n);
        const Vec3<double> w = cross(n, u);
        const int bu = add_body(model, body, X_child_body, JointType::Prismatic, u,
                                joint.name + ":u", links_[c].name + ":u", {}, joint.armature);
        const int bw = add_body(model, bu, identity(), JointType::Prismatic, w,
                                joint.name + ":w", links_[c].name + ":w", {}, joint.armature);
        const int b = add_body(model, bw, identity(), revolute_type(n), n, joint.name + ":rot",
                               links_[c].name, link_inertia(links_[c]), joint.armature);
        model.frames.push_back({links_[c].name, b, identity()});
        stack.push_back({c, b, identity()});
      } else {
        const bool axial = joint.kind != JointKind::Floating && joint.kind != JointKind::Ball;
        const JointType type = joint.kind == JointKind::Floating  ? JointType::Free
                               : joint.kind == JointKind::Ball      ? JointType::Ball
                               : joint.kind == JointKind::Prismatic ? JointType::Prismatic
                                                                    : revolute_type(unit_axis(joint));
        const Vec3<double> axis = axial ? unit_axis(joint) : Vec3<double>{0, 0, 0};
        if (type == JointType::Free && joint.armature != 0)
          throw ModelError("joint '" + joint.name + "' is floating: a free joint has no armature");
        const int b = add_body(model, body, X_child_body, type, axis, joint.name, links_[c].name,
                               link_inertia(links_[c]), joint.armature);
        model.frames.push_back({links_[c].name, b, identity()});
        stack.push_back({c, b, identity()});
      }
    }
    return visited;
  }

  /// The body of moving joint `name`, or -1.
  static int joint_body(const Model<double>& model, const std::string& name) {
    for (int i = 0; i < model.nbodies; ++i)
      if (model.joint_name[i] == name) return i;
    return -1;
  }

  /// Gives each mimic joint its primary's coordinate (Model::mimic) and numbers the others'
  /// again, dropping the mimic joints' entries of the armature.
  void couple_mimics(Model<double>& model) const {
    std::vector<int> mimic(model.nbodies, -1);
    std::vector<double> multiplier(model.nbodies, 1), offset(model.nbodies, 0);
    for (const JointSpec& joint : joints_) {
      if (joint.mimic.empty() || joint.kind == JointKind::Fixed) continue;
      const std::string what = "mimic joint '" + joint.name + "' follows '" + joint.mimic + "'";
      const int m = joint_body(model, joint.name), p = joint_body(model, joint.mimic);
      if (joint.kind != JointKind::Revolute && joint.kind != JointKind::Prismatic)
        throw ModelError(what + ": only a revolute or prismatic joint can mimic another");
      if (p < 0 || !(is_revolute(model.joint_type[p]) || model.joint_type[p] == JointType::Prismatic))
        throw ModelError(what + ", which is not a moving revolute or prismatic joint (a fixed or "
                         "locked one: lock the mimic joint too)");
      if (joint.armature != 0) throw ModelError(what + ": a mimic joint has no armature of its own");
      mimic[m] = p, multiplier[m] = joint.multiplier, offset[m] = joint.offset;
    }
    for (int i = 0; i < model.nbodies; ++i)
      if (mimic[i] >= 0 && mimic[mimic[i]] >= 0)
        throw ModelError("mimic joint '" + model.joint_name[i] + "' follows '" +
                         model.joint_name[mimic[i]] + "', itself a mimic joint");
    if (std::all_of(mimic.begin(), mimic.end(), [](int p) { return p < 0; })) return;
    couple(model, mimic, multiplier, offset);
  }

  static int add_body(Model<double>& model, int parent, const Xform<double>& X_tree,
                      JointType type, const Vec3<double>& axis, const std::string& joint_name,
                      const std::string& body_name, const RigidInertia<double>& inertia,
                      double armature) {
    model.armature.insert(model.armature.end(), joint_nv(type), armature);
    model.parent.push_back(parent);
    model.X_tree.push_back(X_tree);
    model.joint_type.push_back(type);
    model.joint_axis.push_back(axis);
    model.q_index.push_back(model.nq);
    model.v_index.push_back(model.nv);
    model.nq += joint_nq(type);
    model.nv += joint_nv(type);
    model.body_name.push_back(body_name);
    model.joint_name.push_back(joint_name);
    model.I.push_back(inertia);
    return model.nbodies++;
  }

  /// Orthonormal with determinant +1, to 1e-9 (URDF rotations come from rpy or quaternions).
  static bool is_rotation(const Mat3<double>& R) {
    const Mat3<double> P = mul(transpose(R), R);
    const double off = std::abs(P.xy) + std::abs(P.xz) + std::abs(P.yz) + std::abs(P.yx) +
                       std::abs(P.zx) + std::abs(P.zy);
    const double diag = std::abs(P.xx - 1) + std::abs(P.yy - 1) + std::abs(P.zz - 1);
    const Vec3<double> c0{R.xx, R.yx, R.zx}, c1{R.xy, R.yy, R.zy}, c2{R.xz, R.yz, R.zz};
    return off + diag < 1e-9 && dot(cross(c0, c1), c2) > 0;
  }

  static bool is_massless(const LinkSpec& link) {
    const Sym3<double>& I = link.I_com;
    return link.mass == 0 && I.xx == 0 && I.yy == 0 && I.zz == 0 && I.xy == 0 && I.xz == 0 &&
           I.yz == 0;
  }

  static Xform<double> identity() { return {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}}; }

  int find_link(const std::string& name, const std::string& joint, const char* role) const {
    const auto it = link_index_.find(name);
    if (it == link_index_.end())
      throw ModelError(std::string(role) + " link '" + name + "' of joint '" + joint +
                       "' is not defined");
    return it->second;
  }

  /// Any finite non-zero axis is a direction, (1e300, 0, 0) and (1e-200, 0, 0) too.
  static Vec3<double> unit_axis(const JointSpec& joint) {
    const int e = largest_exponent(joint.axis);
    const Vec3<double> a{std::ldexp(joint.axis.x, -e), std::ldexp(joint.axis.y, -e),
                         std::ldexp(joint.axis.z, -e)};
    const double norm = std::sqrt(dot(a, a));
    if (!(norm > 0) || !std::isfinite(norm))
      throw ModelError("joint '" + joint.name + "' has a zero or non-finite axis");
    return norm == 1 ? a : Vec3<double>{a.x / norm, a.y / norm, a.z / norm};
  }

  /// A unit vector normal to n: the coordinate axis least aligned with n, made orthogonal to
  /// it (exactly x or y for n = +-z, and so on).
  static Vec3<double> in_plane_direction(const Vec3<double>& n) {
    const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    const Vec3<double> e = ax <= ay && ax <= az ? Vec3<double>{1, 0, 0}
                           : ay <= az           ? Vec3<double>{0, 1, 0}
                                                : Vec3<double>{0, 0, 1};
    const Vec3<double> u = e - scale(n, dot(n, e));
    const double norm = std::sqrt(dot(u, u));
    return norm == 1 ? u : scale(u, 1 / norm);
  }

  std::vector<LinkSpec> links_;
  std::vector<JointSpec> joints_;
  std::map<std::string, int> link_index_;
  std::map<std::string, std::size_t> joint_index_;
};

}  // namespace dyngen
