// orocos-KDL against the runtime on every shared robot: inverse dynamics, the mass matrix and
// forward dynamics at seeded random states, with a fixed and with a floating base; and every
// URDF link's placement and Jacobian (dyngen's frames). README.md
// lists the modelling differences between the two libraries and how the test removes them.
#include "kdl_peer.hpp"

#include <gtest/gtest.h>

#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treejnttojacsolver.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <ostream>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "backend.hpp"
#include "dyngen/dyngen.hpp"
#include "robot.hpp"
#include "test_support.hpp"

namespace dyngen::test {

void PrintTo(const RobotFile& robot, std::ostream* out) { *out << robot.name; }

namespace kdl {
namespace {

constexpr int states_per_robot = 20;
constexpr std::uint64_t seed = 20261121;
constexpr double tolerance = 1e-9;

enum Algorithm { Rnea, Crba, Aba };
constexpr const char* algorithm_names[] = {"RNEA", "CRBA", "ABA"};
enum Solver { Tree, Chain };
constexpr const char* solver_names[] = {"tree", "chain"};

/// The largest relative error of one algorithm over the seeded random states (NaN if any is).
double largest_error(Algorithm algorithm, const Model<double>& model, Dynamics& kdl) {
  Workspace<double> ws(model);
  Random rng(seed);
  double largest = 0;
  for (int n = 0; n < states_per_robot; ++n) {
    const StatePair s = random_state_pair(model, kdl.joint_names(), rng);
    double error = 0;
    switch (algorithm) {
      case Rnea: {
        Eigen::VectorXd tau(model.nv);
        rnea<double>(model, ws, view(s.q), view(s.v), view(s.a), view(tau));
        error = relative_error(s.G.transpose() * tau, kdl.inverse(s.q_kdl, s.qd_kdl, s.qdd_kdl));
        break;
      }
      case Crba: {
        Eigen::VectorXd M(model.nv * model.nv);  // row-major, symmetric
        crba<double>(model, ws, view(s.q), view(M));
        const Eigen::MatrixXd M_dyngen = M.reshaped<Eigen::RowMajor>(model.nv, model.nv);
        error = relative_error(s.G.transpose() * M_dyngen * s.G, kdl.mass_matrix(s.q_kdl));
        break;
      }
      case Aba: {
        Eigen::VectorXd a(model.nv);
        aba<double>(model, ws, view(s.q), view(s.v), view(s.tau), view(a));
        const Eigen::VectorXd qdd_kdl = kdl.forward(s.q_kdl, s.qd_kdl, s.G.transpose() * s.tau);
        error = relative_error(a, s.G * qdd_kdl + s.Gdot_qd);
        break;
      }
    }
    largest = std::isnan(largest) || std::isnan(error) ? NAN : std::max(largest, error);
  }
  return largest;
}

/// One robot in both libraries, under the same load options (RobotFile's options accept mimic
/// joints as independent joints, which is what kdl_parser makes of them).
struct Peer {
  gen::Robot robot;
  std::unique_ptr<Dynamics> tree, chain;  // chain: null where KDL's chain is not the robot
};

Peer make_peer(const RobotFile& file, gen::LoadOptions options, bool floating_base) {
  options.floating_base = floating_base;
  Peer peer{gen::load_robot(file.path, options), nullptr, nullptr};
  const Model<double>& model = peer.robot.model;
  const KDL::Tree tree = load_tree(file.path, peer.robot.locked, floating_base);
  peer.tree = tree_dynamics(tree, model.gravity);
  if (const auto chain = equivalent_chain(tree, model.body_name.back()))
    peer.chain = chain_dynamics(*chain, model.gravity);
  return peer;
}

struct Row {
  std::string robot;
  bool floating_base;
  int nv;
  std::optional<double> error[2][3];  // [Solver][Algorithm]
};

std::vector<Row>& table() {
  static std::vector<Row> rows;
  return rows;
}

void print_table() {
  std::printf(
      "\nKDL peer: largest ||x_dyngen - x_kdl|| / ||x_kdl|| over %d random states (limit %.0e)\n"
      "tree:  TreeIdSolver_RNE; CRBA column by column from it, ABA = LLT solve of M (tau - h)\n"
      "chain: ChainIdSolver_RNE, ChainDynParam::JntToMass, ChainFdSolver_RNE (serial robots)\n"
      "ABA on romeo with its massless hands locked in both libraries\n\n",
      states_per_robot, tolerance);
  std::printf("%-16s %-8s %3s", "robot", "base", "nv");
  for (const char* solver : solver_names)
    for (const char* algorithm : algorithm_names)
      std::printf("  %10s", (std::string(solver) + " " + algorithm).c_str());
  std::printf("\n");
  for (const Row& row : table()) {
    std::printf("%-16s %-8s %3d", row.robot.c_str(), row.floating_base ? "floating" : "fixed",
                row.nv);
    for (const auto& by_solver : row.error)
      for (const std::optional<double>& error : by_solver)
        if (error)
          std::printf("  %10.2e", *error);
        else
          std::printf("  %10s", "-");
    std::printf("\n");
  }
}

class KdlPeer : public testing::TestWithParam<RobotFile> {
 public:
  static void TearDownTestSuite() { print_table(); }

 protected:
  /// RNEA and CRBA on the whole robot, ABA under the robot's ABA options (locks in both).
  void compare(bool floating_base) {
    const RobotFile& file = GetParam();
    Peer whole = make_peer(file, file.options, floating_base);
    Peer for_aba = make_peer(file, file.aba_options, floating_base);
    Row row{file.name, floating_base, whole.robot.model.nv, {}};
    for (const Solver solver : {Tree, Chain})
      for (const Algorithm algorithm : {Rnea, Crba, Aba}) {
        Peer& peer = algorithm == Aba ? for_aba : whole;
        Dynamics* kdl = (solver == Tree ? peer.tree : peer.chain).get();
        if (!kdl) continue;
        const double error = largest_error(algorithm, peer.robot.model, *kdl);
        row.error[solver][algorithm] = error;
        EXPECT_LE(error, tolerance) << solver_names[solver] << " " << algorithm_names[algorithm];
      }
    table().push_back(row);
  }
};

// kdl_parser keeps every movable joint (it would turn a floating or planar joint into a fixed
// one) and leaves KDL's joint inertia, damping and stiffness at zero: dyngen has none of them,
// and KDL's RNEA adds inertia * qdd to each joint's torque.
TEST_P(KdlPeer, JointsAsInUrdf) {
  const RobotFile& file = GetParam();
  const Model<double> model = gen::load_robot(file.path, file.options).model;
  const KDL::Tree tree = load_tree(file.path, {}, false);
  std::set<std::string> kdl_joints;
  for (const auto& [name, element] : tree.getSegments()) {
    const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
    if (joint.getType() == KDL::Joint::Fixed) continue;
    kdl_joints.insert(joint.getName());
    EXPECT_EQ(joint.getInertia(), 0) << joint.getName();
    EXPECT_EQ(joint.getDamping(), 0) << joint.getName();
    EXPECT_EQ(joint.getStiffness(), 0) << joint.getName();
  }
  EXPECT_EQ(kdl_joints, std::set<std::string>(model.joint_name.begin(), model.joint_name.end()));
}

// The header's maps to Pinocchio's coordinates (pinocchio_maps) against kdl_parser's numbering:
// both it and Pinocchio's URDF parser number the joints depth first from the root link over
// urdfdom's children, so KDL's q_nr order is Pinocchio's. Fixed base: the maps are then a
// reordering of the joints; with a floating base the free joint comes first, its quaternion w
// last (Pinocchio's documented JointModelFreeFlyer), and the rest follows, shifted.
TEST_P(KdlPeer, PinocchioMapsFollowTheParsersOrder) {
  const RobotFile& file = GetParam();
  const gen::Robot robot = gen::load_robot(file.path, file.options);
  const gen::PinocchioMaps maps = gen::pinocchio_maps(robot, robot.model);
  if (!maps.missing.empty()) {  // pr2's continuous joints are cos and sin in Pinocchio
    EXPECT_NE(maps.missing.find("continuous"), std::string::npos) << maps.missing;
    return;
  }
  const Model<double>& model = robot.model;
  std::vector<std::string> velocity(model.nv);
  for (int i = 0; i < model.nbodies; ++i) velocity[model.v_index[i]] = model.joint_name[i];
  const auto dynamics = tree_dynamics(load_tree(file.path, {}, false), model.gravity);
  const std::vector<std::string>& kdl = dynamics->joint_names();
  ASSERT_EQ(maps.to_v.size(), kdl.size());
  for (std::size_t k = 0; k < kdl.size(); ++k) {
    EXPECT_EQ(velocity[maps.to_v[k]], kdl[k]) << "Pinocchio's v[" << k << "]";
    EXPECT_EQ(maps.from_v[maps.to_v[k]], static_cast<int>(k));
  }
  EXPECT_EQ(maps.to_q, maps.to_v);  // one coordinate a joint, as KDL's

  gen::LoadOptions floating = file.options;
  floating.floating_base = true;
  const gen::Robot free = gen::load_robot(file.path, floating);
  const gen::PinocchioMaps free_maps = gen::pinocchio_maps(free, free.model);
  ASSERT_TRUE(free_maps.missing.empty()) << free_maps.missing;
  const std::vector<int> head{0, 1, 2, 4, 5, 6, 3};  // x, y, z, then qx, qy, qz after w
  ASSERT_EQ(free_maps.to_q.size(), maps.to_q.size() + 7);
  EXPECT_TRUE(std::equal(head.begin(), head.end(), free_maps.to_q.begin()));
  for (std::size_t k = 0; k < maps.to_q.size(); ++k) {
    EXPECT_EQ(free_maps.to_q[k + 7], maps.to_q[k] + 7);
    EXPECT_EQ(free_maps.to_v[k + 6], maps.to_v[k] + 6);
  }
}

TEST_P(KdlPeer, FixedBase) { compare(false); }

TEST_P(KdlPeer, FloatingBase) { compare(true); }

// Every URDF link is a dyngen frame and a KDL segment: its pose (TreeFkSolverPos_recursive) and
// Jacobian (TreeJntToJacSolver: at the segment's origin, base axes, linear rows first) against
// frame_placements and frame_jacobians, whose columns map to KDL's joints by v = G qd_kdl.
TEST_P(KdlPeer, FramePlacementsAndJacobians) {
  const RobotFile& file = GetParam();
  for (const bool floating_base : {false, true}) {
    SCOPED_TRACE(floating_base ? "floating base" : "fixed base");
    gen::LoadOptions options = file.options;
    options.floating_base = floating_base;
    options.all_frames = true;
    const gen::Robot robot = gen::load_robot(file.path, options);
    const Model<double>& model = robot.model;
    const KDL::Tree tree = load_tree(file.path, robot.locked, floating_base);
    const std::unique_ptr<Dynamics> names = tree_dynamics(tree, model.gravity);
    KDL::TreeFkSolverPos_recursive fk(tree);
    KDL::TreeJntToJacSolver jacobians(tree);
    Workspace<double> ws(model);
    const int nf = static_cast<int>(model.frames.size()), nv = model.nv;
    std::vector<double> R(9 * nf), p(3 * nf), J(6 * static_cast<std::size_t>(nf) * nv);
    Random rng(seed);
    double placements = 0, jacobian_entries = 0;
    for (int n = 0; n < 5; ++n) {
      const StatePair s = random_state_pair(model, names->joint_names(), rng);
      frame_placements<double>(model, ws, view(s.q), R, p);
      frame_jacobians<double>(model, ws, view(s.q), JacobianAxes::World, J);
      KDL::JntArray q_kdl(static_cast<unsigned>(s.q_kdl.size()));
      q_kdl.data = s.q_kdl;
      for (int f = 0; f < nf; ++f) {
        const std::string& name = model.frames[f].name;
        KDL::Frame pose;
        ASSERT_GE(fk.JntToCart(q_kdl, pose, name), 0) << name;
        KDL::Jacobian jac(q_kdl.rows());
        ASSERT_GE(jacobians.JntToJac(q_kdl, jac, name), 0) << name;
        for (int k = 0; k < 9; ++k)
          placements = std::max(placements, std::abs(R[9 * f + k] - pose.M.data[k]));
        for (int k = 0; k < 3; ++k)
          placements = std::max(placements, std::abs(p[3 * f + k] - pose.p(k)));
        const Eigen::MatrixXd J_dyngen =
            Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                &J[6 * static_cast<std::size_t>(f) * nv], 6, nv);
        jacobian_entries =
            std::max(jacobian_entries, (J_dyngen * s.G - jac.data).cwiseAbs().maxCoeff());
      }
    }
    // the poses are O(1) m and rad: an absolute bound
    EXPECT_LT(placements, tolerance) << nf << " frames";
    EXPECT_LT(jacobian_entries, tolerance) << nf << " frames";
    std::printf("measured KDL frames %-16s %-8s %3d frames: placements %.1e, Jacobians %.1e\n",
                file.name.c_str(), floating_base ? "floating" : "fixed", nf, placements,
                jacobian_entries);
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, KdlPeer, testing::ValuesIn(robot_files()),
                         [](const testing::TestParamInfo<RobotFile>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace kdl
}  // namespace dyngen::test
