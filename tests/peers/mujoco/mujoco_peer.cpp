#include "mujoco_peer.hpp"

#include <tinyxml2.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <stdexcept>

#include "test_support.hpp"

namespace dyngen::test::mujoco_peer {

namespace {

using tinyxml2::XMLElement;
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// fusestatic: merge links on fixed joints into their parent body, as dyngen does (the URDF
// default, said explicitly). inertiafromgeom="false": a link without <inertial> has no mass, as
// in dyngen, instead of one computed from its geometry. balanceinertia: load links whose
// inertia breaks A + B >= C (dyngen accepts them with a warning); MujocoRobot puts their
// inertia back. boundmass, boundinertia = 0 (the defaults): no mass or inertia is raised.
constexpr const char* compiler_options =
    "<mujoco><compiler fusestatic=\"true\" discardvisual=\"true\" inertiafromgeom=\"false\" "
    "balanceinertia=\"true\" boundmass=\"0\" boundinertia=\"0\"/></mujoco>";

std::string attribute(const XMLElement* e, const char* name) {
  const char* value = e->Attribute(name);
  return value ? value : "";
}

std::string link_of(const XMLElement* joint, const char* role) {
  const XMLElement* e = joint->FirstChildElement(role);
  return e ? attribute(e, "link") : "";
}

/// MuJoCo's check of a link's inertia, on the principal moments of the URDF tensor.
bool breaks_triangle_inequality(const XMLElement* link) {
  const XMLElement* inertial = link->FirstChildElement("inertial");
  const XMLElement* inertia = inertial ? inertial->FirstChildElement("inertia") : nullptr;
  if (!inertia) return false;
  auto get = [&](const char* name) { return inertia->DoubleAttribute(name, 0.0); };
  Eigen::Matrix3d J;
  J << get("ixx"), get("ixy"), get("ixz"), get("ixy"), get("iyy"), get("iyz"), get("ixz"),
      get("iyz"), get("izz");
  const Eigen::Vector3d e =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(J, Eigen::EigenvaluesOnly).eigenvalues();
  return e(0) + e(1) < e(2);  // ascending
}

/// Replaces a body's inertial frame, mass and principal moments with a dyngen inertia.
void set_body_inertia(mjModel* m, int body, const RigidInertia<double>& I) {
  const Eigen::Vector3d c = I.m > 0 ? Eigen::Vector3d(dense(I.h) / I.m) : Eigen::Vector3d::Zero();
  const Eigen::Matrix3d Ic =
      dense(I.I) - I.m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Ic);
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) *= -1;
  const Eigen::Quaterniond quat(axes);
  m->body_mass[body] = I.m;
  for (int k = 0; k < 3; ++k) {
    m->body_ipos[3 * body + k] = c(k);
    m->body_inertia[3 * body + k] = eig.eigenvalues()(k);
  }
  const std::array<double, 4> wxyz{quat.w(), quat.x(), quat.y(), quat.z()};
  std::copy(wxyz.begin(), wxyz.end(), m->body_iquat + 4 * body);
}

/// Rotation of a unit quaternion given w first, as dyngen's free joint stores it.
Eigen::Matrix3d rotation(std::span<const double> wxyz) {
  return Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).toRotationMatrix();
}

int mujoco_joint_type(JointType t) {
  switch (t) {
    case JointType::Prismatic: return mjJNT_SLIDE;
    case JointType::Free: return mjJNT_FREE;
    default: return mjJNT_HINGE;
  }
}

}  // namespace

MujocoUrdf mujoco_urdf(const std::string& path, const std::vector<std::string>& locked,
                       bool floating_base) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(path + ": " + doc.ErrorStr());
  XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw std::runtime_error(path + ": no <robot> element");

  std::map<std::string, XMLElement*> links, parent_joint;  // by link name
  for (XMLElement* link = robot->FirstChildElement("link"); link;
       link = link->NextSiblingElement("link")) {
    for (const char* tag : {"visual", "collision"})
      while (XMLElement* e = link->FirstChildElement(tag)) link->DeleteChild(e);
    links[attribute(link, "name")] = link;
  }
  for (XMLElement* joint = robot->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    if (std::ranges::find(locked, attribute(joint, "name")) != locked.end())
      joint->SetAttribute("type", "fixed");  // dyngen locks a joint at q = 0
    parent_joint[link_of(joint, "child")] = joint;
  }

  if (floating_base) {
    std::string root;
    for (const auto& [name, link] : links)
      if (!parent_joint.count(name)) root = name;
    // MuJoCo's URDF importer takes a link named "world" for its world body, which cannot move.
    if (root == "world") {
      root = "dyngen_root";
      links.at("world")->SetAttribute("name", root.c_str());
      for (const auto& [child, joint] : parent_joint)
        if (link_of(joint, "parent") == "world")
          joint->FirstChildElement("parent")->SetAttribute("link", root.c_str());
    }
    XMLElement* world = robot->InsertNewChildElement("link");
    world->SetAttribute("name", "dyngen_world");
    XMLElement* joint = robot->InsertNewChildElement("joint");
    joint->SetAttribute("name", floating_joint);
    joint->SetAttribute("type", "floating");
    joint->InsertNewChildElement("parent")->SetAttribute("link", "dyngen_world");
    joint->InsertNewChildElement("child")->SetAttribute("link", root.c_str());
    parent_joint[root] = joint;
  }

  MujocoUrdf result;
  for (const auto& [name, link] : links) {
    if (!breaks_triangle_inequality(link)) continue;
    // the moving body this link belongs to: up through fixed joints to a moving one
    std::string l = name;
    while (parent_joint.count(l) && attribute(parent_joint.at(l), "type") == "fixed")
      l = link_of(parent_joint.at(l), "parent");
    if (parent_joint.count(l)) result.unphysical.insert(attribute(parent_joint.at(l), "name"));
  }

  while (XMLElement* e = robot->FirstChildElement("mujoco")) robot->DeleteChild(e);
  tinyxml2::XMLDocument options;
  options.Parse(compiler_options);
  robot->InsertFirstChild(options.RootElement()->DeepClone(&doc));

  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  result.text = printer.CStr();
  return result;
}

RigidInertia<double> body_inertia(const mjModel* m, int body) {
  const double mass = m->body_mass[body];
  const Eigen::Map<const Eigen::Vector3d> c(m->body_ipos + 3 * body);
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R;
  mju_quat2Mat(R.data(), m->body_iquat + 4 * body);
  const Eigen::Map<const Eigen::Vector3d> moments(m->body_inertia + 3 * body);
  const Eigen::Matrix3d I = R * moments.asDiagonal() * R.transpose() +
                            mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  return {mass, {mass * c(0), mass * c(1), mass * c(2)},
          {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)}};
}

MujocoRobot::MujocoRobot(const std::string& path, const Model<double>& model,
                         const std::vector<std::string>& locked, bool floating_base)
    : model_(model) {
  const MujocoUrdf urdf = mujoco_urdf(path, locked, floating_base);

  // Load from memory through a virtual file system (an mjVFS is 2 MB: not on the stack).
  const char* file = "robot.urdf";
  const auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), file, static_cast<int>(urdf.text.size())) != 0)
    throw std::runtime_error("cannot make a MuJoCo virtual file");
  std::copy(urdf.text.begin(), urdf.text.end(),
            static_cast<char*>(vfs->filedata[mj_findFileVFS(vfs.get(), file)]));
  std::array<char, 1000> error{};
  m_.reset(mj_loadXML(file, vfs.get(), error.data(), static_cast<int>(error.size())));
  mj_deleteVFS(vfs.get());
  if (!m_) throw std::runtime_error("MuJoCo cannot load " + path + ": " + error.data());

  // Forces dyngen does not model: joint limits and friction (constraints), damping (passive),
  // contacts, equality constraints and actuators; armature would add to the mass matrix.
  m_->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_EQUALITY | mjDSBL_FRICTIONLOSS |
                          mjDSBL_LIMIT | mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;
  std::fill_n(m_->dof_damping, m_->nv, 0.0);
  std::fill_n(m_->dof_frictionloss, m_->nv, 0.0);
  std::fill_n(m_->dof_armature, m_->nv, 0.0);

  if (m_->njnt != model_.nbodies || m_->nq != model_.nq || m_->nv != model_.nv)
    throw std::runtime_error(path + ": MuJoCo has " + std::to_string(m_->njnt) + " joints, nq " +
                             std::to_string(m_->nq) + ", nv " + std::to_string(m_->nv) +
                             "; dyngen " + std::to_string(model_.nbodies) + ", " +
                             std::to_string(model_.nq) + ", " + std::to_string(model_.nv));
  for (int i = 0; i < model_.nbodies; ++i) {
    const int j = mj_name2id(m_.get(), mjOBJ_JOINT, model_.joint_name[i].c_str());
    if (j < 0 || m_->jnt_type[j] != mujoco_joint_type(model_.joint_type[i]))
      throw std::runtime_error(path + ": MuJoCo has no joint '" + model_.joint_name[i] +
                               "' of type " + joint_type_name(model_.joint_type[i]));
    joint_.push_back(j);
    imported_.push_back(body_inertia(m_.get(), body(i)));
    if (urdf.unphysical.count(model_.joint_name[i])) {
      set_body_inertia(m_.get(), body(i), model_.I[i]);
      replaced_.insert(model_.joint_name[i]);
    }
  }
  d_.reset(mj_makeData(m_.get()));
}

Eigen::MatrixXd MujocoRobot::set_state(std::span<const double> q, std::span<const double> v) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(model_.nv, model_.nv);
  for (int i = 0; i < model_.nbodies; ++i) {
    const JointType type = model_.joint_type[i];
    const int j = joint_[i], iq = model_.q_index[i], iv = model_.v_index[i];
    std::copy_n(q.begin() + iq, joint_nq(type), d_->qpos + m_->jnt_qposadr[j]);
    const int dof = m_->jnt_dofadr[j];
    if (type == JointType::Free) {
      A.block<3, 3>(dof, iv) = rotation(q.subspan(iq + 3, 4));
      A.block<3, 3>(dof + 3, iv + 3).setIdentity();
    } else {
      A(dof, iv) = 1;
    }
  }
  Eigen::Map<Eigen::VectorXd>(d_->qvel, m_->nv) =
      A * Eigen::Map<const Eigen::VectorXd>(v.data(), model_.nv);
  return A;
}

Eigen::VectorXd MujocoRobot::free_joint_bias(std::span<const double> q,
                                             std::span<const double> v) const {
  Eigen::VectorXd bias = Eigen::VectorXd::Zero(m_->nv);
  for (int i = 0; i < model_.nbodies; ++i) {
    if (model_.joint_type[i] != JointType::Free) continue;
    const int iv = model_.v_index[i];
    const Eigen::Map<const Eigen::Vector3d> lin(v.data() + iv), ang(v.data() + iv + 3);
    bias.segment<3>(m_->jnt_dofadr[joint_[i]]) =
        rotation(q.subspan(model_.q_index[i] + 3, 4)) * ang.cross(lin);
  }
  return bias;
}

std::vector<double> MujocoRobot::crba(std::span<const double> q) {
  const std::vector<double> zero(model_.nv, 0.0);
  const Eigen::MatrixXd A = set_state(q, zero);
  mj_fwdPosition(m_.get(), d_.get());
  RowMajorMatrix M(m_->nv, m_->nv);
  mj_fullM(m_.get(), M.data(), d_->qM);
  const RowMajorMatrix M_dyngen = A.transpose() * M * A;
  return {M_dyngen.data(), M_dyngen.data() + M_dyngen.size()};
}

std::vector<double> MujocoRobot::rnea(std::span<const double> q, std::span<const double> v,
                                      std::span<const double> a) {
  const Eigen::MatrixXd A = set_state(q, v);
  mj_fwdPosition(m_.get(), d_.get());
  mj_fwdVelocity(m_.get(), d_.get());
  Eigen::Map<Eigen::VectorXd>(d_->qacc, m_->nv) =
      A * Eigen::Map<const Eigen::VectorXd>(a.data(), model_.nv) + free_joint_bias(q, v);
  Eigen::VectorXd tau(m_->nv);
  mj_rne(m_.get(), d_.get(), 1, tau.data());
  const Eigen::VectorXd tau_dyngen = A.transpose() * tau;
  return {tau_dyngen.begin(), tau_dyngen.end()};
}

std::vector<double> MujocoRobot::aba(std::span<const double> q, std::span<const double> v,
                                     std::span<const double> tau) {
  const Eigen::MatrixXd A = set_state(q, v);
  Eigen::Map<Eigen::VectorXd>(d_->qfrc_applied, m_->nv) =
      A * Eigen::Map<const Eigen::VectorXd>(tau.data(), model_.nv);
  mj_forward(m_.get(), d_.get());
  const Eigen::VectorXd a =
      A.transpose() * (Eigen::Map<const Eigen::VectorXd>(d_->qacc, m_->nv) - free_joint_bias(q, v));
  return {a.begin(), a.end()};
}

}  // namespace dyngen::test::mujoco_peer
