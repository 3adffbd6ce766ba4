// Random chains, random states and the shared robot files (see test_support.hpp).
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "dyngen/model_builder.hpp"

namespace dyngen::test {

namespace {

constexpr double pi = std::numbers::pi;

/// Rotational inertia about the centre of mass of a solid box with half-sizes s, in its
/// principal frame: I_xx = m (s_y^2 + s_z^2) / 3 and so on, so it is positive definite and
/// meets the triangle inequality (I_xx + I_yy - I_zz = 2 m s_z^2 / 3 >= 0).
Sym3<double> box_inertia(double m, const Vec3<double>& s) {
  const double x2 = s.x * s.x, y2 = s.y * s.y, z2 = s.z * s.z;
  return {m * (y2 + z2) / 3, m * (x2 + z2) / 3, m * (x2 + y2) / 3, 0, 0, 0};
}

Vec3<double> random_vec(Random& rng, double lo, double hi) {
  return {rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi)};
}

/// Exactly +-x, +-y or +-z half of the time, else a general direction (not normalised: the
/// builder normalises it).
Vec3<double> random_axis(Random& rng) {
  if (rng.chance(0.5)) {
    const double sign = rng.chance(0.5) ? 1.0 : -1.0;
    switch (rng.index(3)) {
      case 0: return {sign, 0, 0};
      case 1: return {0, sign, 0};
      default: return {0, 0, sign};
    }
  }
  for (;;) {
    const Vec3<double> a = random_vec(rng, -1, 1);
    // away from the axes and from zero, so the direction is general
    if (dot(a, a) > 0.25 && std::min({std::abs(a.x), std::abs(a.y), std::abs(a.z)}) > 0.05)
      return a;
  }
}

}  // namespace

Model<double> make_random_chain(int n, std::uint64_t seed, bool planar) {
  Random rng(seed);
  ModelBuilder builder;
  LinkSpec base;
  base.name = "base";
  builder.add_link(base);
  std::string parent = base.name;
  double parent_length = 0;
  for (int k = 1; k <= n; ++k) {
    LinkSpec link;
    link.name = "link" + std::to_string(k);
    link.mass = rng.uniform(0.2, 3.0);
    JointSpec joint;
    joint.name = "joint" + std::to_string(k);
    joint.parent = parent;
    joint.child = link.name;
    if (planar) {
      const double length = rng.uniform(0.3, 1.0);
      double fraction = rng.uniform(0.15, 0.40);
      if (rng.chance(0.5)) fraction = 1 - fraction;
      link.com = {fraction * length, rng.uniform(-0.05, 0.05), 0};
      link.R = rotation_from_rpy(0, 0, rng.uniform(-pi, pi));
      link.I_com =
          box_inertia(link.mass, {length / 2, rng.uniform(0.02, 0.1), rng.uniform(0.02, 0.1)});
      joint.xyz = {parent_length, 0, 0};
      if (rng.chance(0.25)) {
        joint.kind = JointKind::Prismatic;
        const double angle = rng.uniform(-pi, pi);
        joint.axis = {std::cos(angle), std::sin(angle), 0};
      } else {
        joint.kind = JointKind::Revolute;
        joint.axis = {0, 0, rng.chance(0.5) ? 1.0 : -1.0};
      }
      parent_length = length;
    } else {
      link.com = random_vec(rng, -0.3, 0.3);
      link.R = rotation_from_rpy(rng.uniform(-pi, pi), rng.uniform(-pi, pi), rng.uniform(-pi, pi));
      link.I_com = box_inertia(link.mass, random_vec(rng, 0.02, 0.4));
      joint.xyz = random_vec(rng, -0.4, 0.4);
      joint.R = rotation_from_rpy(rng.uniform(-pi, pi), rng.uniform(-pi, pi), rng.uniform(-pi, pi));
      joint.kind = rng.chance(0.2) ? JointKind::Prismatic : JointKind::Revolute;
      joint.axis = random_axis(rng);
    }
    builder.add_link(link);
    builder.add_joint(joint);
    parent = link.name;
  }
  return builder.build(planar ? Vec3<double>{0, -9.81, 0} : Vec3<double>{0, 0, -9.81});
}

std::string model_path(const std::string& file) {
  return (std::filesystem::path(DYNGEN_TEST_MODELS) / file).string();
}

std::vector<RobotFile> robot_files() {
  std::vector<RobotFile> robots;
  for (const auto& entry : std::filesystem::directory_iterator(DYNGEN_TEST_MODELS)) {
    if (entry.path().extension() != ".urdf") continue;
    RobotFile robot{entry.path().stem().string(), entry.path().string(), {}, {}};
    robot.options.mimic_independent = true;
    robot.aba_options = robot.options;
    robot.aba_options.lock_massless = robot.name == "romeo";
    robots.push_back(robot);
  }
  std::sort(robots.begin(), robots.end(),
            [](const RobotFile& a, const RobotFile& b) { return a.name < b.name; });
  return robots;
}

std::string case_name(const std::string& file, bool floating_base) {
  const std::string base = file.substr(file.rfind('/') + 1);  // npos + 1 = 0
  return base.substr(0, base.find('.')) + (floating_base ? "_floating" : "");
}

Model<double> load_model(const std::string& file, bool floating_base, bool all_frames) {
  gen::LoadOptions options;
  options.floating_base = floating_base;
  options.all_frames = all_frames;
  return gen::load_robot(model_path(file), options).model;
}

Model<double> load_for_aba(const RobotFile& robot, bool floating_base) {
  gen::LoadOptions options = robot.aba_options;
  options.floating_base = floating_base;
  return gen::load_robot(robot.path, options).model;
}

}  // namespace dyngen::test
