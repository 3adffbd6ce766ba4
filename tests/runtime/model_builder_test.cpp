// ModelBuilder: merging links on fixed joints into their parent body, locking joints, the
// choice of axis-aligned joint kinds, topological order, and the errors it reports.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <map>
#include <numbers>

#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

/// prefix followed by k ("L3"), built by appending: GCC 12's -Wrestrict misfires on
/// "L" + std::to_string(k).
std::string numbered(const char* prefix, int k) {
  std::string s(prefix);
  s += std::to_string(k);
  return s;
}

using Vector = Eigen::VectorXd;
using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;
using test::dense;

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double pi = std::numbers::pi;

Mat3<double> rpy(double r, double p, double y) { return rotation_from_rpy(r, p, y); }

LinkSpec link(const std::string& name, double mass, const Vec3<double>& com,
              const Sym3<double>& I_com, const Mat3<double>& R = {1, 0, 0, 0, 1, 0, 0, 0, 1}) {
  return {.name = name, .mass = mass, .com = com, .R = R, .I_com = I_com};
}

JointSpec joint(const std::string& name, JointKind kind, const std::string& parent,
                const std::string& child, const Vec3<double>& xyz, const Mat3<double>& R,
                const Vec3<double>& axis) {
  return {.name = name,
          .kind = kind,
          .parent = parent,
          .child = child,
          .xyz = xyz,
          .R = R,
          .axis = axis};
}

/// A five-link arm: a pedestal fixed to the base (its inertia is lost to the fixed base),
/// shoulder and elbow joints, a link on the joint `mount` (of the given kind) in the middle of
/// the chain, a wrist after it and a tool fixed to the wrist.
ModelBuilder arm(JointKind mount) {
  ModelBuilder b;
  b.add_link(link("base", 0, {}, {}));
  b.add_link(link("pedestal", 4.0, {0, 0, 0.1}, {0.1, 0.1, 0.05}));
  b.add_link(link("upper", 2.0, {0.1, 0.02, 0.3}, {0.05, 0.06, 0.01}, rpy(0.1, 0.2, 0.3)));
  b.add_link(link("fore", 1.5, {0.25, -0.01, 0.02}, {0.01, 0.04, 0.04}));
  b.add_link(link("camera", 0.7, {0.03, 0.05, -0.02}, {0.002, 0.003, 0.004}, rpy(-0.4, 0.5, 1)));
  b.add_link(link("wrist", 0.6, {0.02, 0.01, 0.05}, {0.003, 0.003, 0.002}));
  b.add_link(link("tool", 0.4, {0, 0, 0.08}, {0.001, 0.001, 0.0005}));
  b.add_joint(joint("fix_pedestal", JointKind::Fixed, "base", "pedestal", {0, 0, 0.2},
                    rpy(0, 0, 0.7), {1, 0, 0}));
  b.add_joint(joint("shoulder", JointKind::Revolute, "pedestal", "upper", {0, 0, 0.3}, rpy(0, 0, 0),
                    {0, 0, 1}));
  b.add_joint(joint("elbow", JointKind::Revolute, "upper", "fore", {0.05, 0.1, 0.6},
                    rpy(pi / 2, 0, 0.2), {0, 1, 0}));
  b.add_joint(joint("mount", mount, "fore", "camera", {0.5, 0.03, -0.04}, rpy(0.3, -0.2, 0.9),
                    {0.36, 0.48, 0.8}));
  b.add_joint(joint("wrist", JointKind::Revolute, "camera", "wrist", {0.1, -0.05, 0.07},
                    rpy(-0.6, 0.1, 0.4), {1, 1, 0}));
  b.add_joint(joint("fix_tool", JointKind::Fixed, "wrist", "tool", {0, 0.02, 0.12},
                    rpy(0.2, 0.3, -0.1), {1, 0, 0}));
  return b;
}

/// World poses of every link straight from the specs: each joint places its child at
/// (R, xyz) in the parent frame, turned by q about its axis (angle-axis through Eigen).
struct LinkPose {
  Matrix3 R;
  Vector3 p;
};

std::map<std::string, LinkPose> link_poses(const ModelBuilder& b,
                                           const std::map<std::string, double>& q) {
  std::map<std::string, LinkPose> pose{{"base", {Matrix3::Identity(), Vector3::Zero()}}};
  // the joints are listed parent first
  for (const JointSpec& j : b.joints()) {
    const LinkPose& parent = pose.at(j.parent);
    const auto it = q.find(j.name);
    const double angle = it == q.end() ? 0.0 : it->second;
    const Matrix3 R = parent.R * dense(j.R) *
                      Eigen::AngleAxisd(angle, dense(j.axis).normalized()).toRotationMatrix();
    pose[j.child] = {R, parent.p + parent.R * dense(j.xyz)};
  }
  return pose;
}

/// Total mass and centre of mass of the links that move (all but base and pedestal).
std::pair<double, Vector3> mass_and_com_from_specs(const ModelBuilder& b,
                                                   const std::map<std::string, double>& q) {
  const auto pose = link_poses(b, q);
  double m = 0;
  Vector3 mc = Vector3::Zero();
  for (const LinkSpec& l : b.links()) {
    if (l.name == "base" || l.name == "pedestal") continue;
    m += l.mass;
    mc += l.mass * (pose.at(l.name).p + pose.at(l.name).R * dense(l.com));
  }
  return {m, mc / m};
}

/// Total mass and centre of mass of a model's bodies, composing the joint transforms.
std::pair<double, Vector3> mass_and_com(const Model<double>& model, const Vector& q) {
  std::vector<Matrix3> R(model.nbodies);
  std::vector<Vector3> p(model.nbodies);
  double m = 0;
  Vector3 mc = Vector3::Zero();
  for (int i = 0; i < model.nbodies; ++i) {
    const Xform<double> X = joint_transform(model, i, &q[model.q_index[i]]);
    const int parent = model.parent[i];
    const Matrix3 R_p = parent < 0 ? Matrix3::Identity() : R[parent];
    R[i] = R_p * dense(X.E).transpose();
    p[i] = (parent < 0 ? Vector3::Zero() : p[parent]) + R_p * dense(X.r);
    m += model.I[i].m;
    mc += model.I[i].m * p[i] + R[i] * dense(model.I[i].h);
  }
  return {m, mc / m};
}

Eigen::MatrixXd mass_matrix(const Model<double>& model, const Vector& q) {
  Workspace<double> ws(model);
  std::vector<double> M(model.nv * model.nv);
  crba<double>(model, ws, std::span(q.data(), q.size()), M);
  return test::to_eigen(M, model.nv);
}

int body_index(const Model<double>& model, const std::string& name) {
  const auto it = std::find(model.body_name.begin(), model.body_name.end(), name);
  return it == model.body_name.end() ? -1 : static_cast<int>(it - model.body_name.begin());
}

TEST(ModelBuilder, RotationsMatchTheirDefinitions) {
  // rpy: R = Rz(yaw) Ry(pitch) Rx(roll) about fixed axes (URDF); quaternion (x, y, z, w)
  test::Random rng(53);
  for (int k = 0; k < 100; ++k) {
    const double r = rng.uniform(-pi, pi), p = rng.uniform(-pi, pi), y = rng.uniform(-pi, pi);
    const Matrix3 R =
        (Eigen::AngleAxisd(y, Vector3::UnitZ()) * Eigen::AngleAxisd(p, Vector3::UnitY()) *
         Eigen::AngleAxisd(r, Vector3::UnitX()))
            .toRotationMatrix();
    EXPECT_LE((dense(rotation_from_rpy(r, p, y)) - R).cwiseAbs().maxCoeff(), 8 * eps);
    const Eigen::Quaterniond quat = Eigen::Quaterniond(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                                       rng.uniform(-1, 1), rng.uniform(-1, 1))
                                        .normalized();
    EXPECT_LE((dense(rotation_from_quaternion(quat.x(), quat.y(), quat.z(), quat.w())) -
               quat.toRotationMatrix())
                  .cwiseAbs()
                  .maxCoeff(),
              8 * eps);
  }
}

TEST(ModelBuilder, LinkInertiaIsTheInertiaAtTheCentreOfMassTransformed) {
  // I_O = X^T diag(I_C, m 1) X, with X = rot(R^T) xlt(c) from the link frame O to the centre
  // of mass frame C whose axes are R's columns (RBDA eq. 2.66, dense)
  test::Random rng(54);
  for (int k = 0; k < 100; ++k) {
    const LinkSpec l =
        link("l", rng.uniform(0.1, 5), {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)},
             {rng.uniform(0.5, 1), rng.uniform(0.5, 1), rng.uniform(0.5, 1), rng.uniform(-0.2, 0.2),
              rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2)},
             rpy(rng.uniform(-pi, pi), rng.uniform(-pi, pi), rng.uniform(-pi, pi)));
    test::Matrix6<double> I_C = test::Matrix6<double>::Zero();
    I_C.topLeftCorner<3, 3>() = dense(l.I_com);
    I_C.bottomRightCorner<3, 3>() = l.mass * Matrix3::Identity();
    const Mat3<double>& R = l.R;
    const test::Matrix6<double> X =
        dense(Xform<double>{{R.xx, R.yx, R.zx, R.xy, R.yy, R.zy, R.xz, R.yz, R.zz}, l.com});
    const test::Matrix6<double> I_O = X.transpose() * I_C * X;
    EXPECT_LE((dense(link_inertia(l)) - I_O).cwiseAbs().maxCoeff(),
              16 * eps * I_O.cwiseAbs().maxCoeff());
  }
}

TEST(ModelBuilder, FixedJointsMergeIntoParentBody) {
  const Model<double> fixed = arm(JointKind::Fixed).build({0, 0, -9.81});
  ModelBuilder locked_builder = arm(JointKind::Revolute);
  locked_builder.lock("mount");
  const Model<double> locked = locked_builder.build({0, 0, -9.81});
  const Model<double> free = arm(JointKind::Revolute).build({0, 0, -9.81});
  ASSERT_EQ(fixed.nv, 3);
  ASSERT_EQ(locked.nv, 3);
  ASSERT_EQ(free.nv, 4);
  EXPECT_EQ(fixed.body_name, (std::vector<std::string>{"upper", "fore", "wrist"}));
  const int mount = body_index(free, "camera");
  ASSERT_GE(mount, 0);

  test::Random rng(51);
  for (int k = 0; k < 20; ++k) {
    const Vector q = test::to_eigen(rng.vector(3, -pi, pi));
    // the free model at q_mount = 0, with the mount's coordinate inserted
    Vector q_free(4);
    q_free << q.head(mount), 0.0, q.tail(3 - mount);

    // mass and centre of mass: every model against the links placed from their specs
    const auto [m_spec, c_spec] = mass_and_com_from_specs(
        arm(JointKind::Fixed), {{"shoulder", q[0]}, {"elbow", q[1]}, {"wrist", q[2]}});
    for (const auto& [name, model, x] :
         {std::tuple{"fixed", &fixed, q}, {"locked", &locked, q}, {"free", &free, q_free}}) {
      const auto [m, c] = mass_and_com(*model, x);
      EXPECT_NEAR(m, m_spec, 4 * eps * m_spec) << name;
      EXPECT_LE((c - c_spec).cwiseAbs().maxCoeff(), 64 * eps) << name;
    }

    // M: locking is merging, bit for bit; and the merged model's M is the free model's at
    // q_mount = 0 without the mount's row and column
    const Eigen::MatrixXd M = mass_matrix(fixed, q);
    EXPECT_EQ(mass_matrix(locked, q), M);
    const Eigen::MatrixXd M_free = mass_matrix(free, q_free);
    std::vector<int> keep;
    for (int i = 0; i < 4; ++i)
      if (i != mount) keep.push_back(i);
    EXPECT_LE((M_free(keep, keep) - M).cwiseAbs().maxCoeff(), 64 * eps * M.cwiseAbs().maxCoeff());
  }
}

TEST(ModelBuilder, AxisKindsOnlyForExactAxes) {
  const std::pair<Vec3<double>, JointType> axes[] = {
      {{1, 0, 0}, JointType::RevoluteX},      {{-1, 0, 0}, JointType::RevoluteX},
      {{0, 1, 0}, JointType::RevoluteY},      {{0, -1, 0}, JointType::RevoluteY},
      {{0, 0, 1}, JointType::RevoluteZ},      {{0, 0, -1}, JointType::RevoluteZ},
      {{0, 0, 2.5}, JointType::RevoluteZ},    {{1e-17, 0, 1}, JointType::Revolute},
      {{0, 1e-300, -1}, JointType::Revolute}, {{0.6, 0.8, 0}, JointType::Revolute},
      {{1, 1, 1}, JointType::Revolute},
  };
  for (const auto& [axis, type] : axes) {
    ModelBuilder b;
    b.add_link(link("base", 0, {}, {}));
    b.add_link(link("body", 1, {0.1, 0.2, 0.3}, {0.1, 0.1, 0.1}));
    b.add_joint(joint("j", JointKind::Revolute, "base", "body", {}, rpy(0.1, 0.2, 0.3), axis));
    const Model<double> model = b.build({0, 0, -9.81});
    EXPECT_EQ(model.joint_type[0], type) << dense(axis).transpose();
    const Vec3<double>& k = model.joint_axis[0];
    EXPECT_NEAR(std::sqrt(dot(k, k)), 1.0, eps);
    EXPECT_LE((dense(k) - dense(axis).normalized()).cwiseAbs().maxCoeff(), eps);
  }
}

/// Every joint's kind matches its axis: RevoluteX/Y/Z exactly on +-x/y/z, Revolute never.
void expect_axis_kinds(const Model<double>& model, const std::string& name) {
  for (int i = 0; i < model.nbodies; ++i) {
    const Vec3<double>& k = model.joint_axis[i];
    const bool x = k.y == 0 && k.z == 0, y = k.x == 0 && k.z == 0, z = k.x == 0 && k.y == 0;
    switch (model.joint_type[i]) {
      case JointType::RevoluteX: EXPECT_TRUE(x && std::abs(k.x) == 1) << name; break;
      case JointType::RevoluteY: EXPECT_TRUE(y && std::abs(k.y) == 1) << name; break;
      case JointType::RevoluteZ: EXPECT_TRUE(z && std::abs(k.z) == 1) << name; break;
      case JointType::Revolute: EXPECT_FALSE(x || y || z) << name; break;
      case JointType::Prismatic:
      case JointType::Free:
      case JointType::Ball: break;
    }
  }
}

TEST(ModelBuilder, PlanarAndFloatingJointsAnywhere) {
  const Model<double> model =
      gen::load_robot(test::model_path("coverage/all_joints.urdf")).model;
  EXPECT_EQ(model.nq, model.nv + 1);
  auto body = [&](const std::string& name) {
    const auto it = std::find(model.body_name.begin(), model.body_name.end(), name);
    EXPECT_NE(it, model.body_name.end()) << name;
    return static_cast<int>(it - model.body_name.begin());
  };
  // planar: two massless prismatic bodies along orthonormal in-plane directions u and w = n x u,
  // then the link itself, turning about n
  const int u = body("puck:u"), w = body("puck:w"), rot = body("puck");
  EXPECT_EQ(model.parent[w], u);
  EXPECT_EQ(model.parent[rot], w);
  EXPECT_EQ(model.joint_name[u], "table_plane:u");
  EXPECT_EQ(model.joint_type[u], JointType::Prismatic);
  EXPECT_EQ(model.joint_type[w], JointType::Prismatic);
  EXPECT_EQ(model.joint_type[rot], JointType::RevoluteZ);
  EXPECT_EQ(model.I[u].m, 0.0);
  EXPECT_EQ(model.I[w].m, 0.0);
  EXPECT_EQ(dense(model.joint_axis[u]), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(dense(model.joint_axis[w]), Eigen::Vector3d(0, 1, 0));
  // floating below the elbow: a free joint with seven q entries, at the joint's origin
  const int drone = body("drone");
  EXPECT_EQ(model.joint_type[drone], JointType::Free);
  EXPECT_EQ(model.body_name[model.parent[drone]], "arm");
  EXPECT_EQ(model.q_index[drone] - model.v_index[drone], 0);
  EXPECT_EQ(model.q_index[drone + 1] - model.q_index[drone], 7);
  EXPECT_EQ(model.v_index[drone + 1] - model.v_index[drone], 6);
}

/// Bodies in topological order: parent[i] < i, one coordinate each, in body order.
void expect_topological(const Model<double>& model, const std::string& name) {
  ASSERT_EQ(model.parent.size(), std::size_t(model.nbodies)) << name;
  EXPECT_EQ(model.nq, model.nbodies) << name;
  EXPECT_EQ(model.nv, model.nbodies) << name;
  for (int i = 0; i < model.nbodies; ++i) {
    EXPECT_GE(model.parent[i], -1) << name;
    EXPECT_LT(model.parent[i], i) << name;
    EXPECT_EQ(model.q_index[i], i) << name;
  }
}

TEST(ModelBuilder, SharedRobotsAndRandomChains) {
  for (const test::RobotFile& robot : test::robot_files()) {
    const Model<double> model = gen::load_robot(robot.path, robot.options).model;
    expect_topological(model, robot.name);
    expect_axis_kinds(model, robot.name);
  }
  for (int seed = 0; seed < 10; ++seed) {
    const Model<double> model = test::make_random_chain(12, seed, false);
    expect_topological(model, "spatial chain");
    expect_axis_kinds(model, "spatial chain");
  }
}

TEST(ModelBuilder, RandomTreesInShuffledOrder) {
  // Links and joints added in random order, some joints fixed: bodies come out parent first,
  // and each body's parent is the body of its nearest ancestor link on a moving joint.
  test::Random rng(52);
  for (int trial = 0; trial < 50; ++trial) {
    const int nlinks = 2 + rng.index(20);
    std::vector<int> parent_link(nlinks, -1);
    std::vector<bool> fixed(nlinks, false);
    std::vector<int> order(nlinks);
    for (int l = 1; l < nlinks; ++l) {
      parent_link[l] = rng.index(l);
      fixed[l] = rng.chance(0.3);
    }
    for (int l = 0; l < nlinks; ++l) order[l] = l;
    for (int l = nlinks - 1; l > 0; --l) std::swap(order[l], order[rng.index(l + 1)]);
    auto name = [](int l) { return numbered("L", l); };
    ModelBuilder b;
    for (const int l : order) b.add_link(link(name(l), 1, {0.1, 0, 0}, {0.1, 0.1, 0.1}));
    for (const int l : order)
      if (l > 0)
        b.add_joint(joint(numbered("J", l),
                          fixed[l] ? JointKind::Fixed : JointKind::Revolute, name(parent_link[l]),
                          name(l), {0.1, 0.2, 0}, rpy(0, 0, 0), {0, 0, 1}));
    const Model<double> model = b.build({0, 0, -9.81});
    expect_topological(model, numbered("trial ", trial));
    EXPECT_EQ(model.nbodies, std::count(fixed.begin() + 1, fixed.end(), false));
    for (int i = 0; i < model.nbodies; ++i) {
      const int l = std::stoi(model.body_name[i].substr(1));
      EXPECT_EQ(model.joint_name[i], numbered("J", l));
      int a = parent_link[l];
      while (a > 0 && fixed[a]) a = parent_link[a];
      EXPECT_EQ(model.parent[i], a <= 0 ? -1 : body_index(model, name(a)));
    }
  }
}

/// Runs f, which must throw a ModelError whose message contains `text`.
template <class F>
void expect_model_error(F f, const std::string& text) {
  try {
    f();
    ADD_FAILURE() << "no ModelError; expected one saying '" << text << "'";
  } catch (const ModelError& e) {
    EXPECT_TRUE(std::string(e.what()).find(text) != std::string::npos)
        << "message '" << e.what() << "' does not say '" << text << "'";
  }
}

/// Links base, a, b, c and joints from the (parent, child) pairs.
ModelBuilder tree(const std::vector<std::pair<std::string, std::string>>& joints) {
  ModelBuilder b;
  for (const char* name : {"base", "a", "b", "c"}) b.add_link(link(name, 1, {}, {1, 1, 1}));
  for (const auto& [parent, child] : joints)
    b.add_joint(joint(parent + "_" + child, JointKind::Revolute, parent, child, {}, rpy(0, 0, 0),
                      {0, 0, 1}));
  return b;
}

// snap(): a right angle that arrives through rpy and an axis with a 1e-17 component become
// exact, while entries farther from 0 and 1 than the tolerance stay as they are.
TEST(ModelBuilder, SnapMakesNearExactConstantsExact) {
  ModelBuilder b;
  b.add_link(link("base", 0, {}, {}));
  b.add_link(link("body", 1, {0.1, 1e-18, 0.3}, {0.1, 0.2, 0.3}));
  b.add_joint(joint("j", JointKind::Revolute, "base", "body", {0.5, 1e-17, 0},
                    rpy(std::numbers::pi / 2, 0, 0), {1e-17, 0, 1}));
  Model<double> model = b.build({0, 0, -9.81});
  const Model<double> before = model;
  ASSERT_EQ(model.joint_type[0], JointType::Revolute);
  const SnapReport report = snap(model, 1e-9);

  EXPECT_EQ(model.joint_type[0], JointType::RevoluteZ);
  const Mat3<double>& E = model.X_tree[0].E;
  for (const double x : {E.xx, E.xy, E.xz, E.yx, E.yy, E.yz, E.zx, E.zy, E.zz})
    EXPECT_TRUE(x == 0 || x == 1 || x == -1) << x;
  EXPECT_EQ(model.X_tree[0].r.y, 0.0);
  EXPECT_EQ(model.X_tree[0].r.x, 0.5);
  EXPECT_EQ(model.I[0].h.y, 0.0);
  EXPECT_EQ(model.I[0].h.x, before.I[0].h.x);
  EXPECT_GT(report.snapped, 0);
  EXPECT_GT(report.exact, 0);
  EXPECT_LE(report.largest_change, 1e-9);
  EXPECT_EQ(report.entries, 9 + 3 + 3 + 3 + 3);  // E, r, h, inertia products, axis

  // a tighter tolerance than the rounding leaves everything as it was
  Model<double> untouched = before;
  EXPECT_EQ(snap(untouched, 1e-30).snapped, 0);
  EXPECT_EQ(untouched.joint_type[0], JointType::Revolute);
}

// On the shared robots, --snap 1e-9 changes the dynamics no more than the tolerance times the
// problem's conditioning: RNEA, CRBA and ABA of the snapped and unsnapped models agree to 1e-9
// relative (measured at most 2.7e-11, ur5).
TEST(ModelBuilder, SnapChangesTheDynamicsByLessThanTheTolerance) {
  for (const test::RobotFile& robot : test::robot_files()) {
    const Model<double> exact = test::load_for_aba(robot);
    Model<double> snapped = exact;
    snap(snapped, 1e-9);
    Workspace<double> ws_exact(exact), ws_snapped(snapped);
    test::Random rng(5);
    double largest = 0;
    for (int k = 0; k < 20; ++k) {
      const test::State s = test::random_state(exact, rng);
      const int n = exact.nv;
      std::vector<double> a(n), b(n), Ma(n * n), Mb(n * n), qa(n), qb(n);
      rnea<double>(exact, ws_exact, s.q, s.qd, s.qdd, a);
      rnea<double>(snapped, ws_snapped, s.q, s.qd, s.qdd, b);
      crba<double>(exact, ws_exact, s.q, Ma);
      crba<double>(snapped, ws_snapped, s.q, Mb);
      aba<double>(exact, ws_exact, s.q, s.qd, s.tau, qa);
      aba<double>(snapped, ws_snapped, s.q, s.qd, s.tau, qb);
      largest = std::max({largest, test::relative_error(test::to_eigen(b), test::to_eigen(a)),
                          test::relative_error(test::to_eigen(Mb), test::to_eigen(Ma)),
                          test::relative_error(test::to_eigen(qb), test::to_eigen(qa))});
    }
    std::printf("measured %s: snap 1e-9 changes RNEA, CRBA, ABA by %.2g relative\n",
                robot.name.c_str(), largest);
    EXPECT_LT(largest, 1e-9) << robot.name;
  }
}

TEST(ModelBuilder, Errors) {
  const Vec3<double> g{0, 0, -9.81};
  expect_model_error(
      [&] {
        tree({{"base", "a"}, {"a", "b"}, {"base", "b"}, {"b", "c"}}).build(g);
      },
      "link 'b' has two parent joints, 'a_b' and 'base_b'");
  // a loop through every link leaves no root
  expect_model_error(
      [&] {
        tree({{"a", "b"}, {"b", "c"}, {"c", "a"}, {"a", "base"}}).build(g);
      },
      "no root link: every link has a parent (the tree has a loop)");
  // a loop beside the tree is not reached from the root
  expect_model_error(
      [&] {
        tree({{"base", "a"}, {"b", "c"}, {"c", "b"}}).build(g);
      },
      "not connected to the root link 'base'");
  expect_model_error(
      [&] {
        tree({{"base", "a"}, {"a", "b"}}).build(g);
      },
      "more than one root link: 'base', 'c'");
  expect_model_error(
      [&] {
        tree({{"base", "a"}, {"a", "ghost"}}).build(g);
      },
      "child link 'ghost' of joint 'a_ghost' is not defined");
  expect_model_error(
      [&] {
        tree({{"ghost", "a"}}).build(g);
      },
      "parent link 'ghost' of joint 'ghost_a' is not defined");
  expect_model_error(
      [&] {
        tree({{"base", "a"}}).lock("elbow");
      },
      "cannot lock joint 'elbow': no joint of that name");
  expect_model_error([&] { tree({}).add_link(link("a", 1, {}, {})); }, "link 'a' is defined twice");
  expect_model_error(
      [&] {
        tree({{"base", "a"}})
            .add_joint(joint("base_a", JointKind::Fixed, "a", "b", {}, rpy(0, 0, 0), {1, 0, 0}));
      },
      "joint 'base_a' is defined twice");
  expect_model_error(
      [&] {
        ModelBuilder b = tree({{"base", "a"}, {"a", "b"}, {"b", "c"}});
        b.add_link(link("d", 1, {}, {1, 1, 1}));
        b.add_joint(joint("zero", JointKind::Revolute, "c", "d", {}, rpy(0, 0, 0), {0, 0, 0}));
        b.build(g);
      },
      "joint 'zero' has a zero or non-finite axis");
  expect_model_error([&] { tree({{"base", "a"}}).set_armature("elbow", 0.1); },
                     "cannot give joint 'elbow' an armature: no joint of that name");
  expect_model_error(
      [&] {
        ModelBuilder b = tree({{"base", "a"}, {"a", "b"}, {"b", "c"}});
        b.set_armature("base_a", -0.1);
        b.build(g);
      },
      "joint 'base_a': the armature -0.1 kg m^2 is negative");
  expect_model_error(
      [&] {
        ModelBuilder b = tree({{"base", "a"}});
        b.add_link(link("d", 1, {}, {1, 1, 1}));
        b.add_joint(joint("weld", JointKind::Fixed, "a", "d", {}, rpy(0, 0, 0), {1, 0, 0}));
        b.set_armature("weld", 0.1);
      },
      "joint 'weld' is fixed: only a revolute, prismatic, planar or ball joint has an armature");
  // an all-zero or mirrored origin "rotation" would silently build a wrong model
  for (const Mat3<double>& R : {Mat3<double>{}, Mat3<double>{-1, 0, 0, 0, 1, 0, 0, 0, 1}})
    expect_model_error(
        [&] {
          tree({}).add_joint(joint("bent", JointKind::Revolute, "base", "a", {}, R, {0, 0, 1}));
        },
        "joint 'bent': the origin rotation is not a rotation matrix");
}

// A joint's armature goes to each of its degrees of freedom (a planar joint's three), in v's
// order; a model whose joints have none keeps an empty armature.
TEST(ModelBuilder, ArmatureByDegreeOfFreedom) {
  const Vec3<double> g{0, 0, -9.81};
  ModelBuilder b = tree({{"base", "a"}, {"a", "b"}, {"b", "c"}});
  EXPECT_TRUE(b.build(g).armature.empty());
  b.set_armature("a_b", 0.25);
  EXPECT_EQ(b.build(g).armature, (std::vector<double>{0, 0.25, 0}));
  b.add_link(link("d", 1, {}, {1, 1, 1}));
  b.add_joint(joint("slide", JointKind::Planar, "c", "d", {}, rpy(0, 0, 0), {0, 0, 1}));
  b.set_armature("slide", 0.5);
  const Model<double> model = b.build(g);
  EXPECT_EQ(model.armature, (std::vector<double>{0, 0.25, 0, 0.5, 0.5, 0.5}));
  EXPECT_EQ(model.cast<float>().armature, (std::vector<float>{0, 0.25f, 0, 0.5f, 0.5f, 0.5f}));
}

// An axis is a direction whatever its length: (1e300, 0, 0) has a square that overflows and
// (1e-200, 0, 0) one that underflows, yet each is the x axis. The directions are checked against
// long double, whose range holds these squares.
TEST(ModelBuilder, AxesOfAnyFiniteLengthAreDirections) {
  const std::pair<Vec3<double>, JointType> axes[] = {
      {{1e300, 0, 0}, JointType::RevoluteX},        {{1e200, 1e200, 0}, JointType::Revolute},
      {{1e-200, 0, 0}, JointType::RevoluteX},       {{0, -1e-310, 0}, JointType::RevoluteY},
      {{1.5e308, 1.5e308, 0}, JointType::Revolute}, {{3e-200, 4e-200, 0}, JointType::Revolute},
  };
  for (const auto& [axis, type] : axes) {
    ModelBuilder b;
    b.add_link(link("base", 0, {}, {}));
    b.add_link(link("body", 1, {0.1, 0.2, 0.3}, {0.1, 0.1, 0.1}));
    b.add_joint(joint("j", JointKind::Revolute, "base", "body", {}, rpy(0, 0, 0), axis));
    const Model<double> model = b.build({0, 0, -9.81});
    EXPECT_EQ(model.joint_type[0], type) << dense(axis).transpose();
    const long double x = axis.x, y = axis.y, z = axis.z;
    const long double length = std::sqrt(x * x + y * y + z * z);
    const Vec3<double>& k = model.joint_axis[0];
    EXPECT_NEAR(k.x, static_cast<double>(x / length), eps) << dense(axis).transpose();
    EXPECT_NEAR(k.y, static_cast<double>(y / length), eps) << dense(axis).transpose();
    EXPECT_NEAR(k.z, static_cast<double>(z / length), eps) << dense(axis).transpose();
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (const Vec3<double>& axis : {Vec3<double>{0, 0, 0}, Vec3<double>{inf, 0, 0},
                                   Vec3<double>{0, std::nan(""), 1}})
    expect_model_error(
        [&] {
          ModelBuilder b = tree({{"base", "a"}, {"a", "b"}, {"b", "c"}});
          b.add_link(link("d", 1, {}, {1, 1, 1}));
          b.add_joint(joint("bad", JointKind::Prismatic, "a", "d", {}, rpy(0, 0, 0), axis));
          b.build({0, 0, -9.81});
        },
        "joint 'bad' has a zero or non-finite axis");
}

/// A chain of n links on revolute (or fixed) joints about z, each 0.1 m after the last.
ModelBuilder long_chain(int n, JointKind kind) {
  ModelBuilder b;
  b.add_link(link("base", 0, {}, {}));
  for (int i = 1; i <= n; ++i) {
    b.add_link(link(numbered("l", i), 1, {0.05, 0, 0}, {0.01, 0.01, 0.01}));
    b.add_joint(joint(numbered("j", i), i == 1 ? JointKind::Revolute : kind,
                      i == 1 ? "base" : numbered("l", i - 1), numbered("l", i),
                      {i == 1 ? 0 : 0.1, 0, 0}, rpy(0, 0, 0), {0, 0, 1}));
  }
  return b;
}

// The tree is walked without recursion: a chain of 100,000 links (which overflowed the call
// stack at about 20,000) builds, in order, and so does one of 100,000 links on fixed joints,
// merged into one body.
TEST(ModelBuilder, LongChainsBuild) {
  const Model<double> chain = long_chain(100000, JointKind::Revolute).build({0, 0, -9.81});
  ASSERT_EQ(chain.nbodies, 100000);
  for (int i = 0; i < chain.nbodies; ++i) {
    EXPECT_EQ(chain.parent[i], i - 1);
    EXPECT_EQ(chain.body_name[i], numbered("l", i + 1));
  }
  const Model<double> fixed = long_chain(100000, JointKind::Fixed).build({0, 0, -9.81});
  ASSERT_EQ(fixed.nbodies, 1);
  EXPECT_NEAR(fixed.I[0].m, 100000, 1e-9);
  // the first moment sums m (0.1 (i - 1) + 0.05) over the links: 1e4 (1e5 - 1) / 2 + 5e3
  EXPECT_NEAR(fixed.I[0].h.x, 0.1 * 100000.0 * 99999.0 / 2 + 0.05 * 100000, 1e-6 * 5e8);
}

// One check of the model's numbers after building: each constant the algorithms use must be
// finite and at most max_model_constant, and a mass or moment of inertia zero or normal; the
// error names the link or joint and the field.
TEST(ModelBuilder, NumbersTheAlgorithmsCannotComputeWithAreRefused) {
  const Vec3<double> g{0, 0, -9.81};
  const auto one_link = [](double mass, Vec3<double> com, Sym3<double> I, Vec3<double> xyz) {
    ModelBuilder b;
    b.add_link(link("base", 0, {}, {}));
    b.add_link(link("arm", mass, com, I));
    b.add_joint(joint("shoulder", JointKind::Revolute, "base", "arm", xyz, rpy(0, 0, 0),
                      {0, 0, 1}));
    return b;
  };
  const Sym3<double> I{0.1, 0.1, 0.1};
  expect_model_error([&] { one_link(1e308, {10, 0, 0}, I, {}).build(g); },
                     "link 'arm': the mass 1e+308 kg exceeds 1e+50 in magnitude");
  expect_model_error(
      [&] { one_link(1, {1e200, 0, 0}, I, {}).build(g); },
      "link 'arm': the first moment (mass times centre of mass) (1e+200, 0, 0) kg m exceeds");
  // m c is 1e30, but m |c|^2 is 1e60
  expect_model_error([&] { one_link(1, {1e30, 0, 0}, I, {}).build(g); },
                     "link 'arm': the inertia about the link origin (xx, yy, zz, xy, xz, yz) "
                     "(0.1, 1e+60, 1e+60, 0, 0, 0) kg m^2 exceeds");
  // m c is 1e40, but |c|^2 overflows to inf
  expect_model_error([&] { one_link(1e-260, {1e300, 0, 0}, I, {}).build(g); },
                     "(0.1, inf, inf, 0, 0, 0) kg m^2 is not finite");
  expect_model_error([&] { one_link(1e-320, {0.1, 0, 0}, I, {}).build(g); },
                     "link 'arm': the mass 9.99989e-321 kg is subnormal");
  // a normal mass whose moment about the origin, m |c|^2, is subnormal
  expect_model_error([&] { one_link(1e-300, {1e-5, 0, 0}, {0, 0, 0}, {}).build(g); },
                     "link 'arm': the moment of inertia yy about the link origin 1e-310");
  expect_model_error([&] { one_link(1, {}, I, {0, 1e60, 0}).build(g); },
                     "joint 'shoulder': the origin's position in the parent body (0, 1e+60, 0) m "
                     "exceeds");
  // two massless links on fixed joints 1.5e308 m out each put the next joint at infinity
  expect_model_error(
      [&] {
        ModelBuilder b = one_link(1, {}, I, {});
        b.add_link(link("post", 0, {}, {}));
        b.add_link(link("beam", 0, {}, {}));
        b.add_link(link("tip", 1, {}, I));
        b.add_joint(joint("post", JointKind::Fixed, "arm", "post", {1.5e308, 0, 0}, rpy(0, 0, 0),
                          {1, 0, 0}));
        b.add_joint(joint("beam", JointKind::Fixed, "post", "beam", {1.5e308, 0, 0},
                          rpy(0, 0, 0), {1, 0, 0}));
        b.add_joint(joint("tip", JointKind::Revolute, "beam", "tip", {}, rpy(0, 0, 0),
                          {0, 0, 1}));
        b.build(g);
      },
      "joint 'tip': the origin's position in the parent body (inf, 0, 0) m is not finite");
  expect_model_error([&] { one_link(1, {}, I, {}).build({0, 0, 1e308}); },
                     "gravity (0, 0, 1e+308) m/s^2 exceeds 1e+50");
  expect_model_error([&] { one_link(1, {}, I, {}).build({std::nan(""), 0, 0}); },
                     "gravity (nan, 0, 0) m/s^2 is not finite");
  // at the limits: accepted
  const Model<double> big = one_link(1e50, {}, {1e50, 1e50, 1e50}, {1e50, 0, 0}).build({0, 0, 1e50});
  EXPECT_EQ(big.I[0].m, 1e50);
  const Model<double> small = one_link(2.3e-308, {}, {2.3e-308, 2.3e-308, 2.3e-308}, {}).build(g);
  EXPECT_EQ(small.I[0].m, 2.3e-308);
}

}  // namespace
}  // namespace dyngen
