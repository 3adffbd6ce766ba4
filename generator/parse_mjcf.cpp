// MJCF, MuJoCo's format, read by MuJoCo's own compiler (libmujoco): it resolves <default>
// classes, <include>s, angle units and Euler sequences, every orientation form and the inertia
// of bodies from their geoms, by MuJoCo's rules. dyngen then builds its model from the compiled
// bodies and joints. Elements that do not change the rigid-body dynamics are dropped first
// (MuJoCo 2.2 does not know some of MuJoCo 3's attributes there), with one warning.
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <memory>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include "output.hpp"
#include "readers.hpp"

namespace dyngen::gen {

namespace fs = std::filesystem;

namespace {

/// Top-level elements with no part in the rigid-body dynamics: dropped, with one warning.
constexpr const char* ignored_elements[] = {"option",   "size",    "visual",  "statistic",
                                            "actuator", "sensor",  "tendon",  "contact",
                                            "keyframe", "custom",  "extension"};

/// Elements that would change the dynamics in ways dyngen does not model.
constexpr const char* refused_elements[] = {"frame", "attach", "replicate", "composite",
                                            "flexcomp", "flex"};

Vec3<double> vector3(const std::string& path, const tinyxml2::XMLElement* e, const char* name) {
  double x[3];
  const char* text = e->Attribute(name);
  if (!text || std::sscanf(text, "%lf %lf %lf", &x[0], &x[1], &x[2]) != 3)
    throw InputError(fmt::format("{}:{}: <{}> {}=\"{}\": expected three numbers", path,
                                 e->GetLineNum(), e->Name(), name, text ? text : ""));
  return {x[0], x[1], x[2]};
}

/// Gravity from <option gravity> and <option><flag gravity="disable"/>, MuJoCo's default
/// otherwise.
Vec3<double> option_gravity(const std::string& path, const tinyxml2::XMLElement* root) {
  Vec3<double> g{0, 0, -9.81};
  for (const tinyxml2::XMLElement* option = root->FirstChildElement("option"); option;
       option = option->NextSiblingElement("option")) {
    if (option->Attribute("gravity")) g = vector3(path, option, "gravity");
    const tinyxml2::XMLElement* flag = option->FirstChildElement("flag");
    if (flag && flag->Attribute("gravity", "disable")) g = {0, 0, 0};
  }
  return g;
}

/// Refuses what dyngen does not model anywhere under e.
void refuse_unmodelled(const std::string& path, const tinyxml2::XMLElement* e) {
  for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    for (const char* name : refused_elements)
      if (std::string_view(c->Name()) == name)
        throw InputError(fmt::format("{}:{}: <{}> is not supported: dyngen reads bodies, hinge, "
                                     "slide and root free joints, inertials, geoms and sites",
                                     path, c->GetLineNum(), name));
    if (std::string_view(c->Name()) == "equality" && c->FirstChildElement())
      throw InputError(fmt::format(
          "{}:{}: <equality> constraints are not supported: they couple the joints, which "
          "dyngen's tree algorithms do not model",
          path, c->GetLineNum()));
    refuse_unmodelled(path, c);
  }
}

/// What dyngen takes from the document itself.
struct Document {
  std::string text;                  // without the ignored elements
  std::vector<std::string> dropped;  // their names
  Vec3<double> gravity;
  std::string model;                 // <mujoco model>
  std::vector<std::string> meshes;   // "body 'a' (mesh 'shell')": bodies with mesh geoms
};

/// Drops the mesh geoms of the bodies under e that have an <inertial>: their inertia is given,
/// so their meshes (visual or collision shapes, whose files may not be at hand) play no part.
/// Adds the meshes still used to `used`.
void drop_mesh_geoms(tinyxml2::XMLElement* e, std::set<std::string>& used) {
  const bool given = e->FirstChildElement("inertial") != nullptr;
  for (tinyxml2::XMLElement* c = e->FirstChildElement(); c;) {
    tinyxml2::XMLElement* next = c->NextSiblingElement();
    const std::string_view name = c->Name();
    if (name == "geom" && c->Attribute("mesh")) {
      if (given) e->DeleteChild(c);
      else used.insert(c->Attribute("mesh"));
    } else if (name == "body") {
      drop_mesh_geoms(c, used);
    }
    c = next;
  }
}

/// Drops the <mesh> assets that no geom uses any more (a mesh is named by its file's stem when
/// it has no name).
void drop_unused_meshes(tinyxml2::XMLElement* root, const std::set<std::string>& used) {
  for (tinyxml2::XMLElement* asset = root->FirstChildElement("asset"); asset;
       asset = asset->NextSiblingElement("asset"))
    for (tinyxml2::XMLElement* mesh = asset->FirstChildElement("mesh"); mesh;) {
      tinyxml2::XMLElement* next = mesh->NextSiblingElement("mesh");
      const char* file = mesh->Attribute("file");
      const std::string name = mesh->Attribute("name") ? mesh->Attribute("name")
                               : file ? fs::path(file).stem().string()
                                      : "";
      if (!used.count(name)) asset->DeleteChild(mesh);
      mesh = next;
    }
}

/// The bodies under e with a mesh geom, in words.
void mesh_bodies(const tinyxml2::XMLElement* e, const char* body, std::vector<std::string>& out) {
  for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string_view name = c->Name();
    if (name == "geom" && c->Attribute("mesh"))
      out.push_back(fmt::format("body '{}' (mesh '{}')", body ? body : "world",
                                c->Attribute("mesh")));
    if (name == "body") mesh_bodies(c, c->Attribute("name") ? c->Attribute("name") : "", out);
  }
}

Document dynamics_only(const std::string& path, const std::string& text) {
  tinyxml2::XMLDocument doc;
  parse_xml(path, text, doc);
  tinyxml2::XMLElement* root = doc.RootElement();
  refuse_unmodelled(path, root);
  Document out;
  out.gravity = option_gravity(path, root);
  if (const char* model = root->Attribute("model")) out.model = model;
  const tinyxml2::XMLElement* compiler = root->FirstChildElement("compiler");
  if (!(compiler && compiler->Attribute("inertiafromgeom", "true"))) {
    std::set<std::string> used;
    for (tinyxml2::XMLElement* world = root->FirstChildElement("worldbody"); world;
         world = world->NextSiblingElement("worldbody"))
      drop_mesh_geoms(world, used);
    drop_unused_meshes(root, used);
  }
  for (const tinyxml2::XMLElement* world = root->FirstChildElement("worldbody"); world;
       world = world->NextSiblingElement("worldbody"))
    mesh_bodies(world, nullptr, out.meshes);
  std::set<std::string> names;
  for (tinyxml2::XMLElement* c = root->FirstChildElement(); c;) {
    tinyxml2::XMLElement* next = c->NextSiblingElement();
    for (const char* name : ignored_elements)
      if (std::string_view(c->Name()) == name) {
        names.insert(name);
        root->DeleteChild(c);
        break;
      }
    c = next;
  }
  out.dropped.assign(names.begin(), names.end());
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  out.text = printer.CStr();
  return out;
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using MjModel = std::unique_ptr<mjModel, ModelDeleter>;

/// The document compiled by MuJoCo, from a file beside the original, so that its <include>s and
/// mesh files are found where it names them.
/// MuJoCo's error on one line, without its line numbers (of the file without the ignored
/// elements, not the user's).
std::string compiler_error(const char* error) {
  static const std::regex position(R"(, line = -?[0-9]+, column = -?[0-9]+)");
  std::string text = std::regex_replace(error, position, "");
  for (char& c : text)
    if (c == '\n') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

MjModel compile(const std::string& path, const Document& doc) {
  const std::string& text = doc.text;
  const fs::path original(path);
  const fs::path scratch = original.parent_path() /
                           fmt::format(".{}.dyngen-{}.xml", original.stem().string(), getpid());
  try {
    write_file(scratch, text);
  } catch (const FileError& e) {
    throw FileError(fmt::format("{}: dyngen compiles an MJCF file through a copy beside it (so "
                                "that its includes and meshes are found), and cannot write one: {}",
                                path, e.what()));
  }
  std::array<char, 1000> error{};
  MjModel m(mj_loadXML(scratch.string().c_str(), nullptr, error.data(),
                       static_cast<int>(error.size())));
  std::error_code ignored;
  fs::remove(scratch, ignored);
  if (!m && !doc.meshes.empty() && std::string_view(error.data()).find(" file ") != std::string_view::npos)
    throw InputError(fmt::format(
        "{}: MuJoCo's compiler: {}; the inertia of {} comes from its mesh (no <inertial>): give "
        "dyngen the mesh files where the model names them, or the bodies <inertial>s",
        path, compiler_error(error.data()), fmt::join(doc.meshes, ", ")));
  if (!m)
    throw InputError(fmt::format("{}: MuJoCo's compiler: {}", path, compiler_error(error.data())));
  return m;
}

Mat3<double> rotation(const mjtNum* wxyz) {
  return rotation_from_quaternion(wxyz[1], wxyz[2], wxyz[3], wxyz[0]);
}

/// R about unit axis k by angle: Rodrigues.
Mat3<double> axis_rotation(const Vec3<double>& k, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  return {t * k.x * k.x + c,       t * k.x * k.y - s * k.z, t * k.x * k.z + s * k.y,
          t * k.x * k.y + s * k.z, t * k.y * k.y + c,       t * k.y * k.z - s * k.x,
          t * k.x * k.z - s * k.y, t * k.y * k.z + s * k.x, t * k.z * k.z + c};
}

/// A link with no mass: a joint's, or a site's.
LinkSpec massless(const std::string& name) {
  LinkSpec link;
  link.name = name;
  return link;
}

/// A fixed joint placing child in parent.
JointSpec fixed_joint(const std::string& name, const std::string& parent, const std::string& child,
                      const Vec3<double>& xyz, const Mat3<double>& R) {
  JointSpec joint;
  joint.name = name;
  joint.parent = parent;
  joint.child = child;
  joint.xyz = xyz;
  joint.R = R;
  return joint;
}

std::string name_of(const mjModel* m, int type, int id, const char* kind) {
  const char* name = mj_id2name(m, type, id);
  return name && *name ? std::string(name) : fmt::format("{}{}", kind, id);
}

/// Body b's joints, in document order, as a chain of joints from the parent link to the body's
/// link: joint k on a massless link at its anchor, the body's link on a fixed joint at the last
/// anchor's offset. A joint's ref (qpos0) is built into its origin, so that q is MuJoCo's qpos.
void add_joints(const std::string& path, const mjModel* m, int b, const std::string& parent,
                const std::string& body, ModelBuilder& builder) {
  const Vec3<double> pos{m->body_pos[3 * b], m->body_pos[3 * b + 1], m->body_pos[3 * b + 2]};
  const Mat3<double> R = rotation(m->body_quat + 4 * b);
  std::string link = parent;
  Vec3<double> anchor{0, 0, 0};
  for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
    const std::string joint = name_of(m, mjOBJ_JOINT, j, "joint");
    JointSpec spec;
    spec.name = joint;
    spec.parent = link;
    spec.child = m->body_jntnum[b] == 1 ? body + ":joint" : body + ":" + joint;
    if (m->jnt_type[j] == mjJNT_FREE) {
      if (m->body_parentid[b] != 0 || m->body_jntnum[b] != 1)
        throw InputError(fmt::format("{}: body '{}': a free joint is supported only as the one "
                                     "joint of a body of the world",
                                     path, body));
      spec.kind = JointKind::Floating;  // at the world's origin: q is the body's pose, as qpos
      builder.add_link(massless(spec.child));
      builder.add_joint(spec);
      link = spec.child;
      continue;
    }
    const bool ball = m->jnt_type[j] == mjJNT_BALL;
    const Vec3<double> p{m->jnt_pos[3 * j], m->jnt_pos[3 * j + 1], m->jnt_pos[3 * j + 2]};
    const Vec3<double> k{m->jnt_axis[3 * j], m->jnt_axis[3 * j + 1], m->jnt_axis[3 * j + 2]};
    const bool first = j == m->body_jntadr[b];
    spec.kind = ball                            ? JointKind::Ball
                : m->jnt_type[j] == mjJNT_HINGE ? JointKind::Revolute
                                                : JointKind::Prismatic;
    spec.axis = k;
    spec.xyz = first ? pos + mul(R, p) : p - anchor;
    spec.R = first ? R : Mat3<double>{1, 0, 0, 0, 1, 0, 0, 0, 1};
    // a ball's reference is the identity quaternion, a hinge's or slide's ref is baked in
    const double ref = ball ? 0 : m->qpos0[m->jnt_qposadr[j]];
    if (spec.kind == JointKind::Revolute) spec.R = mul(spec.R, axis_rotation(k, -ref));
    if (spec.kind == JointKind::Prismatic) spec.xyz = spec.xyz - mul(spec.R, scale(k, ref));
    spec.armature = m->dof_armature[m->jnt_dofadr[j]];
    builder.add_link(massless(spec.child));
    builder.add_joint(spec);
    link = spec.child;
    anchor = p;
  }
  const Mat3<double> identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (link == parent)  // no joint: welded to its parent
    builder.add_joint(fixed_joint(body + ":body", link, body, pos, R));
  else  // at the last joint's anchor (a free joint's is the body's origin)
    builder.add_joint(fixed_joint(body + ":body", link, body, scale(anchor, -1.0), identity));
}

/// The joint properties MuJoCo turns into passive or constraint forces, which are not part of
/// the rigid-body dynamics: "damping, limits", or "".
std::string passive_properties(const mjModel* m) {
  bool damping = false, stiffness = false, friction = false, limits = false;
  for (int j = 0; j < m->njnt; ++j) {
    stiffness = stiffness || m->jnt_stiffness[j] != 0;
    limits = limits || m->jnt_limited[j];
  }
  for (int k = 0; k < m->nv; ++k) {
    damping = damping || m->dof_damping[k] != 0;
    friction = friction || m->dof_frictionloss[k] != 0;
  }
  std::vector<std::string> found;
  if (damping) found.emplace_back("damping");
  if (stiffness) found.emplace_back("stiffness");
  if (friction) found.emplace_back("friction loss");
  if (limits) found.emplace_back("limits");
  return fmt::format("{}", fmt::join(found, ", "));
}

}  // namespace

RobotDescription parse_mjcf(const std::string& path, const std::string& text) {
  RobotDescription robot;
  const Document doc = dynamics_only(path, text);
  const MjModel compiled = compile(path, doc);
  const mjModel* m = compiled.get();
  if (m->neq > 0)  // from an <include>d file: the document's own are refused above
    throw InputError(fmt::format(
        "{}: {} <equality> constraints (in an included file) are not supported: they couple the "
        "joints, which dyngen's tree algorithms do not model",
        path, m->neq));
  if (!doc.dropped.empty())
    robot.warnings.push_back(fmt::format("{}: <{}> not used by dyngen (no part in the rigid-body "
                                         "dynamics) and ignored",
                                         path, fmt::join(doc.dropped, ">, <")));
  if (const std::string passive = passive_properties(m); !passive.empty())
    robot.warnings.push_back(fmt::format(
        "{}: the joints' {} (MuJoCo's passive and constraint forces) are not part of the "
        "rigid-body dynamics that dyngen computes, and are ignored",
        path, passive));
  robot.gravity = doc.gravity;
  robot.root_is_world = true;
  robot.name = doc.model.empty() ? fs::path(path).stem().string() : doc.model;
  std::vector<std::string> body(m->nbody);
  body[0] = "world";
  robot.builder.add_link(massless(body[0]));
  try {
    for (int b = 1; b < m->nbody; ++b) {
      body[b] = name_of(m, mjOBJ_BODY, b, "body");
      LinkSpec link = massless(body[b]);
      link.mass = m->body_mass[b];
      link.com = {m->body_ipos[3 * b], m->body_ipos[3 * b + 1], m->body_ipos[3 * b + 2]};
      link.R = rotation(m->body_iquat + 4 * b);
      link.I_com = {m->body_inertia[3 * b], m->body_inertia[3 * b + 1],
                    m->body_inertia[3 * b + 2], 0, 0, 0};
      robot.builder.add_link(link);
      add_joints(path, m, b, body[m->body_parentid[b]], body[b], robot.builder);
    }
    for (int s = 0; s < m->nsite; ++s) {
      const std::string site = name_of(m, mjOBJ_SITE, s, "site");
      robot.builder.add_link(massless(site));
      robot.builder.add_joint(fixed_joint(
          site + ":site", body[m->site_bodyid[s]], site,
          {m->site_pos[3 * s], m->site_pos[3 * s + 1], m->site_pos[3 * s + 2]},
          rotation(m->site_quat + 4 * s)));
    }
  } catch (const ModelError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
  return robot;
}

}  // namespace dyngen::gen
