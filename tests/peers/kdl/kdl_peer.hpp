// orocos-KDL as a peer of the runtime: a URDF loaded through kdl_parser (with dyngen's locked
// joints and, for a floating base, a virtual 6-DoF chain in front of the root), KDL's
// dynamics of it, and states expressed in both libraries' coordinates.
#pragma once

#include <Eigen/Core>
#include <kdl/chain.hpp>
#include <kdl/tree.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dyngen/model.hpp"
#include "test_support.hpp"

namespace dyngen::test::kdl {

/// The virtual joints that carry a floating base in KDL, in chain order: prismatic along
/// world x, y, z, then revolute about z (yaw), the new y (pitch) and the new x (roll), so the
/// base sits at p = (x, y, z) with orientation R = Rz(yaw) Ry(pitch) Rx(roll).
inline const std::vector<std::string> virtual_joints{
    "virtual_px", "virtual_py", "virtual_pz", "virtual_yaw", "virtual_pitch", "virtual_roll"};

/// kdl_parser's tree of a URDF file, with the root link under a dummy root link (kdl_parser
/// would drop the root link's inertia) and the named joints turned into fixed joints, as
/// dyngen locks them (at q = 0). floating_base: the robot hangs from a massless virtual 6-DoF
/// chain (virtual_joints) under a world root instead of from the fixed dummy.
KDL::Tree load_tree(const std::string& urdf_path, const std::vector<std::string>& locked,
                    bool floating_base);

/// The chain from the tree's root to `tip`, if it is the same robot as the whole tree: it has
/// every joint of the tree, and every segment off it that can move is massless.
std::optional<KDL::Chain> equivalent_chain(const KDL::Tree& tree, const std::string& tip);

/// KDL's dynamics of a tree or chain, in KDL's joint order.
class Dynamics {
 public:
  virtual ~Dynamics() = default;

  /// Joint names in KDL's order (q_nr for a tree, chain order for a chain).
  const std::vector<std::string>& joint_names() const { return names_; }

  /// Joint torques (inverse dynamics, gravity included).
  virtual Eigen::VectorXd inverse(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                  const Eigen::VectorXd& qdd) = 0;
  /// Joint-space mass matrix.
  virtual Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) = 0;
  /// Joint accelerations (forward dynamics).
  virtual Eigen::VectorXd forward(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                  const Eigen::VectorXd& tau) = 0;

 protected:
  std::vector<std::string> names_;
};

/// TreeIdSolver_RNE; the mass matrix column by column from the same solver (zero gravity,
/// velocity and other accelerations), forward dynamics M^-1 (tau - h) by Eigen's LLT.
std::unique_ptr<Dynamics> tree_dynamics(const KDL::Tree& tree, const Vec3<double>& gravity);

/// KDL's native chain solvers: ChainIdSolver_RNE, ChainDynParam::JntToMass, ChainFdSolver_RNE.
std::unique_ptr<Dynamics> chain_dynamics(const KDL::Chain& chain, const Vec3<double>& gravity);

/// One state in both libraries' coordinates. KDL's velocities map to dyngen's by
/// v = G qd_kdl, so a = G qdd_kdl + Gdot qd_kdl, tau_kdl = G^T tau and M_kdl = G^T M G.
struct StatePair {
  Eigen::VectorXd q, v, a, tau;  // dyngen: nq, nv, nv, nv
  Eigen::VectorXd q_kdl, qd_kdl, qdd_kdl;
  Eigen::MatrixXd G;        // nv x KDL joints
  Eigen::VectorXd Gdot_qd;  // Gdot qd_kdl
};

/// A random state: each 1-DoF joint at q in [-pi, pi] (rad or m), qd and qdd in [-2, 2]; a free
/// joint at a position in [-1, 1]^3, yaw and roll in [-pi, pi], pitch in [-1.4, 1.4] (away from
/// the virtual chain's singularity at +-pi/2), and virtual-joint rates and accelerations in
/// [-2, 2]; tau in [-5, 5]. `kdl_names` is Dynamics::joint_names(); joints are matched by name.
StatePair random_state_pair(const Model<double>& model, const std::vector<std::string>& kdl_names,
                            Random& rng);

}  // namespace dyngen::test::kdl
