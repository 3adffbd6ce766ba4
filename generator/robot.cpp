#include "robot.hpp"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <sstream>

#include "dyngen/aba.hpp"
#include "dyngen/constrained.hpp"
#include "dyngen/numerics/conditioning.hpp"
#include "readers.hpp"

namespace dyngen::gen {

namespace {

std::string sha256_of(const std::string& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr);
  std::string hex;
  for (unsigned int k = 0; k < size; ++k) hex += fmt::format("{:02x}", digest[k]);
  return hex;
}

/// Mass and inertia must be finite, the mass non-negative and the inertia positive
/// semidefinite; inertias that break the triangle inequality are only warned about, as
/// several real robots have them.
void check_inertia(const std::string& path, const LinkSpec& link,
                   std::vector<std::string>& warnings) {
  const std::string where = fmt::format("{}: link '{}' <inertial>", path, link.name);
  if (!std::isfinite(link.mass)) throw InputError(where + ": mass is not finite");
  if (link.mass < 0) throw InputError(fmt::format("{}: mass is negative ({})", where, link.mass));
  const Sym3<double>& I = link.I_com;
  for (const double x : {I.xx, I.yy, I.zz, I.xy, I.xz, I.yz})
    if (!std::isfinite(x)) throw InputError(where + ": an inertia entry is not finite");
  for (const double x : {link.com.x, link.com.y, link.com.z})
    if (!std::isfinite(x)) throw InputError(where + ": the centre of mass is not finite");
  Eigen::Matrix3d A;
  A << I.xx, I.xy, I.xz, I.xy, I.yy, I.yz, I.xz, I.yz, I.zz;
  const Eigen::Vector3d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(A).eigenvalues();
  const double scale = std::max(std::abs(lambda[0]), std::abs(lambda[2]));
  if (lambda[0] < -1e-12 * scale)
    throw InputError(fmt::format(
        "{}: the inertia tensor has a negative eigenvalue ({:.6g}; eigenvalues {:.6g}, {:.6g}, "
        "{:.6g}), so it is not a physical inertia",
        where, lambda[0], lambda[0], lambda[1], lambda[2]));
  if (lambda[0] + lambda[1] < lambda[2] * (1 - 1e-6))
    warnings.push_back(fmt::format(
        "{}: principal moments {:.6g}, {:.6g}, {:.6g} break the triangle inequality "
        "(I1 + I2 >= I3); used as given",
        where, lambda[0], lambda[1], lambda[2]));
}

}  // namespace

std::vector<int> joints_with_massless_subtree(const Model<double>& model) {
  std::vector<bool> has_mass(model.nbodies, false);
  for (int i = model.nbodies - 1; i >= 0; --i) {
    const RigidInertia<double>& I = model.I[i];
    if (I.m != 0 || I.I.xx != 0 || I.I.yy != 0 || I.I.zz != 0 || I.I.xy != 0 || I.I.xz != 0 ||
        I.I.yz != 0)
      has_mass[i] = true;
    if (has_mass[i] && model.parent[i] >= 0) has_mass[model.parent[i]] = true;
  }
  std::vector<int> joints;
  for (int i = 0; i < model.nbodies; ++i)
    if (!has_mass[i]) joints.push_back(i);
  return joints;
}

namespace {

/// Sample `sample` of joints_moving_no_mass: all zeros first, then angles from raw mt19937_64
/// bits (the same samples on every standard library); quaternions the identity, as any
/// rotation will do.
void sample_configuration(const Model<double>& model, std::mt19937_64& rng, int sample,
                          std::vector<double>& q) {
  for (double& x : q)
    x = sample == 0 ? 0.0 : -3.14159 + 6.28318 * static_cast<double>(rng() >> 11) * 0x1.0p-53;
  for (int i = 0; i < model.nbodies; ++i)
    if (const int o = quaternion_offset(model.joint_type[i]); o >= 0) {
      double* quaternion = &q[model.q_index[i] + o];
      quaternion[0] = 1, quaternion[1] = quaternion[2] = quaternion[3] = 0;
    }
}

/// joints_moving_no_mass of a robot with mimic joints, whose forward dynamics factorise M:
/// the joints whose column's pivot D of M = L^T D L is at most 1e-12 of M's diagonal entry.
std::vector<int> columns_moving_no_mass(const Model<double>& model) {
  Workspace<double> ws(model);
  std::mt19937_64 rng(20261121);
  std::vector<double> q(model.nq);
  std::vector<int> joints;
  for (int sample = 0; sample < 16; ++sample) {
    sample_configuration(model, rng, sample, q);
    const std::vector<double> pivots = numerics::factorised_pivots(model, ws, q);
    for (int i = 0; i < model.nbodies; ++i) {
      if (is_mimic(model, i) || std::count(joints.begin(), joints.end(), i)) continue;
      for (int d = 0; d < joint_nv(model.joint_type[i]); ++d)
        if (!std::isnan(pivots[model.v_index[i] + d]) && !(pivots[model.v_index[i] + d] > 1e-12)) {
          joints.push_back(i);
          break;
        }
    }
  }
  std::sort(joints.begin(), joints.end());
  return joints;
}

}  // namespace

std::vector<int> joints_moving_no_mass(const Model<double>& model) {
  if (!model.mimic.empty()) return columns_moving_no_mass(model);
  const int n = model.nv;
  Workspace<double> ws(model);
  std::mt19937_64 rng(20261121);
  std::vector<double> q(model.nq), v(n, 0.0), tau(n, 0.0), qdd(n);
  std::vector<bool> flagged(model.nbodies, false);
  for (int sample = 0; sample < 16; ++sample) {
    sample_configuration(model, rng, sample, q);
    aba<double>(model, ws, q, v, tau, qdd);
    // the composite inertias of CRBA (with ABA's joint transforms) give M's diagonal in O(nv),
    // where M itself takes O(nv^2) memory and up to O(nv^2) time
    for (int i = 0; i < model.nbodies; ++i) ws.Ic[i] = model.I[i];
    for (int i = model.nbodies - 1; i >= 0; --i)
      if (model.parent[i] >= 0)
        ws.Ic[model.parent[i]] = ws.Ic[model.parent[i]] + apply_inertia_T(ws.Xup[i], ws.Ic[i]);
    for (int i = 0; i < model.nbodies; ++i) {
      if (model.joint_type[i] == JointType::Free) {
        // ABA solves with the whole 6x6 articulated inertia: singular when the subtree can move
        // without moving the free body (a massless root above a prismatic joint, say)
        const double lambda = numerics::detail::smallest_eigenvalue(ws.IA[i]);
        if (!std::isnan(lambda) && !(lambda > 1e-12 * numerics::detail::max_abs(ws.IA[i])))
          flagged[i] = true;
        continue;
      }
      if (model.joint_type[i] == JointType::Ball) {
        // ABA inverts the 3x3 angular block: singular when the subtree can turn about some
        // axis through the joint without inertia
        const Sym3<double> D = detail::ball_D(model, ws.IA[i], model.v_index[i]);
        const double lambda = numerics::detail::smallest_eigenvalue(D);
        const double size = std::max({std::abs(D.xx), std::abs(D.yy), std::abs(D.zz)});
        if (!std::isnan(lambda) &&
            !(lambda > 1e-12 * size && lambda >= std::numeric_limits<double>::min()))
          flagged[i] = true;
        continue;
      }
      double Mii;
      joint_project(model, i, mul(ws.Ic[i], joint_column(model, i, 0)), &Mii);
      if (!model.armature.empty()) Mii = Mii + model.armature[model.v_index[i]];
      // a NaN D comes from a division by a vanishing D below, which is flagged itself; a D below
      // double's normal range is as good as zero (1 / D overflows)
      if (!std::isnan(ws.D[i]) &&
          !(ws.D[i] > 1e-12 * Mii && ws.D[i] >= std::numeric_limits<double>::min()))
        flagged[i] = true;
    }
  }
  std::vector<int> joints;
  for (int i = 0; i < model.nbodies; ++i)
    if (flagged[i]) joints.push_back(i);
  return joints;
}

namespace {

/// Mimic joints that still move, accepted as independent joints on request, say so.
void warn_independent_mimics(Robot& robot, const std::vector<RobotDescription::Mimic>& mimics) {
  std::string moving;
  const std::set<std::string> moving_joints(robot.model.joint_name.begin(),
                                            robot.model.joint_name.end());
  for (const RobotDescription::Mimic& m : mimics)
    if (moving_joints.count(m.joint))
      moving += fmt::format("{}'{}' (mimics '{}')", moving.empty() ? "" : ", ", m.joint,
                            m.mimicked);
  if (moving.empty()) return;
  robot.warnings.push_back(
      fmt::format("{}: mimic joints treated as independent joints: {}", robot.path, moving));
}

}  // namespace

std::vector<int> joints_blocking_aba(const Model<double>& model) {
  // a rotor inertia is ABA's pivot where the joint moves no mass
  std::vector<int> joints = joints_with_massless_subtree(model);
  std::erase_if(joints, [&](int i) {
    return !model.armature.empty() && model.armature[model.v_index[i]] > 0;
  });
  for (const int i : joints_moving_no_mass(model))
    if (std::find(joints.begin(), joints.end(), i) == joints.end()) joints.push_back(i);
  std::sort(joints.begin(), joints.end());
  return joints;
}

std::string joint_list(const Model<double>& model, const std::vector<int>& joints) {
  std::string names;
  for (const int i : joints) names += (names.empty() ? "'" : ", '") + model.joint_name[i] + "'";
  return names;
}

std::string aba_undefined_reason(const Model<double>& model) {
  std::vector<int> joints = joints_blocking_aba(model), free;
  std::erase_if(joints, [&](int i) {
    if (model.joint_type[i] != JointType::Free) return false;
    free.push_back(i);
    return true;
  });
  std::vector<std::string> why, remedies;
  if (!joints.empty()) {
    std::string locks;
    for (const int i : joints) locks += " --lock " + model.joint_name[i];
    why.push_back(fmt::format(
        "{} joint{} move{} no mass (the articulated inertia about the joint axis is zero, so ABA "
        "would divide by zero): {}",
        joints.size(), joints.size() == 1 ? "" : "s", joints.size() == 1 ? "s" : "",
        joint_list(model, joints)));
    remedies.push_back(fmt::format("lock them ({})", locks.substr(1)));
    remedies.push_back("lock every joint with a massless subtree (--lock-massless)");
  }
  for (const int i : free) {
    const bool base = model.parent[i] < 0 && model.joint_name[i] == "floating_base";
    why.push_back(fmt::format(
        "the 6x6 articulated inertia of free joint '{}' is singular: its subtree can move without "
        "moving body '{}'{}, so ABA would divide by zero",
        model.joint_name[i], model.body_name[i], model.I[i].m == 0 ? ", which has no mass" : ""));
    remedies.push_back(fmt::format("give link '{}' a mass and inertia", model.body_name[i]));
    remedies.push_back(base ? "fix the base (leave out --floating-base)"
                            : fmt::format("lock the joint (--lock {})", model.joint_name[i]));
  }
  if (why.empty()) return "";
  std::string text = "ABA is undefined for this robot: " + why[0];
  for (std::size_t k = 1; k < why.size(); ++k) text += "; " + why[k];
  remedies[0][0] = static_cast<char>(std::toupper(static_cast<unsigned char>(remedies[0][0])));
  text += ".\n" + remedies[0];
  for (std::size_t k = 1; k < remedies.size(); ++k) text += ", " + remedies[k];
  return text;
}

std::vector<int> joints_blocking_aba_in_float(const Model<double>& model) {
  return joints_blocking_aba(model.cast<float>().cast<double>());
}

std::string read_file(const std::string& path) {
  if (path.empty()) throw InputError("no file given: the path is empty");
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (status.type() == std::filesystem::file_type::not_found)
    throw InputError(fmt::format("{}: no such file", path));
  if (error) throw InputError(fmt::format("{}: cannot read the file: {}", path, error.message()));
  if (!std::filesystem::is_regular_file(status))
    throw InputError(fmt::format("{}: not a regular file", path));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: cannot read the file: {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad())
    throw InputError(fmt::format("{}: cannot read the file: {}", path, std::strerror(errno)));
  return text.str();
}

namespace {

/// The frame of the link named (--frames, --contacts, a chain spec's loop); `where` starts the
/// error that lists the links when there is none.
const Frame<double>& link_frame(const Model<double>& model, const std::string& name,
                                const std::string& where) {
  const auto it = std::find_if(model.frames.begin(), model.frames.end(),
                               [&](const Frame<double>& f) { return f.name == name; });
  if (it == model.frames.end()) {
    std::string links;
    for (std::size_t k = 0; k < model.frames.size() && k < 40; ++k)
      links += (k ? ", '" : "'") + model.frames[k].name + "'";
    if (model.frames.size() > 40) links += fmt::format(" and {} more", model.frames.size() - 40);
    throw InputError(fmt::format("{}: no link named '{}'; the links are {}", where, name, links));
  }
  return *it;
}

/// Keeps the frames of the links named (in that order), or without names those of
/// default_frames_rule, in the model's order: the leaf links on a body without moving children.
void select_frames(Model<double>& model, const ModelBuilder& builder,
                   const std::vector<std::string>& names, const std::string& path) {
  std::vector<Frame<double>> kept;
  if (names.empty()) {
    std::set<std::string> parents;
    for (const JointSpec& joint : builder.joints()) parents.insert(joint.parent);
    std::vector<bool> end_of_limb(model.nbodies, true);
    for (int i = 0; i < model.nbodies; ++i)
      if (model.parent[i] >= 0) end_of_limb[model.parent[i]] = false;
    for (const Frame<double>& f : model.frames)
      if (f.body >= 0 && end_of_limb[f.body] && !parents.count(f.name)) kept.push_back(f);
  }
  for (const std::string& name : names) {
    const Frame<double>& f = link_frame(model, name, path + ": --frames");
    if (std::none_of(kept.begin(), kept.end(),
                     [&](const Frame<double>& k) { return k.name == name; }))
      kept.push_back(f);
  }
  model.frames = kept;
}

/// The frame moved to the point at xyz in its own axes: X = xlt(xyz) X_frame.
Frame<double> at_point(Frame<double> f, const Vec3<double>& xyz) {
  f.placement.r = f.placement.r + mul_T(f.placement.E, xyz);
  return f;
}

/// "FOOT", "FOOT:3d" or "FOOT:6d" (--contacts): the link and whether it is a surface contact.
std::pair<std::string, bool> parse_contact(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon != std::string::npos) {
    const std::string kind = text.substr(colon + 1);
    if (kind == "3d" || kind == "6d") return {text.substr(0, colon), kind == "6d"};
  }
  return {text, false};
}

/// The model's constraints: the contacts of --contacts (a link held to the world) and the file's
/// loop closures, from the frames of every link (before --frames chooses some).
void add_constraints(Model<double>& model, const std::vector<RobotDescription::Loop>& loops,
                     const LoadOptions& options, const std::string& path) {
  std::vector<Constraint<double>> constraints;
  for (const std::string& text : options.contacts) {
    const auto [link, six_d] = parse_contact(text);
    const Frame<double>& f = link_frame(model, link, fmt::format("--contacts {}", text));
    if (f.body < 0)
      throw InputError(
          fmt::format("--contacts {}: link '{}' is welded to the fixed base, so a "
                      "contact there constrains nothing",
                      text, link));
    for (const Constraint<double>& c : constraints)
      if (c.name.substr(0, c.name.rfind(':')) == link)
        throw InputError(fmt::format("--contacts: link '{}' is given twice", link));
    constraints.push_back({link + (six_d ? ":6d" : ":3d"), f.body, f.placement, -1,
                           Xform<double>{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {}}, six_d, false});
  }
  for (const RobotDescription::Loop& loop : loops) {
    const std::string where = fmt::format("{}: loop {}-{}", path, loop.link_a, loop.link_b);
    const Frame<double> a = at_point(link_frame(model, loop.link_a, where), loop.xyz_a);
    const Frame<double> b = at_point(link_frame(model, loop.link_b, where), loop.xyz_b);
    if (a.body == b.body)
      throw InputError(where +
                       ": both links are on one rigid body, so the loop constrains nothing");
    constraints.push_back(
        {fmt::format("{}-{}:{}", loop.link_a, loop.link_b, loop.six_d ? "6d" : "3d"), a.body,
         a.placement, b.body, b.placement, loop.six_d, true});
  }
  if (!constraints.empty() && model.nv > Workspace<double>::max_matrix_nv)
    throw InputError(
        fmt::format("{}: constraints need M factorised, which dyngen does for at most "
                    "{} degrees of freedom; the robot has {}",
                    path, Workspace<double>::max_matrix_nv, model.nv));
  set_constraints(model, std::move(constraints), options.constraint_settings);
}

}  // namespace

std::vector<std::string> redundant_constraints(const Model<double>& model) {
  if (model.nc == 0) return {};
  Workspace<double> ws(model);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<double> q(static_cast<std::size_t>(model.nq));
  std::set<std::string> names;
  for (int sample = 0; sample < 3; ++sample) {
    for (double& x : q) x = uniform(random);
    normalize_configuration<double>(model, q);
    detail::body_placements<double>(model, ws, q);
    detail::constraint_jacobians(model, ws, false);
    const Eigen::MatrixXd J =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            ws.Jc.data(), model.nc, model.nv);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullU);
    const Eigen::VectorXd& s = svd.singularValues();
    const double tol = 1e-9 * (s.size() > 0 ? s[0] : 0.0);
    int rank = 0;
    while (rank < s.size() && s[rank] > tol) ++rank;
    // a combination w of the rows with w^T J = 0: the constraints with a part in it
    for (int k = rank; k < model.nc; ++k) {
      int row = 0;
      for (const Constraint<double>& c : model.constraints) {
        for (int r = 0; r < constraint_rows(c); ++r)
          if (std::abs(svd.matrixU()(row + r, k)) > 1e-6) names.insert(c.name);
        row += constraint_rows(c);
      }
    }
  }
  std::vector<std::string> out;
  for (const Constraint<double>& c : model.constraints)
    if (names.count(c.name)) out.push_back(c.name);
  return out;
}

Robot load_robot(const std::string& path, const LoadOptions& options) {
  return parse_robot(path, read_file(path), options);
}

Robot parse_robot(const std::string& path, const std::string& text, const LoadOptions& options) {
  const Reader& reader = reader_for(path, text);
  RobotDescription description = reader.parse(path, text);

  const std::size_t joints = description.builder.joints().size();
  const std::size_t links = description.builder.links().size();
  if (joints > max_joints)
    throw InputError(fmt::format("{}: the robot has {} joints; dyngen reads at most {}", path,
                                 joints, max_joints));
  if (links > max_joints + 1)
    throw InputError(fmt::format("{}: the robot has {} links; dyngen reads at most {} (a tree of "
                                 "{} joints)",
                                 path, links, max_joints + 1, max_joints));
  if (options.floating_base && description.root_is_world)
    throw InputError(fmt::format(
        "{}: --floating-base puts the root link on a free joint, and this file's root is the "
        "world: give the floating body a free joint in the file (<freejoint/>) instead",
        path));
  if (options.gravity) {
    try {
      check_gravity(*options.gravity);
    } catch (const ModelError& e) {
      throw InputError(fmt::format("--gravity: {}", e.what()));
    }
  }

  Robot robot;
  robot.path = path;
  robot.format = reader.format;
  robot.name = description.name;
  robot.sha256 = sha256_of(text);
  robot.warnings = description.warnings;
  robot.pinocchio_order = description.pinocchio_order;
  robot.pinocchio_missing = description.pinocchio_missing;
  for (const LinkSpec& link : description.builder.links())
    check_inertia(path, link, robot.warnings);

  const Vec3<double> gravity = options.gravity ? *options.gravity
                               : description.gravity ? *description.gravity
                                                     : default_gravity;
  ModelBuilder& builder = description.builder;
  try {
    if (!options.mimic_independent)
      for (const RobotDescription::Mimic& m : description.mimics)
        builder.set_mimic(m.joint, m.mimicked, m.multiplier, m.offset);
    for (const auto& [joint, value] : options.armature) {
      if (joint != "all") {
        builder.set_armature(joint, value);
        continue;
      }
      for (const JointSpec& j : builder.joints())
        if (j.kind != JointKind::Fixed && j.kind != JointKind::Floating && j.mimic.empty())
          builder.set_armature(j.name, value);
    }
    for (const std::string& joint : options.lock) {
      builder.lock(joint);
      robot.locked.push_back(joint);
    }
    robot.model = builder.build(gravity, options.floating_base);
    if (options.lock_massless) {
      std::vector<int> massless = joints_with_massless_subtree(robot.model);
      // a floating base with no mass is an error for ABA, not a joint to lock
      std::erase_if(massless, [&](int i) { return robot.model.joint_type[i] == JointType::Free; });
      for (const int i : massless) {
        builder.lock(robot.model.joint_name[i]);
        robot.locked.push_back(robot.model.joint_name[i]);
      }
      if (!massless.empty()) robot.model = builder.build(gravity, options.floating_base);
    }
  } catch (const ModelError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
  if (robot.model.nbodies == 0)
    throw InputError(fmt::format("{}: the robot has no moving joint", path));
  if (robot.model.nv > max_nv)
    throw InputError(fmt::format(
        "{}: the robot has {} degrees of freedom; dyngen handles at most {}", path,
        robot.model.nv, max_nv));
  if (options.mimic_independent) warn_independent_mimics(robot, description.mimics);
  if (options.snap) robot.snapped = snap(robot.model, *options.snap);
  add_constraints(robot.model, description.loops, options, path);
  if (const std::vector<std::string> r = redundant_constraints(robot.model); !r.empty())
    robot.warnings.push_back(fmt::format(
        "{}: the rows of the constraints {} are not independent ({} rows in all): "
        "contact_dynamics and impulse_dynamics return the minimum-norm lambda, from a "
        "proximal solve damped by {:g} of the operational-space inertia's mean diagonal; a "
        "state whose velocities break the constraints makes lambda grow as 1 / damping",
        path, fmt::join(r, ", "), robot.model.nc, robot.model.constraint_settings.damping));
  if (!options.all_frames) select_frames(robot.model, builder, options.frames, path);
  return robot;
}

}  // namespace dyngen::gen
