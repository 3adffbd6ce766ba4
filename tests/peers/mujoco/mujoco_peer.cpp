#include "mujoco_peer.hpp"

#include <tinyxml2.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "test_support.hpp"

namespace dyngen::test::mujoco_peer {

namespace {

using tinyxml2::XMLElement;
using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// fusestatic="false": every link stays a body of its own, welded to its parent by a fixed
// joint; fusing would re-diagonalise merged inertias with MuJoCo's inaccurate eigensolver.
// inertiafromgeom="false": a link without <inertial> has no mass, as in dyngen, instead of one
// computed from its geometry. balanceinertia: load the links whose inertia breaks A + B >= C
// (dyngen accepts them with a warning); MujocoRobot puts their moments back. boundmass,
// boundinertia = 0 (the defaults): no mass or inertia is raised.
constexpr const char* compiler_options =
    "<mujoco><compiler fusestatic=\"false\" discardvisual=\"true\" inertiafromgeom=\"false\" "
    "balanceinertia=\"true\" boundmass=\"0\" boundinertia=\"0\"/></mujoco>";

std::string attribute(const XMLElement* e, const char* name) {
  const char* value = e->Attribute(name);
  return value ? value : "";
}

std::string link_of(const XMLElement* joint, const char* role) {
  const XMLElement* e = joint->FirstChildElement(role);
  return e ? attribute(e, "link") : "";
}

/// Numbers as text that reads back to the same doubles.
std::string format(std::initializer_list<double> values) {
  std::string text;
  for (const double x : values) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", x);
    if (!text.empty()) text += ' ';
    text += buffer;
  }
  return text;
}

Vector3 read_vector(const XMLElement* e, const char* name) {
  Vector3 v = Vector3::Zero();
  std::istringstream text(e ? attribute(e, name) : "");
  text >> v(0) >> v(1) >> v(2);
  return v;
}

/// URDF's rotation from roll, pitch and yaw: Rz(yaw) Ry(pitch) Rx(roll).
Matrix3 rotation_from_rpy(const Vector3& rpy) {
  return (Eigen::AngleAxisd(rpy(2), Vector3::UnitZ()) *
          Eigen::AngleAxisd(rpy(1), Vector3::UnitY()) * Eigen::AngleAxisd(rpy(0), Vector3::UnitX()))
      .toRotationMatrix();
}

/// Roll, pitch and yaw of a rotation; at pitch +-pi/2 exactly, the one with yaw 0.
Vector3 rpy_from_rotation(const Matrix3& R) {
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  if (std::hypot(R(0, 0), R(1, 0)) == 0) return {std::atan2(-R(1, 2), R(1, 1)), pitch, 0};
  return {std::atan2(R(2, 1), R(2, 2)), pitch, std::atan2(R(1, 0), R(0, 0))};
}

/// Principal axes (columns, a rotation as close to the identity as the axes allow, which
/// keeps the inertial frame's pitch away from +-pi/2) and moments of a symmetric tensor.
std::pair<Matrix3, Vector3> principal_axes(const Matrix3& J) {
  const Eigen::SelfAdjointEigenSolver<Matrix3> eig(J);
  std::array<int, 3> order{0, 1, 2}, best = order;
  double best_alignment = -1;
  do {
    const double alignment = std::abs(eig.eigenvectors()(0, order[0])) +
                             std::abs(eig.eigenvectors()(1, order[1])) +
                             std::abs(eig.eigenvectors()(2, order[2]));
    if (alignment > best_alignment) best_alignment = alignment, best = order;
  } while (std::next_permutation(order.begin(), order.end()));
  Matrix3 axes;
  Vector3 moments;
  for (int k = 0; k < 3; ++k) {
    const double sign = eig.eigenvectors()(k, best[k]) < 0 ? -1 : 1;
    axes.col(k) = sign * eig.eigenvectors().col(best[k]);
    moments(k) = eig.eigenvalues()(best[k]);
  }
  if (axes.determinant() < 0) axes.col(2) *= -1;
  return {axes, moments};
}

/// Rewrites a link's <inertial> with a diagonal inertia in its principal axes.
PrincipalInertia diagonalise_inertia(XMLElement* inertial) {
  XMLElement* origin = inertial->FirstChildElement("origin");
  if (!origin) origin = inertial->InsertNewChildElement("origin");
  XMLElement* inertia = inertial->FirstChildElement("inertia");
  if (!inertia) inertia = inertial->InsertNewChildElement("inertia");
  auto get = [&](const char* name) { return inertia->DoubleAttribute(name, 0.0); };
  Matrix3 J;
  J << get("ixx"), get("ixy"), get("ixz"), get("ixy"), get("iyy"), get("iyz"), get("ixz"),
      get("iyz"), get("izz");
  const auto [axes, moments] = principal_axes(J);
  const Matrix3 frame = rotation_from_rpy(read_vector(origin, "rpy")) * axes;
  const Vector3 rpy = rpy_from_rotation(frame);
  origin->SetAttribute("rpy", format({rpy(0), rpy(1), rpy(2)}).c_str());
  for (const char* product : {"ixy", "ixz", "iyz"}) inertia->SetAttribute(product, "0");
  inertia->SetAttribute("ixx", format({moments(0)}).c_str());
  inertia->SetAttribute("iyy", format({moments(1)}).c_str());
  inertia->SetAttribute("izz", format({moments(2)}).c_str());
  const Eigen::Quaterniond quat(frame);
  return {{moments(0), moments(1), moments(2)}, {quat.w(), quat.x(), quat.y(), quat.z()}};
}

/// Rotation of a unit quaternion given w first (dyngen's free joint and MuJoCo).
Matrix3 rotation(std::span<const double> wxyz) {
  RowMajor3 R;
  mju_quat2Mat(R.data(), wxyz.data());
  return R;
}

int mujoco_joint_type(JointType t) {
  switch (t) {
    case JointType::Prismatic: return mjJNT_SLIDE;
    case JointType::Free: return mjJNT_FREE;
    case JointType::Ball: return mjJNT_BALL;
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

  MujocoUrdf result;
  std::map<std::string, XMLElement*> links, parent_joint;  // by link name
  for (XMLElement* link = robot->FirstChildElement("link"); link;
       link = link->NextSiblingElement("link")) {
    for (const char* tag : {"visual", "collision"})
      while (XMLElement* e = link->FirstChildElement(tag)) link->DeleteChild(e);
    const std::string name = attribute(link, "name");
    links[name] = link;
    if (XMLElement* inertial = link->FirstChildElement("inertial")) {
      const PrincipalInertia principal = diagonalise_inertia(inertial);
      const auto& [a, b, c] = principal.moments;
      if (a + b < c || a + c < b || b + c < a) result.unphysical[name] = principal;
    }
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
    // MuJoCo's URDF importer takes the link named "world" for its world body: the free joint
    // goes from a new link of that name (the root, if it has that name, is renamed).
    if (root == "world") {
      root = "dyngen_root";
      result.renamed["world"] = root;
      links.at("world")->SetAttribute("name", root.c_str());
      for (const auto& [child, joint] : parent_joint)
        if (link_of(joint, "parent") == "world")
          joint->FirstChildElement("parent")->SetAttribute("link", root.c_str());
    }
    robot->InsertNewChildElement("link")->SetAttribute("name", "world");
    XMLElement* joint = robot->InsertNewChildElement("joint");
    joint->SetAttribute("name", floating_joint);
    joint->SetAttribute("type", "floating");
    joint->InsertNewChildElement("parent")->SetAttribute("link", "world");
    joint->InsertNewChildElement("child")->SetAttribute("link", root.c_str());
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

namespace {

/// A tetrahedron of 1 cm edges as a mesh file of MuJoCo's: binary STL or Wavefront OBJ.
void write_tetrahedron(const std::filesystem::path& file) {
  std::filesystem::create_directories(file.parent_path());
  const float v[4][3] = {{0, 0, 0}, {0.01f, 0, 0}, {0, 0.01f, 0}, {0, 0, 0.01f}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};  // outward
  std::ofstream out(file, std::ios::binary);
  if (file.extension() == ".obj" || file.extension() == ".OBJ") {
    for (const auto& p : v) out << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& f : faces)
      out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  } else {  // STL: 80-byte header, count, then per face a normal, 3 vertices and 2 bytes
    const std::string header(80, ' ');
    const std::uint32_t count = 4;
    out.write(header.data(), 80).write(reinterpret_cast<const char*>(&count), 4);
    for (const auto& f : faces) {
      const float normal[3] = {0, 0, 0};  // MuJoCo takes the winding
      out.write(reinterpret_cast<const char*>(normal), sizeof normal);
      for (int k : f) out.write(reinterpret_cast<const char*>(v[k]), sizeof v[k]);
      out.write("\0\0", 2);
    }
  }
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
}

/// Every element named `name` under e, depth first.
void collect(XMLElement* e, std::string_view name, std::vector<XMLElement*>& found) {
  for (XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (name == c->Name()) found.push_back(c);
    collect(c, name, found);
  }
}

}  // namespace

std::string mujoco_mjcf(const std::string& path, const std::string& dir) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(path + ": " + doc.ErrorStr());
  std::filesystem::create_directories(dir);
  XMLElement* root = doc.RootElement();
  std::vector<XMLElement*> compilers, meshes, options;
  collect(root, "compiler", compilers);
  collect(root, "mesh", meshes);
  collect(root, "option", options);
  std::filesystem::path meshdir = dir;
  for (const XMLElement* c : compilers)
    for (const char* key : {"assetdir", "meshdir"})
      if (c->Attribute(key)) meshdir = std::filesystem::path(dir) / c->Attribute(key);
  for (const XMLElement* mesh : meshes)
    if (mesh->Attribute("file")) write_tetrahedron(meshdir / mesh->Attribute("file"));
  for (XMLElement* option : options) option->DeleteAttribute("integrator");
  const std::string copy = (std::filesystem::path(dir) / std::filesystem::path(path).filename());
  if (doc.SaveFile(copy.c_str()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(copy + ": " + doc.ErrorStr());
  return copy;
}

std::vector<double> qpos(const mjModel* m, const Model<double>& model, std::span<const int> joint,
                         std::span<const double> q) {
  std::vector<double> qpos(m->nq);
  for (int i = 0; i < model.nbodies; ++i)
    std::copy_n(q.begin() + model.q_index[i], joint_nq(model.joint_type[i]),
                qpos.begin() + m->jnt_qposadr[joint[i]]);
  return qpos;
}

Eigen::MatrixXd velocity_map(const mjModel* m, const Model<double>& model,
                             std::span<const int> joint, std::span<const double> q) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(model.nv, model.nv);
  for (int i = 0; i < model.nbodies; ++i) {
    const int dof = m->jnt_dofadr[joint[i]], iv = model.v_index[i];
    if (model.joint_type[i] == JointType::Free) {
      A.block<3, 3>(dof, iv) = rotation(q.subspan(model.q_index[i] + 3, 4));
      A.block<3, 3>(dof + 3, iv + 3).setIdentity();
    } else {
      for (int d = 0; d < joint_nv(model.joint_type[i]); ++d) A(dof + d, iv + d) = 1;
    }
  }
  return A;
}

Eigen::VectorXd free_joint_bias(const mjModel* m, const Model<double>& model,
                                std::span<const int> joint, std::span<const double> q,
                                std::span<const double> v) {
  Eigen::VectorXd bias = Eigen::VectorXd::Zero(m->nv);
  for (int i = 0; i < model.nbodies; ++i) {
    if (model.joint_type[i] != JointType::Free) continue;
    const int iv = model.v_index[i];
    const Eigen::Map<const Vector3> lin(v.data() + iv), ang(v.data() + iv + 3);
    bias.segment<3>(m->jnt_dofadr[joint[i]]) =
        rotation(q.subspan(model.q_index[i] + 3, 4)) * ang.cross(lin);
  }
  return bias;
}

MujocoRobot::MujocoRobot(const std::string& path, const Model<double>& model,
                         const std::vector<std::string>& locked, bool floating_base)
    : model_(model) {
  const MujocoUrdf urdf = mujoco_urdf(path, locked, floating_base);
  renamed_ = urdf.renamed;

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
  // contacts, equality constraints and actuators. Armature is dyngen's, set below.
  m_->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_EQUALITY | mjDSBL_FRICTIONLOSS | mjDSBL_LIMIT |
                          mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;
  std::fill_n(m_->dof_damping, m_->nv, 0.0);
  std::fill_n(m_->dof_frictionloss, m_->nv, 0.0);
  std::fill_n(m_->dof_armature, m_->nv, 0.0);

  // balanceinertia's isotropic moments come with arbitrary axes: put both back
  for (const auto& [link, principal] : urdf.unphysical) {
    const int b = mj_name2id(m_.get(), mjOBJ_BODY, link.c_str());
    if (b <= 0) throw std::runtime_error(path + ": MuJoCo has no body for link '" + link + "'");
    double* inertia = m_->body_inertia + 3 * b;
    balanced_[link] = {inertia[0], inertia[1], inertia[2]};
    std::copy(principal.moments.begin(), principal.moments.end(), inertia);
    std::copy(principal.quat.begin(), principal.quat.end(), m_->body_iquat + 4 * b);
  }

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
    if (!model_.armature.empty() && model_.joint_type[i] != JointType::Free)
      for (int d = 0; d < joint_nv(model_.joint_type[i]); ++d)
        m_->dof_armature[m_->jnt_dofadr[j] + d] = model_.armature[model_.v_index[i] + d];
  }
  d_.reset(mj_makeData(m_.get()));
}

std::pair<Matrix3, Vector3> relative_pose(const mjModel* m, int body, int ancestor) {
  Matrix3 R = Matrix3::Identity();
  Vector3 p = Vector3::Zero();
  for (int l = body; l != ancestor; l = m->body_parentid[l]) {
    if (l == 0) throw std::runtime_error("relative_pose: not an ancestor");
    const Matrix3 R_l = rotation({m->body_quat + 4 * l, 4});
    p = R_l * p + Eigen::Map<const Vector3>(m->body_pos + 3 * l);
    R = R_l * R;
  }
  return {R, p};
}

Eigen::Matrix<double, 6, 6> MujocoRobot::inertia(int i) const {
  const mjModel* m = m_.get();
  const int b = body(i);
  Eigen::Matrix<double, 6, 6> total = Eigen::Matrix<double, 6, 6>::Zero();
  for (int k = 0; k < m->nbody; ++k) {
    if (m->body_weldid[k] != b) continue;
    // body k's inertia about its origin, in its coordinates
    const double mass = m->body_mass[k];
    const Vector3 c = Eigen::Map<const Vector3>(m->body_ipos + 3 * k);
    const Matrix3 Rc = rotation({m->body_iquat + 4 * k, 4});
    const Matrix3 J =
        Rc * Eigen::Map<const Vector3>(m->body_inertia + 3 * k).asDiagonal() * Rc.transpose() +
        mass * (c.squaredNorm() * Matrix3::Identity() - c * c.transpose());
    const Vector3 h = mass * c;
    const RigidInertia<double> I_k{
        mass, {h(0), h(1), h(2)}, {J(0, 0), J(1, 1), J(2, 2), J(0, 1), J(0, 2), J(1, 2)}};
    const auto [R, p] = relative_pose(m, k, b);
    // X maps motion from b's coordinates to k's: X = rot(R^T) xlt(p)
    const Xform<double> X{
        {R(0, 0), R(1, 0), R(2, 0), R(0, 1), R(1, 1), R(2, 1), R(0, 2), R(1, 2), R(2, 2)},
        {p(0), p(1), p(2)}};
    total += dense(X).transpose() * dense(I_k) * dense(X);
  }
  return total;
}

Eigen::MatrixXd MujocoRobot::set_state(std::span<const double> q, std::span<const double> v) {
  const std::vector<double> pos = qpos(q);
  std::copy(pos.begin(), pos.end(), d_->qpos);
  const Eigen::MatrixXd A = velocity_map(q);
  Eigen::Map<Eigen::VectorXd>(d_->qvel, m_->nv) =
      A * Eigen::Map<const Eigen::VectorXd>(v.data(), model_.nv);
  return A;
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
  Eigen::Map<Eigen::VectorXd>(d_->qacc, m_->nv) =
      A * Eigen::Map<const Eigen::VectorXd>(a.data(), model_.nv) + free_joint_bias(q, v);
  // with constraints and passive forces disabled, qfrc_inverse = M qacc + bias, armature in M
  mj_inverse(m_.get(), d_.get());
  const Eigen::VectorXd tau_dyngen =
      A.transpose() * Eigen::Map<const Eigen::VectorXd>(d_->qfrc_inverse, m_->nv);
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

std::vector<double> MujocoRobot::minv(std::span<const double> q) {
  const std::vector<double> zero(model_.nv, 0.0);
  const Eigen::MatrixXd A = set_state(q, zero);
  mj_fwdPosition(m_.get(), d_.get());
  // column-major identity in, M^-1 columns out: M^-1 is symmetric, so either layout
  Eigen::MatrixXd Minv = Eigen::MatrixXd::Identity(m_->nv, m_->nv);
  mj_solveM(m_.get(), d_.get(), Minv.data(), Minv.data(), m_->nv);
  const RowMajorMatrix Minv_dyngen = A.transpose() * Minv * A;
  return {Minv_dyngen.data(), Minv_dyngen.data() + Minv_dyngen.size()};
}

std::pair<std::vector<double>, std::vector<double>> MujocoRobot::aba_derivatives(
    std::span<const double> q, std::span<const double> v, std::span<const double> tau,
    double eps) {
  const int nv = m_->nv, nx = 2 * nv + m_->na;
  const Eigen::MatrixXd A = velocity_map(q);
  const std::vector<double> Minv = minv(q);
  const Eigen::MatrixXd Minv_mj =
      A * Eigen::Map<const RowMajorMatrix>(Minv.data(), nv, nv) * A.transpose();
  const std::vector<double> qdd = aba(q, v, tau);  // leaves the state and qfrc_applied set

  RowMajorMatrix transition(nx, nx);
  // B, C and D have no columns or no rows (no actuators, no sensors), but take no null pointer
  std::vector<double> unused(static_cast<std::size_t>(nx) * (m_->nu + m_->nsensordata) + 1);
  const double timestep = m_->opt.timestep;
  const int integrator = m_->opt.integrator;
  m_->opt.timestep = 1;
  m_->opt.integrator = mjINT_EULER;
  mjd_transitionFD(m_.get(), d_.get(), eps, 1, transition.data(), unused.data(), unused.data(),
                   unused.data());
  m_->opt.timestep = timestep;
  m_->opt.integrator = integrator;
  const Eigen::MatrixXd Jq = transition.block(nv, 0, nv, nv);
  const Eigen::MatrixXd Jv =
      transition.block(nv, nv, nv, nv) - Eigen::MatrixXd::Identity(nv, nv);

  // qdd = A^T (qacc(q, A v, A tau) - bias(q, v)), A and the bias depending on each free
  // joint's rotation R: moved to R (1 + [d]x), R x changes by -R [x]x d and R^T y by
  // [R^T y]x d
  Eigen::MatrixXd dv_bias = Eigen::MatrixXd::Zero(nv, nv), dq_rotation = dv_bias;
  Eigen::MatrixXd dq_outer = Eigen::MatrixXd::Zero(nv, nv);
  for (int i = 0; i < model_.nbodies; ++i) {
    if (model_.joint_type[i] != JointType::Free) continue;
    const int dof = m_->jnt_dofadr[joint_[i]], iv = model_.v_index[i];
    const Matrix3 R = rotation(q.subspan(model_.q_index[i] + 3, 4));
    const Vector3 lin(v.data() + iv), ang(v.data() + iv + 3), force(tau.data() + iv),
        qdd_lin(qdd.data() + iv);
    // bias R (w x v_lin): d / dv_lin = R [w]x, d / dw = -R [v_lin]x, d / d rotation =
    // -R [w x v_lin]x
    dv_bias.block<3, 3>(dof, iv) = R * skew(ang);
    dv_bias.block<3, 3>(dof, iv + 3) = -R * skew(lin);
    // qacc's arguments A v and A tau, less the bias
    dq_rotation.middleCols<3>(iv + 3) += Jv.middleCols<3>(dof) * (-R * skew(lin));
    dq_rotation.middleCols<3>(iv + 3) += Minv_mj.middleCols<3>(dof) * (-R * skew(force));
    // less the bias's -R [w x v_lin]x
    dq_rotation.block<3, 3>(dof, iv + 3) += R * skew(ang.cross(lin));
    // the outer A^T
    dq_outer.block<3, 3>(iv, iv + 3) = skew(qdd_lin);
  }
  const RowMajorMatrix dqdd_dq = A.transpose() * (Jq * A + dq_rotation) + dq_outer;
  const RowMajorMatrix dqdd_dv = A.transpose() * (Jv * A - dv_bias);
  return {{dqdd_dq.data(), dqdd_dq.data() + dqdd_dq.size()},
          {dqdd_dv.data(), dqdd_dv.data() + dqdd_dv.size()}};
}

int MujocoRobot::link_body(const std::string& link) const {
  const auto it = renamed_.find(link);
  return mj_name2id(m_.get(), mjOBJ_BODY, (it == renamed_.end() ? link : it->second).c_str());
}

std::vector<std::pair<Matrix3, Vector3>> MujocoRobot::placements(std::span<const double> q,
                                                                 std::span<const int> bodies) {
  const std::vector<double> zero(model_.nv, 0.0);
  set_state(q, zero);
  mj_kinematics(m_.get(), d_.get());
  std::vector<std::pair<Matrix3, Vector3>> result;
  for (const int b : bodies)
    result.emplace_back(Eigen::Map<const RowMajor3>(d_->xmat + 9 * b),
                        Eigen::Map<const Vector3>(d_->xpos + 3 * b));
  return result;
}

std::vector<Eigen::MatrixXd> MujocoRobot::jacobians(std::span<const double> q,
                                                    std::span<const int> bodies) {
  const std::vector<double> zero(model_.nv, 0.0);
  const Eigen::MatrixXd A = set_state(q, zero);
  mj_kinematics(m_.get(), d_.get());
  mj_comPos(m_.get(), d_.get());
  std::vector<Eigen::MatrixXd> result;
  RowMajorMatrix J(6, m_->nv);
  for (const int b : bodies) {
    mj_jac(m_.get(), d_.get(), J.data(), J.data() + 3 * m_->nv, d_->xpos + 3 * b, b);
    result.emplace_back(J * A);
  }
  return result;
}

std::pair<Vector3, Eigen::MatrixXd> MujocoRobot::com(std::span<const double> q) {
  const std::vector<double> zero(model_.nv, 0.0);
  const Eigen::MatrixXd A = set_state(q, zero);
  mj_kinematics(m_.get(), d_.get());
  mj_comPos(m_.get(), d_.get());
  RowMajorMatrix Jc(3, m_->nv);
  mj_jacSubtreeCom(m_.get(), d_.get(), Jc.data(), 0);
  // the world's subtree also holds the bodies welded to the world (a fixed base's root link and
  // the links fixed to it), which dyngen's model has no inertia for; they add nothing to Jc
  const double mass = m_->body_subtreemass[0];
  double fixed_mass = 0;
  Vector3 fixed_moment = Vector3::Zero();
  for (int b = 1; b < m_->nbody; ++b) {
    if (m_->body_weldid[b] != 0) continue;
    fixed_mass += m_->body_mass[b];
    fixed_moment += m_->body_mass[b] * Eigen::Map<const Vector3>(d_->xipos + 3 * b);
  }
  const double moving_mass = mass - fixed_mass;
  return {(mass * Eigen::Map<const Vector3>(d_->subtree_com) - fixed_moment) / moving_mass,
          (mass / moving_mass) * Jc * A};
}

std::vector<Eigen::Matrix<double, 6, 1>> MujocoRobot::bias_accelerations(
    std::span<const double> q, std::span<const double> v, std::span<const int> bodies) {
  set_state(q, v);
  mj_fwdPosition(m_.get(), d_.get());  // cdof, cinert, subtree_com
  mj_fwdVelocity(m_.get(), d_.get());  // cvel, cdof_dot
  // MuJoCo's qacc when dyngen's is 0
  Eigen::Map<Eigen::VectorXd>(d_->qacc, m_->nv) = free_joint_bias(q, v);
  // cacc starts at the world with -gravity (MuJoCo's RNE adds gravity that way): without it,
  // cacc is the bodies' acceleration (spatial, at the subtree's centre of mass)
  const int flags = m_->opt.disableflags;
  m_->opt.disableflags |= mjDSBL_GRAVITY;
  mj_rnePostConstraint(m_.get(), d_.get());
  m_->opt.disableflags = flags;
  std::vector<Eigen::Matrix<double, 6, 1>> result;
  for (const int b : bodies) {
    // angular first, at xpos; the classical acceleration (it adds w x v to the spatial one)
    std::array<double, 6> a;
    mj_objectAcceleration(m_.get(), d_.get(), mjOBJ_XBODY, b, a.data(), 0);
    result.push_back(
        (Eigen::Matrix<double, 6, 1>() << a[3], a[4], a[5], a[0], a[1], a[2]).finished());
  }
  return result;
}

}  // namespace dyngen::test::mujoco_peer
