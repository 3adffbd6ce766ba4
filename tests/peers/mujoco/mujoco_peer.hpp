// MuJoCo 2.2.2 as a peer of the runtime: a shared robot URDF rewritten so that MuJoCo's URDF
// importer builds the same rigid-body model as dyngen's loader, loaded with every force that
// dyngen does not model switched off, and MuJoCo's dynamics mapped into dyngen's coordinates.
// README.md lists the modelling differences this removes.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dyngen/model.hpp"

namespace dyngen::test::mujoco_peer {

/// The free joint that MuJoCo gets for a floating base, named like dyngen's.
inline constexpr const char* floating_joint = "floating_base";

/// A link's inertia in its principal axes, as written for MuJoCo.
struct PrincipalInertia {
  std::array<double, 3> moments;
  std::array<double, 4> quat;  // w first: orientation of the principal axes in the link
};

/// A URDF rewritten for MuJoCo's importer.
struct MujocoUrdf {
  std::string text;
  /// The links (by name) whose principal moments break the triangle inequality A + B >= C:
  /// MuJoCo refuses them unless balanceinertia replaces the moments by their mean.
  std::map<std::string, PrincipalInertia> unphysical;
  /// The links renamed for MuJoCo: the file's name and MuJoCo's.
  std::map<std::string, std::string> renamed;
};

/// The file at path rewritten for MuJoCo: without <visual> and <collision> (their meshes are not
/// here, and collision geometry would give links without <inertial> a mass); each inertia
/// diagonalised here, exactly to rounding, its principal axes moved into the <inertial> origin
/// (MuJoCo's own diagonalisation is accurate to only about 1e-8); the locked joints fixed; with
/// floating_base, a free joint from a new world link to the root link; and MuJoCo compiler
/// options that keep every link a body of its own with the file's inertia.
MujocoUrdf mujoco_urdf(const std::string& path, const std::vector<std::string>& locked,
                       bool floating_base);

/// An MJCF file as MuJoCo 2.2.2 compiles it, written into `dir`: each <mesh> file replaced by a
/// small tetrahedron (the files of published models are often not at hand, and a body whose
/// <inertial> is given takes nothing from its meshes), and <option integrator> dropped (MuJoCo 3's
/// "implicitfast" is unknown to 2.2, and the integrator plays no part in M, tau or qacc).
/// Returns the path of the copy. Throws std::runtime_error when the file cannot be read.
std::string mujoco_mjcf(const std::string& path, const std::string& dir);

/// Rotation and position of MuJoCo body `body` in the frame of its ancestor `ancestor`, at
/// q = 0 of the joints between them.
std::pair<Eigen::Matrix3d, Eigen::Vector3d> relative_pose(const mjModel* m, int body, int ancestor);

/// dyngen's coordinates against MuJoCo's model m, where joint[i] is the MuJoCo joint of dyngen
/// body i (see MujocoRobot below): q as qpos; the orthogonal A with v_mujoco = A v at q (joint
/// order, and a free joint's linear velocity turned into world axes); and the acceleration of
/// each free joint's world-axis linear velocity when dyngen's is zero, so that
/// a_mujoco = A a + free_joint_bias(q, v).
std::vector<double> qpos(const mjModel* m, const Model<double>& model, std::span<const int> joint,
                         std::span<const double> q);
Eigen::MatrixXd velocity_map(const mjModel* m, const Model<double>& model,
                             std::span<const int> joint, std::span<const double> q);
Eigen::VectorXd free_joint_bias(const mjModel* m, const Model<double>& model,
                                std::span<const int> joint, std::span<const double> q,
                                std::span<const double> v);

/// MuJoCo's model of a robot that dyngen loaded, and its dynamics in dyngen's coordinates.
///
/// dyngen's and MuJoCo's q, v and tau differ only in order, except on a free joint: MuJoCo's
/// linear velocity is in world coordinates, dyngen's in body coordinates, so with R the body's
/// rotation and T = blockdiag(R, 1), v_mujoco = T v (the same map for the force entries, which
/// are dual to them; T is orthogonal). dyngen's linear acceleration is the derivative of the
/// body-coordinate velocity: a_mujoco = T a + [R (w x v_lin); 0].
class MujocoRobot {
 public:
  /// Loads the URDF at path as dyngen loaded it into `model`, with `locked` joints locked and
  /// floating_base as given. Throws std::runtime_error when MuJoCo refuses the file or its
  /// joints do not match the model's.
  MujocoRobot(const std::string& path, const Model<double>& model,
              const std::vector<std::string>& locked, bool floating_base);

  const mjModel* mj() const { return m_.get(); }

  /// MuJoCo's body of dyngen body i.
  int body(int i) const { return m_->jnt_bodyid[joint_[i]]; }

  /// MuJoCo's body of the URDF link named `link` (each link is a body of its own; a fixed base's
  /// root link named "world" is MuJoCo's world body 0), or -1.
  int link_body(const std::string& link) const;

  /// MuJoCo's inertia of dyngen body i: the sum over the MuJoCo bodies welded to body(i) (its
  /// links on fixed joints), about its origin in its coordinates, as a dense 6x6 matrix.
  Eigen::Matrix<double, 6, 6> inertia(int i) const;

  /// The unphysical links: MuJoCo's balanced principal moments, which were replaced with the
  /// file's.
  const std::map<std::string, std::array<double, 3>>& balanced() const { return balanced_; }

  /// Mass matrix, row-major nv x nv, from mj_fwdPosition.
  std::vector<double> crba(std::span<const double> q);

  /// Inverse dynamics, from mj_inverse's qfrc_inverse.
  std::vector<double> rnea(std::span<const double> q, std::span<const double> v,
                           std::span<const double> a);

  /// Forward dynamics, from mj_forward with tau as qfrc_applied.
  std::vector<double> aba(std::span<const double> q, std::span<const double> v,
                          std::span<const double> tau);

  /// M^-1, row-major nv x nv, from mj_solveM on the identity after mj_fwdPosition: MuJoCo's
  /// own factorisation of its own M.
  std::vector<double> minv(std::span<const double> q);

  /// d qdd / dq and d qdd / dv of forward dynamics at q, v and tau (tau as qfrc_applied), in
  /// dyngen's coordinates (a free joint's q columns its tangent directions, q moved to
  /// M exp(d)), row-major nv x nv, from mjd_transitionFD's centred differences with step eps of
  /// one Euler step of length 1, whose qvel rows are d qacc / d(qpos, qvel) in MuJoCo's
  /// coordinates (qvel + qacc; with the identity for qvel). A free joint's velocity map T and
  /// the bias of its world-coordinate acceleration depend on its rotation: their terms are
  /// added to the differences.
  std::pair<std::vector<double>, std::vector<double>> aba_derivatives(std::span<const double> q,
                                                                      std::span<const double> v,
                                                                      std::span<const double> tau,
                                                                      double eps);

  /// Rotation (xmat: the body's axes as columns) and origin (xpos) of each of `bodies` in the
  /// world at q, from mj_kinematics.
  std::vector<std::pair<Eigen::Matrix3d, Eigen::Vector3d>> placements(std::span<const double> q,
                                                                      std::span<const int> bodies);

  /// Jacobian of each of `bodies` at its origin and q, for dyngen's v: 6 x nv, the origin's
  /// velocity then the angular velocity, in world axes. mj_jac at xpos after mj_kinematics and
  /// mj_comPos (which fills cdof), times velocity_map(q).
  std::vector<Eigen::MatrixXd> jacobians(std::span<const double> q, std::span<const int> bodies);

  /// Centre of mass of the moving bodies, as dyngen's, and its Jacobian (3 x nv) for dyngen's v
  /// at q: subtree_com of the world body (from mj_comPos) and mj_jacSubtreeCom of it, times
  /// velocity_map(q), without the bodies welded to the world (a fixed base's, with no inertia
  /// in dyngen's model).
  std::pair<Eigen::Vector3d, Eigen::MatrixXd> com(std::span<const double> q);

  /// Classical acceleration of the origin of each of `bodies`, then its angular acceleration,
  /// in world axes, at q, v and dyngen's acceleration 0: mj_objectAcceleration (world axes) after
  /// mj_rnePostConstraint with qacc = free_joint_bias(q, v) and gravity disabled.
  std::vector<Eigen::Matrix<double, 6, 1>> bias_accelerations(std::span<const double> q,
                                                              std::span<const double> v,
                                                              std::span<const int> bodies);

  /// The maps above for this robot; forces map as velocities.
  std::vector<double> qpos(std::span<const double> q) const {
    return mujoco_peer::qpos(m_.get(), model_, joint_, q);
  }
  Eigen::MatrixXd velocity_map(std::span<const double> q) const {
    return mujoco_peer::velocity_map(m_.get(), model_, joint_, q);
  }
  Eigen::VectorXd free_joint_bias(std::span<const double> q, std::span<const double> v) const {
    return mujoco_peer::free_joint_bias(m_.get(), model_, joint_, q, v);
  }

 private:
  struct ModelDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
  };
  struct DataDeleter {
    void operator()(mjData* d) const { mj_deleteData(d); }
  };

  /// Sets qpos and qvel; returns velocity_map(q).
  Eigen::MatrixXd set_state(std::span<const double> q, std::span<const double> v);

  Model<double> model_;
  std::unique_ptr<mjModel, ModelDeleter> m_;
  std::unique_ptr<mjData, DataDeleter> d_;
  std::vector<int> joint_;  // [nbodies] MuJoCo joint of each dyngen body
  std::map<std::string, std::array<double, 3>> balanced_;
  std::map<std::string, std::string> renamed_;
};

}  // namespace dyngen::test::mujoco_peer
