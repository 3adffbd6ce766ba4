// The chain spec: a serial chain in YAML (format in docs/chain-spec.md).
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "readers.hpp"

namespace dyngen::gen {

namespace {

struct Reader {
  const std::string& path;

  [[noreturn]] void fail(const YAML::Node& node, const std::string& where,
                         const std::string& what) const {
    const int line = node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
    throw InputError(line > 0 ? fmt::format("{}:{}: {}: {}", path, line, where, what)
                              : fmt::format("{}: {}: {}", path, where, what));
  }

  void only_keys(const YAML::Node& map, const std::string& where,
                 const std::set<std::string>& keys) const {
    if (!map.IsMap()) fail(map, where, "expected a mapping");
    for (const auto& kv : map) {
      if (!kv.first.IsScalar())
        fail(kv.first, where, "a key must be a name, not a list or mapping");
      const std::string key = kv.first.as<std::string>();
      if (!keys.count(key)) {
        std::string allowed;
        for (const std::string& k : keys) allowed += (allowed.empty() ? "" : ", ") + k;
        fail(kv.first, where, fmt::format("unknown key '{}' (allowed: {})", key, allowed));
      }
    }
  }

  double number(const YAML::Node& node, const std::string& where) const {
    double x = 0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, x))
      fail(node, where, "expected a number");
    if (!std::isfinite(x)) fail(node, where, "expected a finite number");
    return x;
  }

  Vec3<double> vec3(const YAML::Node& node, const std::string& where) const {
    if (!node.IsSequence() || node.size() != 3) fail(node, where, "expected [x, y, z]");
    return {number(node[0], where + "[0]"), number(node[1], where + "[1]"),
            number(node[2], where + "[2]")};
  }

  std::string text(const YAML::Node& node, const std::string& where) const {
    if (!node.IsScalar()) fail(node, where, "expected a string");
    return node.as<std::string>();
  }
};

}  // namespace

namespace {

/// loops: [{a: LINK, b: LINK, a_xyz: [x, y, z], b_xyz: [x, y, z], type: 3d | 6d}, ...]: the
/// point at a_xyz in link a's frame held to the point at b_xyz in link b's (default: their
/// origins), and with 6d their orientations too. The links are checked once the model is built.
void parse_loops(const Reader& r, const YAML::Node& loops, RobotDescription& robot) {
  if (!loops.IsSequence()) r.fail(loops, "loops", "expected a list of loop closures");
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const YAML::Node loop = loops[k];
    const std::string at = fmt::format("loops[{}]", k);
    r.only_keys(loop, at, {"a", "b", "a_xyz", "b_xyz", "type"});
    RobotDescription::Loop l;
    for (const char* key : {"a", "b"})
      if (!loop[key]) r.fail(loop, at, fmt::format("missing '{}' (a link)", key));
    l.link_a = r.text(loop["a"], at + ".a");
    l.link_b = r.text(loop["b"], at + ".b");
    if (loop["a_xyz"]) l.xyz_a = r.vec3(loop["a_xyz"], at + ".a_xyz");
    if (loop["b_xyz"]) l.xyz_b = r.vec3(loop["b_xyz"], at + ".b_xyz");
    if (loop["type"]) {
      const std::string type = r.text(loop["type"], at + ".type");
      if (type != "3d" && type != "6d")
        r.fail(loop["type"], at + ".type", fmt::format("'{}' is not 3d or 6d", type));
      l.six_d = type == "6d";
    }
    robot.loops.push_back(l);
  }
}

RobotDescription parse_document(const std::string& path, const std::string& text) {
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(fmt::format("{}:{}: malformed YAML: {}", path, e.mark.line + 1, e.msg));
  }
  const Reader r{path};
  r.only_keys(doc, "chain spec", {"name", "gravity", "base", "links", "loops"});

  RobotDescription robot;
  robot.name = doc["name"] ? r.text(doc["name"], "name") : "chain";
  if (doc["gravity"]) robot.gravity = r.vec3(doc["gravity"], "gravity");
  const std::string base = doc["base"] ? r.text(doc["base"], "base") : "base";
  LinkSpec base_link;
  base_link.name = base;
  robot.builder.add_link(base_link);

  const YAML::Node links = doc["links"];
  if (!links || !links.IsSequence() || links.size() == 0)
    r.fail(links ? links : doc, "links", "expected a non-empty list of links");

  std::string parent = base;
  double parent_length = 0;
  for (std::size_t k = 0; k < links.size(); ++k) {
    const YAML::Node link = links[k];
    const std::string at = fmt::format("links[{}]", k);
    r.only_keys(link, at, {"name", "joint", "length", "mass", "com", "inertia"});

    LinkSpec spec;
    spec.name = link["name"] ? r.text(link["name"], at + ".name") : fmt::format("link{}", k + 1);
    if (!link["mass"]) r.fail(link, at, "missing 'mass'");
    spec.mass = r.number(link["mass"], at + ".mass");
    if (link["com"]) spec.com = r.vec3(link["com"], at + ".com");
    if (const YAML::Node in = link["inertia"]) {
      r.only_keys(in, at + ".inertia", {"ixx", "iyy", "izz", "ixy", "ixz", "iyz"});
      auto get = [&](const char* key) {
        return in[key] ? r.number(in[key], at + ".inertia." + key) : 0.0;
      };
      spec.I_com = {get("ixx"), get("iyy"), get("izz"), get("ixy"), get("ixz"), get("iyz")};
    }

    JointSpec joint;
    joint.name = spec.name + "_joint";
    joint.kind = JointKind::Revolute;
    joint.parent = parent;
    joint.child = spec.name;
    joint.xyz = {parent_length, 0, 0};
    joint.axis = {0, 0, 1};
    if (const YAML::Node j = link["joint"]) {
      const std::string jat = at + ".joint";
      r.only_keys(j, jat, {"name", "type", "axis", "xyz", "rpy", "armature"});
      if (j["name"]) joint.name = r.text(j["name"], jat + ".name");
      if (j["type"]) {
        const std::string type = r.text(j["type"], jat + ".type");
        if (type == "revolute" || type == "continuous") joint.kind = JointKind::Revolute;
        else if (type == "prismatic") joint.kind = JointKind::Prismatic;
        else if (type == "fixed") joint.kind = JointKind::Fixed;
        else if (type == "ball") joint.kind = JointKind::Ball;
        else
          r.fail(j["type"], jat + ".type",
                 fmt::format("joint type '{}' is not supported (revolute, continuous, prismatic, "
                             "ball, fixed)",
                             type));
        if (joint.kind == JointKind::Ball && j["axis"])
          r.fail(j["axis"], jat + ".axis", "a ball joint turns about every axis: it takes none");
      }
      if (j["axis"]) joint.axis = r.vec3(j["axis"], jat + ".axis");
      if (j["armature"]) joint.armature = r.number(j["armature"], jat + ".armature");
      if (j["xyz"]) joint.xyz = r.vec3(j["xyz"], jat + ".xyz");
      if (j["rpy"]) {
        const Vec3<double> rpy = r.vec3(j["rpy"], jat + ".rpy");
        joint.R = rotation_from_rpy(rpy.x, rpy.y, rpy.z);
      }
    }
    try {
      robot.builder.add_link(spec);
      robot.builder.add_joint(joint);
    } catch (const ModelError& e) {
      r.fail(link, at, e.what());
    }
    parent = spec.name;
    parent_length = link["length"] ? r.number(link["length"], at + ".length") : 0.0;
  }
  if (const YAML::Node loops = doc["loops"]) parse_loops(r, loops, robot);
  return robot;
}

}  // namespace

RobotDescription parse_chain(const std::string& path, const std::string& text) {
  try {
    return parse_document(path, text);
  } catch (const YAML::Exception& e) {
    // what the checks above did not foresee is still bad input, with yaml-cpp's line
    throw InputError(e.mark.is_null() ? fmt::format("{}: {}", path, e.msg)
                                      : fmt::format("{}:{}: {}", path, e.mark.line + 1, e.msg));
  }
}

}  // namespace dyngen::gen
