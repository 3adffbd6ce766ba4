#include "kdl_peer.hpp"

#include <tinyxml2.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <map>
#include <numbers>
#include <set>
#include <stdexcept>

namespace dyngen::test::kdl {

namespace {

constexpr double pi = std::numbers::pi;

/// The virtual 6-DoF chain under a world root: massless segments with identity tip frames,
/// so the last one's frame is the base frame, at p with orientation R.
KDL::Tree virtual_base_tree() {
  const KDL::Joint::JointType types[6] = {KDL::Joint::TransX, KDL::Joint::TransY,
                                          KDL::Joint::TransZ, KDL::Joint::RotZ,
                                          KDL::Joint::RotY,   KDL::Joint::RotX};
  KDL::Tree tree("kdl_peer_world");
  std::string hook = "kdl_peer_world";
  for (int d = 0; d < 6; ++d) {
    const std::string segment = virtual_joints[d] + "_link";
    tree.addSegment(KDL::Segment(segment, KDL::Joint(virtual_joints[d], types[d]),
                                 KDL::Frame::Identity(), KDL::RigidBodyInertia::Zero()),
                    hook);
    hook = segment;
  }
  return tree;
}

bool is_massless(const KDL::RigidBodyInertia& I) {
  const KDL::RotationalInertia J = I.getRotationalInertia();
  return I.getMass() == 0 && std::all_of(J.data, J.data + 9, [](double x) { return x == 0; });
}

KDL::JntArray jnt(const Eigen::VectorXd& x) {
  KDL::JntArray a(static_cast<unsigned>(x.size()));
  a.data = x;
  return a;
}

void check(int error, const char* what) {
  if (error < 0)
    throw std::runtime_error(std::string(what) + " failed with KDL error " + std::to_string(error));
}

class TreeDynamics final : public Dynamics {
 public:
  TreeDynamics(const KDL::Tree& tree, const Vec3<double>& g)
      : tree_(tree),
        rne_(tree_, KDL::Vector(g.x, g.y, g.z)),
        rne_no_gravity_(tree_, KDL::Vector::Zero()) {
    names_.resize(tree_.getNrOfJoints());
    for (const auto& [name, element] : tree_.getSegments()) {
      const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
      if (joint.getType() != KDL::Joint::Fixed)
        names_[GetTreeElementQNr(element)] = joint.getName();
    }
  }

  Eigen::VectorXd inverse(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                          const Eigen::VectorXd& qdd) override {
    return inverse(rne_, q, qd, qdd);
  }

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) override {
    const Eigen::Index n = q.size();
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd M(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
      M.col(j) = inverse(rne_no_gravity_, q, zero, Eigen::VectorXd::Unit(n, j));
    return M;
  }

  Eigen::VectorXd forward(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                          const Eigen::VectorXd& tau) override {
    const Eigen::VectorXd h = inverse(q, qd, Eigen::VectorXd::Zero(q.size()));
    const Eigen::LLT<Eigen::MatrixXd> llt(mass_matrix(q));
    if (llt.info() != Eigen::Success)
      throw std::runtime_error("KDL's mass matrix is not positive definite");
    return llt.solve(tau - h);
  }

 private:
  static Eigen::VectorXd inverse(KDL::TreeIdSolver_RNE& rne, const Eigen::VectorXd& q,
                                 const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    KDL::JntArray tau(static_cast<unsigned>(q.size()));
    check(rne.CartToJnt(jnt(q), jnt(qd), jnt(qdd), KDL::WrenchMap{}, tau), "TreeIdSolver_RNE");
    return tau.data;
  }

  KDL::Tree tree_;  // the solvers keep a reference to it
  KDL::TreeIdSolver_RNE rne_, rne_no_gravity_;
};

class ChainDynamics final : public Dynamics {
 public:
  ChainDynamics(const KDL::Chain& chain, const Vec3<double>& g)
      : chain_(chain),
        no_wrenches_(chain_.getNrOfSegments(), KDL::Wrench::Zero()),
        id_(chain_, KDL::Vector(g.x, g.y, g.z)),
        param_(chain_, KDL::Vector(g.x, g.y, g.z)),
        fd_(chain_, KDL::Vector(g.x, g.y, g.z)) {
    for (const KDL::Segment& segment : chain_.segments)
      if (segment.getJoint().getType() != KDL::Joint::Fixed)
        names_.push_back(segment.getJoint().getName());
  }

  Eigen::VectorXd inverse(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                          const Eigen::VectorXd& qdd) override {
    KDL::JntArray tau(static_cast<unsigned>(q.size()));
    check(id_.CartToJnt(jnt(q), jnt(qd), jnt(qdd), no_wrenches_, tau), "ChainIdSolver_RNE");
    return tau.data;
  }

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) override {
    KDL::JntSpaceInertiaMatrix M(static_cast<int>(q.size()));
    check(param_.JntToMass(jnt(q), M), "ChainDynParam::JntToMass");
    return M.data;
  }

  Eigen::VectorXd forward(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                          const Eigen::VectorXd& tau) override {
    KDL::JntArray qdd(static_cast<unsigned>(q.size()));
    check(fd_.CartToJnt(jnt(q), jnt(qd), jnt(tau), no_wrenches_, qdd), "ChainFdSolver_RNE");
    return qdd.data;
  }

 private:
  KDL::Chain chain_;  // the solvers keep a reference to it
  KDL::Wrenches no_wrenches_;
  KDL::ChainIdSolver_RNE id_;
  KDL::ChainDynParam param_;
  KDL::ChainFdSolver_RNE fd_;
};

/// Fills the free joint's blocks (q at iq, v at iv) from random virtual-joint coordinates
/// (KDL columns k[0..5], in virtual_joints order).
void fill_free_joint(StatePair& s, int iq, int iv, const int (&k)[6], Random& rng) {
  Eigen::Vector3d p, angles, pd, rates, pdd, accelerations;
  p << rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1);
  angles << rng.uniform(-pi, pi), rng.uniform(-1.4, 1.4), rng.uniform(-pi, pi);
  for (Eigen::Vector3d* x : {&pd, &rates, &pdd, &accelerations})
    *x << rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2);

  const Eigen::AngleAxisd yaw(angles[0], Eigen::Vector3d::UnitZ());
  const Eigen::AngleAxisd pitch(angles[1], Eigen::Vector3d::UnitY());
  const Eigen::AngleAxisd roll(angles[2], Eigen::Vector3d::UnitX());
  const Eigen::Quaterniond orientation = yaw * pitch * roll;
  const Eigen::Matrix3d R = orientation.toRotationMatrix();
  s.q.segment<3>(iq) = p;
  s.q.segment<4>(iq + 3) << orientation.w(), orientation.x(), orientation.y(), orientation.z();

  // The virtual revolute axes in world coordinates: each turns with the joints before it.
  Eigen::Matrix3d axes;
  axes.col(0) = Eigen::Vector3d::UnitZ();
  axes.col(1) = yaw * Eigen::Vector3d::UnitY();
  axes.col(2) = (yaw * pitch) * Eigen::Vector3d::UnitX();
  // v = R^T pd and w = R^T axes rates, both in base coordinates
  Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Zero();
  T.topLeftCorner<3, 3>() = R.transpose();
  T.bottomRightCorner<3, 3>() = R.transpose() * axes;

  // d/dt (R^T pd) = R^T pdd - w x v (as dR/dt = R skew(w)), and d/dt (R^T w_world) =
  // R^T dw_world/dt, where each axis turns with the rates of the joints before it:
  // dw_world/dt = axes accelerations + w0 x w1 + (w0 + w1) x w2, w_j = axes_j rates_j.
  const Eigen::Vector3d w0 = axes.col(0) * rates[0], w1 = axes.col(1) * rates[1],
                        w2 = axes.col(2) * rates[2];
  const Eigen::Vector3d v = R.transpose() * pd, w = R.transpose() * (w0 + w1 + w2);
  Eigen::Matrix<double, 6, 1> Tdot_qd;
  Tdot_qd << -w.cross(v), R.transpose() * (w0.cross(w1) + (w0 + w1).cross(w2));

  Eigen::Matrix<double, 6, 1> qd, qdd;
  qd << pd, rates;
  qdd << pdd, accelerations;
  s.v.segment<6>(iv) = T * qd;
  s.a.segment<6>(iv) = T * qdd + Tdot_qd;
  s.Gdot_qd.segment<6>(iv) = Tdot_qd;
  for (int d = 0; d < 6; ++d) {
    s.qd_kdl[k[d]] = qd[d];
    s.qdd_kdl[k[d]] = qdd[d];
    s.q_kdl[k[d]] = d < 3 ? p[d] : angles[d - 3];
    s.G.block<6, 1>(iv, k[d]) = T.col(d);
  }
}

}  // namespace

KDL::Tree load_tree(const std::string& urdf_path, const std::vector<std::string>& locked,
                    bool floating_base) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(urdf_path.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(urdf_path + ": cannot read the URDF");
  tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  std::set<std::string> to_lock(locked.begin(), locked.end()), children;
  for (auto* joint = robot->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    if (to_lock.erase(joint->Attribute("name"))) joint->SetAttribute("type", "fixed");
    children.insert(joint->FirstChildElement("child")->Attribute("link"));
  }
  if (!to_lock.empty())
    throw std::runtime_error(urdf_path + ": no joint '" + *to_lock.begin() + "' to lock");

  // kdl_parser drops the root link's inertia (with a warning), so the root link goes under a
  // dummy link, as that warning suggests. On a fixed base the root link's mass then rests on
  // the ground, where it moves nothing (dyngen drops it); on a floating base it is the base.
  const auto* root = robot->FirstChildElement("link");
  while (root && children.count(root->Attribute("name"))) root = root->NextSiblingElement("link");
  if (!root) throw std::runtime_error(urdf_path + ": no root link");
  const std::string dummy = "kdl_peer_root";
  robot->InsertNewChildElement("link")->SetAttribute("name", dummy.c_str());
  tinyxml2::XMLElement* joint = robot->InsertNewChildElement("joint");
  joint->SetAttribute("name", (dummy + "_joint").c_str());
  joint->SetAttribute("type", "fixed");
  joint->InsertNewChildElement("parent")->SetAttribute("link", dummy.c_str());
  joint->InsertNewChildElement("child")->SetAttribute("link", root->Attribute("name"));
  KDL::Tree tree;
  if (!kdl_parser::treeFromXml(&doc, tree))
    throw std::runtime_error(urdf_path + ": kdl_parser could not build a tree");
  if (!floating_base) return tree;

  KDL::Tree floating = virtual_base_tree();
  if (!floating.addTree(tree, virtual_joints.back() + "_link"))
    throw std::runtime_error(urdf_path + ": cannot hang the robot from the virtual chain");
  return floating;
}

std::optional<KDL::Chain> equivalent_chain(const KDL::Tree& tree, const std::string& tip) {
  KDL::Chain chain;
  const auto root = tree.getRootSegment();
  if (!tree.getChain(root->first, tip, chain) || chain.getNrOfJoints() != tree.getNrOfJoints())
    return std::nullopt;
  std::set<std::string> on_chain;
  for (const KDL::Segment& segment : chain.segments) on_chain.insert(segment.getName());
  for (auto it = tree.getSegments().begin(); it != tree.getSegments().end(); ++it) {
    if (it == root || on_chain.count(it->first) ||
        is_massless(GetTreeElementSegment(it->second).getInertia()))
      continue;
    for (auto up = it; up != root; up = GetTreeElementParent(up->second))
      if (GetTreeElementSegment(up->second).getJoint().getType() != KDL::Joint::Fixed)
        return std::nullopt;  // a mass off the chain that moves
  }
  return chain;
}

std::unique_ptr<Dynamics> tree_dynamics(const KDL::Tree& tree, const Vec3<double>& gravity) {
  return std::make_unique<TreeDynamics>(tree, gravity);
}

std::unique_ptr<Dynamics> chain_dynamics(const KDL::Chain& chain, const Vec3<double>& gravity) {
  return std::make_unique<ChainDynamics>(chain, gravity);
}

StatePair random_state_pair(const Model<double>& model, const std::vector<std::string>& kdl_names,
                            Random& rng) {
  const Eigen::Index nk = static_cast<Eigen::Index>(kdl_names.size());
  std::map<std::string, int> kdl_index;
  for (int k = 0; k < nk; ++k) kdl_index.emplace(kdl_names[k], k);
  auto column = [&](const std::string& name) {
    const auto it = kdl_index.find(name);
    if (it == kdl_index.end())
      throw std::runtime_error("joint '" + name + "' is not in KDL's model");
    return it->second;
  };

  StatePair s;
  s.q = Eigen::VectorXd::Zero(model.nq);
  s.v = s.a = s.Gdot_qd = Eigen::VectorXd::Zero(model.nv);
  s.q_kdl = s.qd_kdl = s.qdd_kdl = Eigen::VectorXd::Zero(nk);
  s.G = Eigen::MatrixXd::Zero(model.nv, nk);
  for (int i = 0; i < model.nbodies; ++i) {
    const int iq = model.q_index[i], iv = model.v_index[i];
    if (model.joint_type[i] == JointType::Free) {
      if (model.parent[i] != -1) throw std::runtime_error("a free joint that is not the root's");
      int k[6];
      for (int d = 0; d < 6; ++d) k[d] = column(virtual_joints[d]);
      fill_free_joint(s, iq, iv, k, rng);
      continue;
    }
    const int k = column(model.joint_name[i]);
    s.q[iq] = s.q_kdl[k] = rng.uniform(-pi, pi);
    s.v[iv] = s.qd_kdl[k] = rng.uniform(-2, 2);
    s.a[iv] = s.qdd_kdl[k] = rng.uniform(-2, 2);
    s.G(iv, k) = 1;
  }
  for (Eigen::Index k = 0; k < nk; ++k)
    if (s.G.col(k).isZero(0))
      throw std::runtime_error("KDL joint '" + kdl_names[k] + "' is not in dyngen's model");
  s.tau = Eigen::VectorXd::NullaryExpr(model.nv, [&rng] { return rng.uniform(-5, 5); });
  return s;
}

}  // namespace dyngen::test::kdl
