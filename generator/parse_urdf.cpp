// URDF through urdfdom. tinyxml2 reads the file first for line-numbered XML errors, the
// document order of joints and the tags urdfdom ignores.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <console_bridge/console.h>
#include <fmt/format.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include "names.hpp"
#include "readers.hpp"

namespace dyngen::gen {

namespace {

/// Collects urdfdom's console_bridge messages instead of printing them.
class CollectMessages : public console_bridge::OutputHandler {
 public:
  CollectMessages() { console_bridge::useOutputHandler(this); }
  ~CollectMessages() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors.push_back(text);
    else if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) warnings.push_back(text);
  }
  std::vector<std::string> errors, warnings;
};

Vec3<double> vec(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

Mat3<double> rotation(const urdf::Rotation& r) {
  return rotation_from_quaternion(r.x, r.y, r.z, r.w);
}

/// Elements of <robot> and of its links and joints that urdfdom uses; others are ignored
/// with a warning.
const std::set<std::string> known_robot_children{"link", "joint", "material"};
const std::set<std::string> known_link_children{"inertial", "visual", "collision"};
const std::set<std::string> known_joint_children{"origin", "parent", "child", "axis", "limit",
                                                 "dynamics", "safety_controller", "calibration",
                                                 "mimic"};

/// urdfdom reports a loop only as "no root link"; this names the joints on it.
void check_no_loop(const std::string& path, const tinyxml2::XMLElement* robot) {
  std::map<std::string, std::pair<std::string, std::string>> up;  // child -> (joint, parent)
  std::vector<std::string> children;
  for (const auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const auto* parent = j->FirstChildElement("parent");
    const auto* child = j->FirstChildElement("child");
    // incomplete joints are urdfdom's to report
    if (!j->Attribute("name") || !parent || !child || !parent->Attribute("link") ||
        !child->Attribute("link"))
      continue;
    if (up.emplace(child->Attribute("link"),
                   std::pair{std::string(j->Attribute("name")), parent->Attribute("link")})
            .second)
      children.emplace_back(child->Attribute("link"));
  }
  // Each link's way up is walked once (a walk per link would take quadratic time on a long
  // chain): it ends at a root, leads into a loop, or is on one. The first link in document order
  // that is on a loop is reported.
  enum class Way { Unknown, ToRoot, IntoLoop, OnLoop };
  std::map<std::string, Way> way;
  for (const std::string& start : children) {
    if (way[start] == Way::Unknown) {
      std::vector<std::string> walked;
      std::map<std::string, std::size_t> step;
      Way end = Way::ToRoot;
      for (std::string link = start;;) {
        step.emplace(link, walked.size());
        walked.push_back(link);
        const auto it = up.find(link);
        if (it == up.end()) break;
        link = it->second.second;
        const auto known = way.find(link);
        if (known != way.end() && known->second != Way::Unknown) {
          end = known->second == Way::ToRoot ? Way::ToRoot : Way::IntoLoop;
          break;
        }
        if (const auto again = step.find(link); again != step.end()) {
          for (std::size_t k = again->second; k < walked.size(); ++k) way[walked[k]] = Way::OnLoop;
          walked.resize(again->second);
          end = Way::IntoLoop;
          break;
        }
      }
      for (const std::string& link : walked) way[link] = end;
    }
    if (way[start] != Way::OnLoop) continue;
    std::string joints, link = start;
    do {
      const auto& [joint, parent] = up.at(link);
      joints += (joints.empty() ? "'" : ", '") + joint + "'";
      link = parent;
    } while (link != start);
    throw InputError(fmt::format(
        "{}: joints {} form a loop (link '{}' is its own ancestor); a URDF must be a tree", path,
        joints, start));
  }
}

}  // namespace

namespace {

/// The moving joints as Pinocchio's URDF parser numbers them (pinocchio::urdf::buildModel):
/// depth first from the root link, each link's child joints in urdfdom's order, which is the
/// order of their names (it keeps joints in a std::map); or the reason it gives other
/// coordinates than dyngen's (a continuous joint is cos and sin there).
void pinocchio_order(const urdf::ModelInterface& urdf, RobotDescription& robot) {
  for (const auto& [name, joint] : urdf.joints_)
    if (joint->type == urdf::Joint::CONTINUOUS || joint->type == urdf::Joint::PLANAR ||
        joint->type == urdf::Joint::FLOATING) {
      robot.pinocchio_missing =
          fmt::format("joint '{}' is {}", safe_text(name),
                      joint->type == urdf::Joint::CONTINUOUS
                          ? "continuous, which is cos and sin there"
                          : "planar or floating, with other coordinates there");
      return;
    }
  // a stack of joints to visit, the next on top: each link's children pushed in reverse; a
  // link once (the builder, later, refuses what is not a tree)
  std::vector<urdf::JointSharedPtr> joints(urdf.getRoot()->child_joints.rbegin(),
                                           urdf.getRoot()->child_joints.rend());
  std::set<std::string> visited{urdf.getRoot()->name};
  while (!joints.empty()) {
    const urdf::JointSharedPtr joint = joints.back();
    joints.pop_back();
    const urdf::LinkConstSharedPtr child = urdf.getLink(joint->child_link_name);
    if (!child || !visited.insert(child->name).second) continue;
    if (joint->type != urdf::Joint::FIXED) robot.pinocchio_order.push_back(joint->name);
    joints.insert(joints.end(), child->child_joints.rbegin(), child->child_joints.rend());
  }
  robot.pinocchio_missing.clear();
}

}  // namespace

RobotDescription parse_urdf(const std::string& path, const std::string& xml) {
  RobotDescription robot;

  tinyxml2::XMLDocument doc;
  parse_xml(path, xml, doc);
  const tinyxml2::XMLElement* root = doc.FirstChildElement("robot");
  if (!root) throw InputError(fmt::format("{}: not a URDF: no <robot> element", path));
  check_no_loop(path, root);
  std::vector<std::string> joint_order;
  std::set<std::string> ignored;
  for (const auto* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->Name();
    if (!known_robot_children.count(tag)) {
      ignored.insert("<" + tag + ">");
      continue;
    }
    const auto& known = tag == "link" ? known_link_children : known_joint_children;
    if (tag != "material")
      for (const auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
        if (!known.count(c->Name())) ignored.insert(fmt::format("<{}> in <{}>", c->Name(), tag));
    if (tag == "joint" && e->Attribute("name")) joint_order.push_back(e->Attribute("name"));
  }
  for (const std::string& tag : ignored)
    robot.warnings.push_back(fmt::format("{}: {} is not used by dyngen and is ignored", path, tag));

  urdf::ModelInterfaceSharedPtr urdf;
  {
    CollectMessages messages;
    urdf = urdf::parseURDF(xml);
    for (const std::string& w : messages.warnings)
      robot.warnings.push_back(fmt::format("{}: {}", path, w));
    // urdfdom logs some errors (an unreadable <inertial> number) and still returns a model
    if (!urdf || !messages.errors.empty()) {
      std::string why;
      for (const std::string& e : messages.errors) why += (why.empty() ? "" : "; ") + e;
      throw InputError(fmt::format("{}: invalid URDF: {}", path, why.empty() ? "urdfdom rejected it" : why));
    }
  }
  robot.name = urdf->getName();

  std::string massless;
  for (const auto& [name, link] : urdf->links_) {
    LinkSpec spec;
    spec.name = name;
    if (!link->inertial) {
      massless += (massless.empty() ? "'" : ", '") + name + "'";
    } else {
      const urdf::Inertial& in = *link->inertial;
      spec.mass = in.mass;
      spec.com = vec(in.origin.position);
      spec.R = rotation(in.origin.rotation);
      spec.I_com = {in.ixx, in.iyy, in.izz, in.ixy, in.ixz, in.iyz};
    }
    robot.builder.add_link(spec);
  }
  if (!massless.empty())
    robot.warnings.push_back(
        fmt::format("{}: links without <inertial>, treated as massless frames: {}", path, massless));

  std::map<std::string, int> position;
  for (std::size_t k = 0; k < joint_order.size(); ++k) position.emplace(joint_order[k], k);
  std::vector<urdf::JointSharedPtr> joints;
  for (const auto& [name, joint] : urdf->joints_) joints.push_back(joint);
  std::stable_sort(joints.begin(), joints.end(), [&](const auto& a, const auto& b) {
    return position[a->name] < position[b->name];
  });
  for (const urdf::JointSharedPtr& joint : joints) {
    JointSpec spec;
    spec.name = joint->name;
    spec.parent = joint->parent_link_name;
    spec.child = joint->child_link_name;
    spec.xyz = vec(joint->parent_to_joint_origin_transform.position);
    spec.R = rotation(joint->parent_to_joint_origin_transform.rotation);
    spec.axis = vec(joint->axis);
    switch (joint->type) {
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS: spec.kind = JointKind::Revolute; break;
      case urdf::Joint::PRISMATIC: spec.kind = JointKind::Prismatic; break;
      case urdf::Joint::FIXED: spec.kind = JointKind::Fixed; break;
      case urdf::Joint::FLOATING: spec.kind = JointKind::Floating; break;
      case urdf::Joint::PLANAR: spec.kind = JointKind::Planar; break;
      case urdf::Joint::UNKNOWN:
        throw InputError(fmt::format("{}: joint '{}': unknown joint type", path, joint->name));
    }
    const bool has_axis = spec.kind != JointKind::Fixed && spec.kind != JointKind::Floating;
    const double norm = scaled_length(spec.axis);
    if (has_axis && norm > 0 && std::abs(norm - 1) > 1e-6)
      robot.warnings.push_back(fmt::format(
          "{}: joint '{}': axis ({} {} {}) has length {:.6g}; it is normalised", path, joint->name,
          spec.axis.x, spec.axis.y, spec.axis.z, norm));
    if (joint->mimic)
      robot.mimics.push_back({joint->name, joint->mimic->joint_name, joint->mimic->multiplier,
                              joint->mimic->offset});
    robot.builder.add_joint(spec);
  }
  pinocchio_order(*urdf, robot);
  return robot;
}

}  // namespace dyngen::gen
