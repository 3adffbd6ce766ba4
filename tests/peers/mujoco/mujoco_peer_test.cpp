// The runtime against MuJoCo 2.2.2 on every shared robot, with a fixed and with a floating base:
// the imported models agree body by body, and the mass matrix (CRBA), inverse dynamics (RNEA)
// and forward dynamics (ABA) agree to a norm-wise relative error of 1e-9 at seeded random
// states, as do every link's frame placement, Jacobian and bias acceleration, and the centre of
// mass and its Jacobian; the derivatives agree with MuJoCo's finite differences of its forward
// dynamics to 1e-5. The largest dynamics errors are printed as a table when the program ends,
// the frames' and derivatives' on lines starting with "measured".
#include "mujoco_peer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "robot.hpp"
#include "test_support.hpp"

namespace dyngen::test {
namespace {

using mujoco_peer::MujocoRobot;

constexpr double tolerance = 1e-9;
constexpr int samples = 20;

struct Case {
  RobotFile robot;
  bool floating_base;
};

std::string case_name(const Case& c) {
  return c.robot.name + (c.floating_base ? "_floating" : "_fixed");
}

std::vector<Case> cases() {
  std::vector<Case> all;
  for (const bool floating_base : {false, true})
    for (const RobotFile& robot : robot_files()) all.push_back({robot, floating_base});
  return all;
}

void PrintTo(const Case& c, std::ostream* os) { *os << case_name(c); }

/// The robot with its ABA options: mimic joints as independent joints (MuJoCo's importer
/// ignores <mimic>), and romeo's massless hands locked (MuJoCo refuses moving bodies without
/// mass, so every algorithm is compared on that model).
gen::Robot load(const Case& c) {
  gen::LoadOptions options = c.robot.aba_options;
  options.floating_base = c.floating_base;
  return gen::load_robot(c.robot.path, options);
}

/// A row-major rows x cols array (the runtime's Jacobian layout) as an Eigen matrix.
Eigen::MatrixXd row_major(const std::vector<double>& x, int rows, int cols) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      x.data(), rows, cols);
}

// ---- the table of largest errors, printed when the program ends ---------------------------

struct Row {
  std::string name;
  int nv;
  double crba, rnea, aba;
};

std::vector<Row>& table() {
  static std::vector<Row> rows;
  return rows;
}

class PrintTable : public ::testing::Environment {
 public:
  void TearDown() override {
    if (table().empty()) return;
    std::printf("\nLargest relative error vs MuJoCo %s over %d states (tolerance %.0e):\n",
                mj_versionString(), samples, tolerance);
    std::printf("%-26s %4s %10s %10s %10s\n", "robot", "nv", "CRBA", "RNEA", "ABA");
    for (const Row& r : table())
      std::printf("%-26s %4d %10.2e %10.2e %10.2e\n", r.name.c_str(), r.nv, r.crba, r.rnea, r.aba);
  }
};

[[maybe_unused]] const auto* const print_table =
    ::testing::AddGlobalTestEnvironment(new PrintTable);

// ---- tests ---------------------------------------------------------------------------------

class MujocoPeer : public ::testing::TestWithParam<Case> {};

// MuJoCo's importer builds dyngen's model: the same joints, tree, joint frames and axes, and
// the same inertias (each dyngen body against its MuJoCo body and the bodies welded to it).
// The only change balanceinertia makes is that of the links that break the triangle
// inequality, to the mean of their moments, and MujocoRobot undoes it.
TEST_P(MujocoPeer, ImportMatchesModel) {
  const gen::Robot robot = load(GetParam());
  const Model<double>& model = robot.model;
  const MujocoRobot peer(robot.path, model, robot.locked, GetParam().floating_base);
  const mjModel* m = peer.mj();

  for (int k = 0; k < 3; ++k) EXPECT_EQ(m->opt.gravity[k], dense(model.gravity)(k));
  for (int i = 0; i < model.nbodies; ++i) {
    SCOPED_TRACE("joint " + model.joint_name[i]);
    const int b = peer.body(i);
    const int parent = model.parent[i] < 0 ? 0 : peer.body(model.parent[i]);
    ASSERT_EQ(m->body_weldid[m->body_parentid[b]], parent);
    const auto [R, r] = mujoco_peer::relative_pose(m, b, parent);
    EXPECT_LT((R - dense(model.X_tree[i].E).transpose()).norm(), 1e-12);
    EXPECT_LT((r - dense(model.X_tree[i].r)).norm(), 1e-12);
    if (model.joint_type[i] != JointType::Free) {
      const int j = m->body_jntadr[b];
      const Eigen::Vector3d axis = Eigen::Map<const Eigen::Vector3d>(m->jnt_axis + 3 * j);
      EXPECT_LT((axis - dense(model.joint_axis[i])).norm(), 1e-12);
      EXPECT_EQ(m->qpos0[m->jnt_qposadr[j]], 0.0);
    }
    const Matrix6<double> I = dense(model.I[i]);
    EXPECT_LT((peer.inertia(i) - I).norm(), 1e-12 * I.norm());
  }

  const mujoco_peer::MujocoUrdf urdf =
      mujoco_peer::mujoco_urdf(robot.path, robot.locked, GetParam().floating_base);
  ASSERT_EQ(peer.balanced().size(), urdf.unphysical.size());
  for (const auto& [link, principal] : urdf.unphysical) {
    const auto& moments = principal.moments;
    ASSERT_TRUE(peer.balanced().count(link)) << link;
    const double mean = (moments[0] + moments[1] + moments[2]) / 3;
    for (const double balanced : peer.balanced().at(link))
      EXPECT_NEAR(balanced, mean, 1e-15 * mean);
    std::printf(
        "%s: link %s: principal moments %.6g %.6g %.6g break A + B >= C; balanceinertia "
        "made them %.6g\n",
        case_name(GetParam()).c_str(), link.c_str(), moments[0], moments[1], moments[2], mean);
  }
}

TEST_P(MujocoPeer, DynamicsMatch) {
  const gen::Robot robot = load(GetParam());
  const Model<double>& model = robot.model;
  MujocoRobot peer(robot.path, model, robot.locked, GetParam().floating_base);
  Workspace<double> ws(model);
  const int nv = model.nv;
  std::vector<double> M(nv * nv), tau(nv), qdd(nv);

  Row row{case_name(GetParam()), nv, 0, 0, 0};
  Random rng(20261121);
  for (int sample = 0; sample < samples; ++sample) {
    const State s = random_state(model, rng);
    crba<double>(model, ws, s.q, M);
    rnea<double>(model, ws, s.q, s.qd, s.qdd, tau);
    aba<double>(model, ws, s.q, s.qd, s.tau, qdd);
    row.crba = std::max(row.crba, relative_error(to_eigen(M), to_eigen(peer.crba(s.q))));
    row.rnea =
        std::max(row.rnea, relative_error(to_eigen(tau), to_eigen(peer.rnea(s.q, s.qd, s.qdd))));
    row.aba =
        std::max(row.aba, relative_error(to_eigen(qdd), to_eigen(peer.aba(s.q, s.qd, s.tau))));
  }
  EXPECT_LE(row.crba, tolerance);
  EXPECT_LE(row.rnea, tolerance);
  EXPECT_LE(row.aba, tolerance);
  table().push_back(row);
}

// Every URDF link is a dyngen frame and a MuJoCo body of its own (fusestatic="false"), so the
// frame functions compare with MuJoCo's bodies of the same links: placements with mj_kinematics,
// World Jacobians with mj_jac at the bodies' origins, bias accelerations with
// mj_objectAcceleration at dyngen's qdd = 0, and the centre of mass and its Jacobian with the
// world body's subtree_com and mj_jacSubtreeCom. Each must agree to a norm-wise relative error
// of 1e-9 over all frames at once; the largest are printed on a line starting with "measured".
TEST_P(MujocoPeer, FramesMatch) {
  gen::LoadOptions options = GetParam().robot.aba_options;
  options.floating_base = GetParam().floating_base;
  options.all_frames = true;
  const gen::Robot robot = gen::load_robot(GetParam().robot.path, options);
  const Model<double>& model = robot.model;
  MujocoRobot peer(robot.path, model, robot.locked, GetParam().floating_base);
  const int nf = static_cast<int>(model.frames.size()), nv = model.nv;

  // every frame's link is a MuJoCo body, and every MuJoCo body but the world is a frame's
  std::vector<int> bodies;
  for (const Frame<double>& f : model.frames) {
    bodies.push_back(peer.link_body(f.name));
    ASSERT_GE(bodies.back(), 0) << "MuJoCo has no body for link " << f.name;
  }
  std::vector<int> distinct = bodies;
  distinct.push_back(0);
  std::ranges::sort(distinct);
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  ASSERT_EQ(static_cast<int>(distinct.size()), peer.mj()->nbody);

  Workspace<double> ws(model);
  std::vector<double> R(9 * nf), p(3 * nf), J(6 * static_cast<std::size_t>(nf) * nv),
      Jdot_v(6 * nf), c(3), Jc(3 * nv);
  Eigen::VectorXd pose(12 * nf), pose_mj(12 * nf), bias_mj(6 * nf);
  Eigen::MatrixXd J_mj(6 * nf, nv);
  double placements = 0, jacobians = 0, bias = 0, centre = 0, centre_jacobian = 0;
  Random rng(20261121);
  for (int sample = 0; sample < samples; ++sample) {
    const State s = random_state(model, rng);
    frame_placements<double>(model, ws, s.q, R, p);
    frame_jacobians<double>(model, ws, s.q, JacobianAxes::World, J);
    frame_bias_accelerations<double>(model, ws, s.q, s.qd, JacobianAxes::World, Jdot_v);
    com<double>(model, ws, s.q, c, Jc);

    const auto placements_mj = peer.placements(s.q, bodies);
    const auto jacobians_mj = peer.jacobians(s.q, bodies);
    const auto bias_accelerations_mj = peer.bias_accelerations(s.q, s.qd, bodies);
    const auto [c_mj, Jc_mj] = peer.com(s.q);
    for (int f = 0; f < nf; ++f) {
      const auto& [R_mj, p_mj] = placements_mj[f];
      pose.segment(12 * f, 9) = Eigen::Map<const Eigen::VectorXd>(&R[9 * f], 9);
      pose.segment(12 * f + 9, 3) = Eigen::Map<const Eigen::VectorXd>(&p[3 * f], 3);
      for (int row = 0; row < 3; ++row) pose_mj.segment(12 * f + 3 * row, 3) = R_mj.row(row);
      pose_mj.segment(12 * f + 9, 3) = p_mj;
      J_mj.middleRows(6 * f, 6) = jacobians_mj[f];
      bias_mj.segment(6 * f, 6) = bias_accelerations_mj[f];
    }
    placements = std::max(placements, relative_error(pose, pose_mj));
    jacobians = std::max(jacobians, relative_error(row_major(J, 6 * nf, nv), J_mj));
    bias = std::max(bias, relative_error(to_eigen(Jdot_v), bias_mj));
    centre = std::max(centre, relative_error(to_eigen(c), c_mj));
    centre_jacobian = std::max(centre_jacobian, relative_error(row_major(Jc, 3, nv), Jc_mj));
  }
  EXPECT_LE(placements, tolerance);
  EXPECT_LE(jacobians, tolerance);
  EXPECT_LE(bias, tolerance);
  EXPECT_LE(centre, tolerance);
  EXPECT_LE(centre_jacobian, tolerance);
  std::printf(
      "measured %s (%d frames): frame_placements %.2e, frame_jacobians %.2e, "
      "frame_bias_accelerations %.2e, com c %.2e, com Jc %.2e\n",
      case_name(GetParam()).c_str(), nf, placements, jacobians, bias, centre, centre_jacobian);
}

// The derivatives against MuJoCo's finite differences of its own forward dynamics
// (mjd_transitionFD, centred, step fd_step), a free joint's carried into dyngen's tangent
// (MujocoRobot::aba_derivatives): aba_derivatives' d qdd / dq and d qdd / dv to
// fd_tolerance; its M^-1 against MuJoCo's factorisation (mj_solveM) to tolerance; and
// rnea_derivatives at qdd = aba(q, v, tau) against -M d qdd / d(q, v) from MuJoCo's M and
// differences, since tau = ID(q, v, FD(q, v, tau)) for every q and v. The largest are printed
// on a line starting with "measured".
TEST_P(MujocoPeer, DerivativesMatchMujocosFiniteDifferences) {
  constexpr double fd_step = 1e-4, fd_tolerance = 1e-5;
  const gen::Robot robot = load(GetParam());
  const Model<double>& model = robot.model;
  MujocoRobot peer(robot.path, model, robot.locked, GetParam().floating_base);
  Workspace<double> ws(model);
  const int nv = model.nv;
  std::vector<double> dqdd_dq(nv * nv), dqdd_dv(nv * nv), Minv(nv * nv), dtau_dq(nv * nv),
      dtau_dv(nv * nv), qdd(nv);
  Eigen::MatrixXd dqdd(nv, 2 * nv), dqdd_mj(nv, 2 * nv), dtau(nv, 2 * nv);
  double forward = 0, inverse = 0, inverse_dynamics = 0;
  Random rng(20261127);
  for (int sample = 0; sample < samples; ++sample) {
    const State s = random_state(model, rng);
    aba_derivatives<double>(model, ws, s.q, s.qd, s.tau, dqdd_dq, dqdd_dv, Minv);
    aba<double>(model, ws, s.q, s.qd, s.tau, qdd);
    rnea_derivatives<double>(model, ws, s.q, s.qd, qdd, dtau_dq, dtau_dv);
    const auto [dq_mj, dv_mj] = peer.aba_derivatives(s.q, s.qd, s.tau, fd_step);
    dqdd << row_major(dqdd_dq, nv, nv), row_major(dqdd_dv, nv, nv);
    dqdd_mj << row_major(dq_mj, nv, nv), row_major(dv_mj, nv, nv);
    dtau << row_major(dtau_dq, nv, nv), row_major(dtau_dv, nv, nv);
    forward = std::max(forward, relative_error(dqdd, dqdd_mj));
    inverse = std::max(inverse,
                       relative_error(row_major(Minv, nv, nv), row_major(peer.minv(s.q), nv, nv)));
    inverse_dynamics = std::max(
        inverse_dynamics,
        relative_error(dtau, (-row_major(peer.crba(s.q), nv, nv) * dqdd_mj).eval()));
  }
  EXPECT_LE(forward, fd_tolerance);
  EXPECT_LE(inverse, tolerance);
  EXPECT_LE(inverse_dynamics, fd_tolerance);
  std::printf(
      "measured %s (nv %d): aba_derivatives d qdd against MuJoCo's differences %.2e, M^-1 "
      "against mj_solveM %.2e; rnea_derivatives against -M d qdd %.2e\n",
      case_name(GetParam()).c_str(), nv, forward, inverse, inverse_dynamics);
}

INSTANTIATE_TEST_SUITE_P(Robots, MujocoPeer, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return case_name(info.param);
                         });

// Rotor inertias (--armature) are MuJoCo's dof_armature: M, tau, qdd and M^-1 agree to 1e-9 and
// the derivatives of forward dynamics with MuJoCo's differences to 1e-5, on a fixed arm with a
// different armature on one joint and on a floating quadruped.
TEST(MujocoPeerArmature, RotorInertiasAreMujocosArmature) {
  constexpr double fd_step = 1e-4, fd_tolerance = 1e-5;
  for (const auto& [file, floating_base] : {std::pair{"ur5", false}, std::pair{"solo12", true}}) {
    gen::LoadOptions options;
    options.floating_base = floating_base;
    options.armature = {{"all", 0.05}};
    if (!floating_base) options.armature.push_back({"elbow_joint", 0.3});
    const gen::Robot robot =
        gen::load_robot(std::string(DYNGEN_TEST_MODELS) + "/" + file + ".urdf", options);
    const Model<double>& model = robot.model;
    ASSERT_EQ(model.armature.size(), static_cast<std::size_t>(model.nv)) << file;
    MujocoRobot peer(robot.path, model, robot.locked, floating_base);
    Workspace<double> ws(model);
    const int nv = model.nv;
    std::vector<double> M(nv * nv), tau(nv), qdd(nv), Minv(nv * nv), dqdd_dq(nv * nv),
        dqdd_dv(nv * nv), Minv_fd(nv * nv);
    double crba_error = 0, rnea_error = 0, aba_error = 0, minv_error = 0, fd_error = 0;
    Random rng(20261128);
    for (int sample = 0; sample < 5; ++sample) {
      const State s = random_state(model, rng);
      crba<double>(model, ws, s.q, M);
      rnea<double>(model, ws, s.q, s.qd, s.qdd, tau);
      aba<double>(model, ws, s.q, s.qd, s.tau, qdd);
      minv<double>(model, ws, s.q, Minv);
      aba_derivatives<double>(model, ws, s.q, s.qd, s.tau, dqdd_dq, dqdd_dv, Minv_fd);
      crba_error = std::max(crba_error, relative_error(to_eigen(M), to_eigen(peer.crba(s.q))));
      rnea_error = std::max(rnea_error, relative_error(to_eigen(tau),
                                                       to_eigen(peer.rnea(s.q, s.qd, s.qdd))));
      aba_error = std::max(aba_error, relative_error(to_eigen(qdd),
                                                     to_eigen(peer.aba(s.q, s.qd, s.tau))));
      minv_error = std::max(minv_error, relative_error(to_eigen(Minv), to_eigen(peer.minv(s.q))));
      const auto [dq_mj, dv_mj] = peer.aba_derivatives(s.q, s.qd, s.tau, fd_step);
      fd_error = std::max({fd_error, relative_error(to_eigen(dqdd_dq), to_eigen(dq_mj)),
                           relative_error(to_eigen(dqdd_dv), to_eigen(dv_mj))});
    }
    EXPECT_LE(crba_error, tolerance) << file;
    EXPECT_LE(rnea_error, tolerance) << file;
    EXPECT_LE(aba_error, tolerance) << file;
    EXPECT_LE(minv_error, tolerance) << file;
    EXPECT_LE(fd_error, fd_tolerance) << file;
    std::printf("measured %s with armature: crba %.2e, rnea %.2e, aba %.2e, minv %.2e against "
                "MuJoCo; aba_derivatives against its differences %.2e\n",
                file, crba_error, rnea_error, aba_error, minv_error, fd_error);
  }
}

// romeo's hands and fingers have no mass. MuJoCo refuses moving bodies without mass, so the
// comparison above locks them; that loses nothing: on the full model their rows of M and tau
// are zero and the other entries are those of the locked model, whatever the hands do.
TEST(MujocoPeerRomeo, MasslessHandsRefusedByMujocoAndLockingThemLosesNothing) {
  const RobotFile romeo = [] {
    for (const RobotFile& r : robot_files())
      if (r.name == "romeo") return r;
    throw std::runtime_error("romeo.urdf not found");
  }();
  const gen::Robot full = gen::load_robot(romeo.path, romeo.options);
  try {
    MujocoRobot peer(full.path, full.model, {}, false);
    ADD_FAILURE() << "MuJoCo now loads romeo's massless hands: compare the full model";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mass and inertia of moving bodies"), std::string::npos)
        << e.what();
  }

  const gen::Robot locked = load({romeo, false});
  ASSERT_FALSE(locked.locked.empty());
  const Model<double>& f = full.model;
  const Model<double>& l = locked.model;
  std::vector<int> kept(f.nv, -1);  // index in the locked model of each entry of the full one
  for (int i = 0; i < f.nbodies; ++i) {
    const auto it = std::ranges::find(l.joint_name, f.joint_name[i]);
    if (it != l.joint_name.end()) kept[f.v_index[i]] = l.v_index[it - l.joint_name.begin()];
  }
  Workspace<double> wf(f), wl(l);
  std::vector<double> Mf(f.nv * f.nv), Ml(l.nv * l.nv), tf(f.nv), tl(l.nv);
  Random rng(20261121);
  double largest_difference = 0;
  for (int sample = 0; sample < samples; ++sample) {
    const State s = random_state(f, rng);
    State sl{std::vector<double>(l.nq), std::vector<double>(l.nv), std::vector<double>(l.nv), {}};
    for (int k = 0; k < f.nv; ++k)  // fixed base: q and v indices coincide
      if (kept[k] >= 0)
        sl.q[kept[k]] = s.q[k], sl.qd[kept[k]] = s.qd[k], sl.qdd[kept[k]] = s.qdd[k];
    crba<double>(f, wf, s.q, Mf);
    crba<double>(l, wl, sl.q, Ml);
    rnea<double>(f, wf, s.q, s.qd, s.qdd, tf);
    rnea<double>(l, wl, sl.q, sl.qd, sl.qdd, tl);
    for (int a = 0; a < f.nv; ++a) {
      const double t = kept[a] < 0 ? 0.0 : tl[kept[a]];
      largest_difference = std::max(largest_difference, std::abs(tf[a] - t));
      for (int b = 0; b < f.nv; ++b) {
        const double M = kept[a] < 0 || kept[b] < 0 ? 0.0 : Ml[kept[a] * l.nv + kept[b]];
        largest_difference = std::max(largest_difference, std::abs(Mf[a * f.nv + b] - M));
      }
    }
  }
  EXPECT_EQ(largest_difference, 0.0);
}

}  // namespace
}  // namespace dyngen::test
