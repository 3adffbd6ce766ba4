// RNEA, CRBA and ABA by the runtime, MuJoCo and orocos-KDL, on the states the generated code is
// timed on, for the benchmarks that set them beside the generated code (dyngen_bench,
// dyngen_batch_bench). Each implementation has run(a, k), the timed call on state k, and
// error(a, k): run(a, k) and its relative difference from the runtime.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <memory>
#include <optional>
#include <vector>

#include "algorithm.hpp"
#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/random.hpp"
#include "kdl_peer.hpp"
#include "mujoco_peer.hpp"
#include "robot.hpp"

namespace dyngen::bench {

using numerics::Random;
using numerics::State;

inline int output_size(Algorithm a, int nv) { return a == Computes::MassMatrix ? nv * nv : nv; }

inline Eigen::Map<const Eigen::VectorXd> vec(const std::vector<double>& x) {
  return {x.data(), static_cast<Eigen::Index>(x.size())};
}

/// The runtime's result at s (M row-major): what every timed call is checked against.
inline std::vector<double> reference(const Model<double>& model, Algorithm a, const State& s) {
  Workspace<double> ws(model);
  std::vector<double> out(output_size(a, model.nv));
  switch (a) {
    case Computes::Other: break;
    case Computes::InverseDynamics: rnea<double>(model, ws, s.q, s.qd, s.qdd, out); break;
    case Computes::MassMatrix: crba<double>(model, ws, s.q, out); break;
    case Computes::ForwardDynamics: aba<double>(model, ws, s.q, s.qd, s.tau, out); break;
  }
  return out;
}

/// The runtime's functions on Model<double>, with a Workspace reused from call to call.
class RuntimeCode {
 public:
  RuntimeCode(const Model<double>& model, const std::vector<State>& states)
      : model_(model), ws_(model), states_(states), out_(model.nv * model.nv) {}

  bool has(Algorithm) const { return true; }

  void run(Algorithm a, int k) {
    const State& s = states_[k];
    const std::span<double> out(out_.data(), output_size(a, model_.nv));
    switch (a) {
      case Computes::Other: break;
      case Computes::InverseDynamics: rnea<double>(model_, ws_, s.q, s.qd, s.qdd, out); break;
      case Computes::MassMatrix: crba<double>(model_, ws_, s.q, out); break;
      case Computes::ForwardDynamics: aba<double>(model_, ws_, s.q, s.qd, s.tau, out); break;
    }
  }

  double error(Algorithm a, int k) {
    run(a, k);
    const std::vector<double> expected = reference(model_, a, states_[k]);
    return test::relative_error(vec(out_).head(expected.size()), vec(expected));
  }

 private:
  const Model<double>& model_;
  Workspace<double> ws_;
  const std::vector<State>& states_;
  std::vector<double> out_;
};

/// MuJoCo's functions that compute what dyngen's do, on its own copy of the peer's model (with
/// the model's gravity, which a chain spec may set and URDF cannot) and its own mjData. Each
/// call copies the state into mjData, as a caller would.
///   RNEA: mj_kinematics, mj_comPos, mj_comVel, mj_rne with accelerations.
///   CRBA: mj_kinematics, mj_comPos, mj_crb, mj_fullM (qM to a dense matrix, as dyngen's).
///   ABA:  mj_forward's smooth path: mj_kinematics, mj_comPos, mj_crb, mj_factorM, mj_comVel,
///         mj_rne without accelerations (the bias force), mj_solveM of qfrc_applied - bias.
class MujocoCode {
 public:
  MujocoCode(const gen::Robot& robot, const char* urdf, bool floating_base,
             const std::vector<State>& states)
      : model_(robot.model),
        peer_(urdf, robot.model, robot.locked, floating_base),
        m_(mj_copyModel(nullptr, peer_.mj()), mj_deleteModel),
        d_(nullptr, mj_deleteData),
        states_(states) {
    m_->opt.gravity[0] = model_.gravity.x;
    m_->opt.gravity[1] = model_.gravity.y;
    m_->opt.gravity[2] = model_.gravity.z;
    d_.reset(mj_makeData(m_.get()));
    const int nv = m_->nv;
    for (const State& s : states) {
      const Eigen::MatrixXd A = peer_.velocity_map(s.q);
      const std::vector<double> qpos = peer_.qpos(s.q);
      const Eigen::VectorXd qvel = A * vec(s.qd),
                            qacc = A * vec(s.qdd) + peer_.free_joint_bias(s.q, s.qd),
                            qfrc = A * vec(s.tau);
      qpos_.insert(qpos_.end(), qpos.begin(), qpos.end());
      qvel_.insert(qvel_.end(), qvel.begin(), qvel.end());
      qacc_.insert(qacc_.end(), qacc.begin(), qacc.end());
      qfrc_.insert(qfrc_.end(), qfrc.begin(), qfrc.end());
    }
    out_.resize(nv * nv);
    force_.resize(nv);
  }

  bool has(Algorithm) const { return true; }

  void run(Algorithm a, int k) {
    const mjModel* m = m_.get();
    mjData* d = d_.get();
    const int nq = m->nq, nv = m->nv;
    mju_copy(d->qpos, &qpos_[k * nq], nq);
    mj_kinematics(m, d);
    mj_comPos(m, d);
    switch (a) {
      case Computes::Other: break;
      case Computes::InverseDynamics:
        mju_copy(d->qvel, &qvel_[k * nv], nv);
        mju_copy(d->qacc, &qacc_[k * nv], nv);
        mj_comVel(m, d);
        mj_rne(m, d, 1, out_.data());
        break;
      case Computes::MassMatrix:
        mj_crb(m, d);
        mj_fullM(m, out_.data(), d->qM);
        break;
      case Computes::ForwardDynamics:
        mju_copy(d->qvel, &qvel_[k * nv], nv);
        mju_copy(d->qfrc_applied, &qfrc_[k * nv], nv);
        mj_crb(m, d);
        mj_factorM(m, d);
        mj_comVel(m, d);
        mj_rne(m, d, 0, d->qfrc_bias);
        mju_sub(force_.data(), d->qfrc_applied, d->qfrc_bias, nv);
        mj_solveM(m, d, out_.data(), force_.data(), 1);
        break;
    }
  }

  /// In dyngen's coordinates (mujoco_peer.hpp): tau = A^T tau_mujoco, M = A^T M_mujoco A,
  /// a = A^T (qacc - bias).
  double error(Algorithm a, int k) {
    run(a, k);
    const State& s = states_[k];
    const Eigen::MatrixXd A = peer_.velocity_map(s.q);
    const int nv = m_->nv;
    const Eigen::Map<const Eigen::VectorXd> out(out_.data(), output_size(a, nv));
    Eigen::VectorXd got;
    switch (a) {
      case Computes::Other: break;
      case Computes::InverseDynamics: got = A.transpose() * out; break;
      case Computes::MassMatrix: {
        const Eigen::MatrixXd M = out.reshaped<Eigen::RowMajor>(nv, nv);
        got = (A.transpose() * M * A).reshaped<Eigen::RowMajor>();
        break;
      }
      case Computes::ForwardDynamics:
        got = A.transpose() * (out - peer_.free_joint_bias(s.q, s.qd));
        break;
    }
    return test::relative_error(got, vec(reference(model_, a, s)));
  }

 private:
  const Model<double>& model_;
  test::mujoco_peer::MujocoRobot peer_;
  std::unique_ptr<mjModel, decltype(&mj_deleteModel)> m_;
  std::unique_ptr<mjData, decltype(&mj_deleteData)> d_;
  const std::vector<State>& states_;
  std::vector<double> qpos_, qvel_, qacc_, qfrc_;  // state k at k * nq or k * nv
  std::vector<double> out_, force_;
};

/// orocos-KDL's solvers, on the peer's tree (kdl_peer.hpp: the locked joints fixed, a floating
/// base as a virtual 6-DoF chain) and on its own state_count random states, drawn in KDL's
/// coordinates from seed (as random_state draws the caller's states).
/// Where the tree is a serial chain (equivalent_chain): ChainIdSolver_RNE,
/// ChainDynParam::JntToMass and ChainFdSolver_RNE; otherwise TreeIdSolver_RNE, and KDL has no
/// mass matrix or forward dynamics of a tree.
class KdlCode {
 public:
  KdlCode(const gen::Robot& robot, const char* urdf, bool floating_base, std::uint64_t seed,
          int state_count)
      : model_(robot.model), tree_(test::kdl::load_tree(urdf, robot.locked, floating_base)) {
    const Vec3<double>& g = model_.gravity;
    const KDL::Vector gravity(g.x, g.y, g.z);
    chain_ = test::kdl::equivalent_chain(tree_, model_.body_name.back());
    const auto names =
        (chain_ ? test::kdl::chain_dynamics(*chain_, g) : test::kdl::tree_dynamics(tree_, g))
            ->joint_names();
    const unsigned n = static_cast<unsigned>(names.size());
    if (chain_) {
      chain_id_ = std::make_unique<KDL::ChainIdSolver_RNE>(*chain_, gravity);
      chain_param_ = std::make_unique<KDL::ChainDynParam>(*chain_, gravity);
      chain_fd_ = std::make_unique<KDL::ChainFdSolver_RNE>(*chain_, gravity);
      no_wrenches_.assign(chain_->getNrOfSegments(), KDL::Wrench::Zero());
    } else {
      tree_id_ = std::make_unique<KDL::TreeIdSolver_RNE>(tree_, gravity);
    }
    Random rng(seed);
    for (int k = 0; k < state_count; ++k) {
      pairs_.push_back(test::kdl::random_state_pair(model_, names, rng));
      const test::kdl::StatePair& s = pairs_.back();
      q_.emplace_back(n), qd_.emplace_back(n), qdd_.emplace_back(n), tau_.emplace_back(n);
      q_.back().data = s.q_kdl, qd_.back().data = s.qd_kdl, qdd_.back().data = s.qdd_kdl;
      tau_.back().data = s.G.transpose() * s.tau;
    }
    out_ = KDL::JntArray(n);
    M_ = KDL::JntSpaceInertiaMatrix(static_cast<int>(n));
  }

  bool is_chain() const { return chain_.has_value(); }

  bool has(Algorithm a) const { return a == Computes::InverseDynamics || chain_; }

  void run(Algorithm a, int k) {
    switch (a) {
      case Computes::Other: break;
      case Computes::InverseDynamics:
        if (chain_)
          chain_id_->CartToJnt(q_[k], qd_[k], qdd_[k], no_wrenches_, out_);
        else
          tree_id_->CartToJnt(q_[k], qd_[k], qdd_[k], no_wrench_map_, out_);
        break;
      case Computes::MassMatrix: chain_param_->JntToMass(q_[k], M_); break;
      case Computes::ForwardDynamics:
        chain_fd_->CartToJnt(q_[k], qd_[k], tau_[k], no_wrenches_, out_);
        break;
    }
  }

  /// In KDL's coordinates for RNEA and CRBA, in dyngen's for ABA (kdl_peer.hpp).
  double error(Algorithm a, int k) {
    run(a, k);
    const test::kdl::StatePair& s = pairs_[k];
    const State state{{s.q.begin(), s.q.end()},
                      {s.v.begin(), s.v.end()},
                      {s.a.begin(), s.a.end()},
                      {s.tau.begin(), s.tau.end()}};
    const std::vector<double> expected = reference(model_, a, state);
    const int nv = model_.nv;
    switch (a) {
      case Computes::Other: break;
      case Computes::InverseDynamics:
        return test::relative_error(out_.data, s.G.transpose() * vec(expected));
      case Computes::MassMatrix: {
        const Eigen::MatrixXd M = vec(expected).reshaped<Eigen::RowMajor>(nv, nv);
        return test::relative_error(M_.data.reshaped(), (s.G.transpose() * M * s.G).reshaped());
      }
      case Computes::ForwardDynamics:
        return test::relative_error(s.G * out_.data + s.Gdot_qd, vec(expected));
    }
    return NAN;
  }

 private:
  const Model<double>& model_;
  KDL::Tree tree_;  // the solvers keep references to it and to chain_
  std::optional<KDL::Chain> chain_;
  std::unique_ptr<KDL::ChainIdSolver_RNE> chain_id_;
  std::unique_ptr<KDL::ChainDynParam> chain_param_;
  std::unique_ptr<KDL::ChainFdSolver_RNE> chain_fd_;
  std::unique_ptr<KDL::TreeIdSolver_RNE> tree_id_;
  KDL::Wrenches no_wrenches_;
  KDL::WrenchMap no_wrench_map_;
  std::vector<test::kdl::StatePair> pairs_;
  std::vector<KDL::JntArray> q_, qd_, qdd_, tau_;
  KDL::JntArray out_;
  KDL::JntSpaceInertiaMatrix M_;
};

}  // namespace dyngen::bench
