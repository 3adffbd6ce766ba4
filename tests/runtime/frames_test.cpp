// Frames: the builder keeps every URDF link as a frame (those on fixed joints where they sit on
// the body they merged into); each frame's Jacobian is the derivative of its placement, checked
// against central differences of frame_placements along every direction of v (a free joint's
// by dyngen::integrate), and its bias acceleration the derivative of J v along the motion, in
// the base's axes and the frame's own.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "pattern.hpp"
#include "test_support.hpp"

namespace {

using namespace dyngen;

/// The names of a model's frames, in its order.
std::vector<std::string> frame_names(const Model<double>& model) {
  std::vector<std::string> names;
  for (const Frame<double>& f : model.frames) names.push_back(f.name);
  return names;
}

// By default the model keeps the frames at the ends of the limbs (--frames names others, in its
// order)
TEST(Frames, EndsOfTheLimbsByDefaultOrThoseNamed) {
  const std::string path = test::model_path("ur5.urdf");
  // ur5.urdf's links that no joint hangs from are the flange (ee_link), ROS's tool0, and base,
  // which is on the fixed base, not at the end of the arm
  EXPECT_EQ(frame_names(gen::load_robot(path).model),
            (std::vector<std::string>{"ee_link", "tool0"}));
  std::vector<std::string> names;
  gen::LoadOptions options;
  options.frames = {"wrist_1_link", "base_link", "wrist_1_link"};
  names.clear();
  for (const Frame<double>& f : gen::load_robot(path, options).model.frames)
    names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"wrist_1_link", "base_link"}));
  options.frames = {"tool"};
  try {
    gen::load_robot(path, options);
    ADD_FAILURE() << "loaded";
  } catch (const gen::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--frames: no link named 'tool'; the links are 'world'"),
              std::string::npos)
        << e.what();
  }
}

// A quadruped as Unitree's describe theirs: an IMU and a radar on the trunk, and on each leg a
// rotor for each joint, fixed to the body before the joint it drives.
std::string quadruped_urdf() {
  const std::string inertial = R"(<inertial><mass value="1"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)";
  const auto link = [&](const std::string& name) {
    return "<link name=\"" + name + "\">" + inertial + "</link>\n";
  };
  const auto joint = [](const std::string& name, const char* type, const std::string& parent,
                        const std::string& child) {
    return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/><origin xyz=\"0 0 -0.2\"/><axis xyz=\"0 1 0\"/>" +
           "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
  };
  std::string urdf = "<robot name=\"quadruped\">\n" + link("base") + link("imu") + link("radar") +
                     joint("imu_joint", "fixed", "base", "imu") +
                     joint("radar_joint", "fixed", "base", "radar");
  for (const std::string leg : {"FL", "FR"}) {
    std::string parent = "base";
    for (const std::string part : {"hip", "thigh", "calf"}) {
      const std::string name = leg + "_" + part;
      urdf += link(name) + link(name + "_rotor") +
              joint(name + "_rotor_joint", "fixed", parent, name + "_rotor") +
              joint(name + "_joint", "revolute", parent, name);
      parent = name;
    }
    urdf += link(leg + "_foot") + joint(leg + "_foot_fixed", "fixed", parent, leg + "_foot");
  }
  return urdf + "</robot>\n";
}

TEST(Frames, ByDefaultNotTheSensorsAndRotorsOnTheTrunkAndAlongTheLegs) {
  // of the 10 leaf links, the feet; locking the knee makes the thigh the end of the leg
  gen::LoadOptions options;
  options.floating_base = true;
  const std::string urdf = quadruped_urdf();
  EXPECT_EQ(frame_names(gen::parse_robot("quadruped.urdf", urdf, options).model),
            (std::vector<std::string>{"FL_foot", "FR_foot"}));
  options.lock = {"FL_calf_joint"};
  EXPECT_EQ(frame_names(gen::parse_robot("quadruped.urdf", urdf, options).model),
            (std::vector<std::string>{"FL_calf_rotor", "FL_foot", "FR_foot"}));
  // a robot that is one free body: its leaf links
  options.lock = {"FL_hip_joint", "FL_thigh_joint", "FL_calf_joint", "FR_hip_joint",
                  "FR_thigh_joint", "FR_calf_joint"};
  EXPECT_EQ(frame_names(gen::parse_robot("quadruped.urdf", urdf, options).model).size(), 10u);
}

TEST(Frames, EveryUrdfLinkIsAFrameOnTheBodyItMovesWith) {
  const std::string path = test::model_path("ur5.urdf");
  std::ifstream in(path);
  const std::string urdf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::set<std::string> links;
  for (const test::Groups& link : test::Pattern(R"re(<link\s+name="([^"]+)")re").find_all(urdf))
    links.insert(link[1]);
  gen::LoadOptions all;
  all.all_frames = true;
  const Model<double> model = gen::load_robot(path, all).model;
  std::set<std::string> frames;
  for (const Frame<double>& f : model.frames) frames.insert(f.name);
  EXPECT_EQ(frames, links);
  ASSERT_EQ(model.frames.size(), links.size());
  for (const Frame<double>& f : model.frames) {
    SCOPED_TRACE(f.name);
    // the URDF's world is the fixed base; base_link hangs on it by a fixed joint
    if (f.name == "world" || f.name == "base_link") {
      EXPECT_EQ(f.body, -1);
    }
    // a moving link is its body's own frame
    const auto body = std::find(model.body_name.begin(), model.body_name.end(), f.name);
    if (body != model.body_name.end()) {
      EXPECT_EQ(f.body, body - model.body_name.begin());
      EXPECT_EQ(f.placement.r.x, 0);
      EXPECT_EQ(f.placement.E.xx, 1);
    }
  }
  // ee_link: fixed to wrist_3_link at xyz 0 0.0823 0, rpy 0 0 pi/2 (ur5.urdf's ee_fixed_joint)
  const auto ee = std::find_if(model.frames.begin(), model.frames.end(),
                               [](const Frame<double>& f) { return f.name == "ee_link"; });
  ASSERT_NE(ee, model.frames.end());
  EXPECT_EQ(model.body_name[ee->body], "wrist_3_link");
  EXPECT_NEAR(ee->placement.r.y, 0.0823, 1e-15);
  EXPECT_NEAR(ee->placement.r.x, 0, 1e-15);
  // E rotates wrist_3 coordinates into ee_link's: the transpose of Rz(pi/2)
  EXPECT_NEAR(ee->placement.E.xy, 1, 1e-11);
  EXPECT_NEAR(ee->placement.E.yx, -1, 1e-11);
}

struct Case {
  std::string name;
  std::function<Model<double>()> make;
};

std::vector<Case> cases() {
  std::vector<Case> all;
  all.push_back({"spatial_chain_7", [] { return test::make_random_chain(7, 77, false); }});
  all.push_back({"all_joints", [] {
                   gen::LoadOptions options;
                   options.all_frames = true;
                   return gen::load_robot(test::model_path("coverage/all_joints.urdf"), options)
                       .model;
                 }});
  all.push_back(
      {"ball_chain", [] { return test::load_model("coverage/ball_chain.yaml", false, true); }});
  for (const std::string robot : {"ur5", "solo12", "atlas"})
    for (const bool floating : {false, true})
      all.push_back({robot + (floating ? "_floating" : ""), [=] {
                       gen::LoadOptions options;
                       options.floating_base = floating;
                       options.all_frames = true;
                       return gen::load_robot(test::model_path(robot + ".urdf"), options).model;
                     }});
  return all;
}

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

class FrameJacobians : public ::testing::TestWithParam<Case> {};

/// The model, or for the random chain, which has no URDF, the chain with a frame on each body,
/// off its origin and turned.
Model<double> with_frames(Model<double> model) {
  if (model.frames.empty())
    for (int i = 0; i < model.nbodies; ++i)
      model.frames.push_back({"frame" + std::to_string(i), i,
                              {{0, 0.6, 0.8, 1, 0, 0, 0, 0.8, -0.6}, {0.1, -0.2, 0.3}}});
  return model;
}

/// The angular velocity w with exp([w] 2h) = B A^T (both 3x3), for small 2h.
Eigen::Vector3d rotation_rate(const Eigen::Matrix3d& after, const Eigen::Matrix3d& before,
                              double two_h) {
  const Eigen::Matrix3d D = after * before.transpose();
  return Eigen::Vector3d(D(2, 1) - D(1, 2), D(0, 2) - D(2, 0), D(1, 0) - D(0, 1)) / (2 * two_h);
}

/// q (free joints' quaternions normalised) and v, every entry uniform in [-1.5, 1.5], from seed.
std::pair<std::vector<double>, std::vector<double>> random_q_v(const Model<double>& model,
                                                               unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<double> q(model.nq), v(model.nv);
  for (double& x : q) x = u(rng);
  for (double& x : v) x = u(rng);
  normalize_configuration<double>(model, q);
  return {q, v};
}

TEST_P(FrameJacobians, AreTheDerivativesOfThePlacements) {
  const Model<double> model = with_frames(GetParam().make());
  const int nv = model.nv, nf = static_cast<int>(model.frames.size());
  ASSERT_GT(nf, 0);
  Workspace<double> ws(model);
  const std::vector<double> q = random_q_v(model, 5).first;
  std::vector<double> d(nv, 0), qp(model.nq), qm(model.nq);
  std::vector<double> R(9 * nf), p(3 * nf), Rp(R.size()), pp(p.size()), Rm(R.size()), pm(p.size());
  std::vector<double> Jw(6 * nf * nv), Jl(Jw.size());
  frame_placements<double>(model, ws, q, R, p);
  frame_jacobians<double>(model, ws, q, JacobianAxes::World, Jw);
  frame_jacobians<double>(model, ws, q, JacobianAxes::Local, Jl);
  const double h = 1e-6;
  double worst = 0, largest = 0;
  for (int c = 0; c < nv; ++c) {
    std::fill(d.begin(), d.end(), 0.0);
    d[c] = h;
    integrate<double>(model, q, d, qp);
    d[c] = -h;
    integrate<double>(model, q, d, qm);
    frame_placements<double>(model, ws, qp, Rp, pp);
    frame_placements<double>(model, ws, qm, Rm, pm);
    for (int f = 0; f < nf; ++f) {
      using M3 = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
      const M3 Rf(&R[9 * f]), Rpf(&Rp[9 * f]), Rmf(&Rm[9 * f]);
      const Eigen::Vector3d lin =
          (Eigen::Vector3d(&pp[3 * f]) - Eigen::Vector3d(&pm[3 * f])) / (2 * h);
      const Eigen::Vector3d ang = rotation_rate(Rpf, Rmf, 2 * h);
      const Eigen::Vector3d local_lin = Rf.transpose() * lin, local_ang = Rf.transpose() * ang;
      for (int row = 0; row < 3; ++row) {
        const std::size_t at = (6 * static_cast<std::size_t>(f) + row) * nv + c;
        const std::size_t ang_at = at + 3 * static_cast<std::size_t>(nv);
        for (const auto& [J, expected] :
             {std::pair{Jw[at], lin[row]}, std::pair{Jw[ang_at], ang[row]},
              std::pair{Jl[at], local_lin[row]}, std::pair{Jl[ang_at], local_ang[row]}}) {
          worst = std::max(worst, std::abs(J - expected));
          largest = std::max(largest, std::abs(expected));
        }
      }
    }
  }
  // central differences: truncation h^2 |third derivative| and rounding eps |p| / h, both
  // about 1e-10 here; a wrong column is off by O(1)
  EXPECT_LT(worst, 1e-7 * std::max(1.0, largest)) << "largest entry " << largest;
  EXPECT_GT(largest, 0.1);
}

// J v is the frame's velocity from kinematics.hpp's velocity pass: its body's spatial velocity
// in base coordinates, taken to the frame's origin
TEST_P(FrameJacobians, TimesVAreTheVelocitiesOfTheVelocityPass) {
  const Model<double> model = with_frames(GetParam().make());
  const int nv = model.nv, nf = static_cast<int>(model.frames.size());
  Workspace<double> ws(model);
  const auto [q, v] = random_q_v(model, 8);
  std::vector<double> R(9 * nf), p(3 * nf), J(6 * nf * nv);
  frame_placements<double>(model, ws, q, R, p);
  frame_jacobians<double>(model, ws, q, JacobianAxes::World, J);
  forward_kinematics<double>(model, ws, q, v);
  double worst = 0, largest = 0;
  for (int f = 0; f < nf; ++f) {
    const int b = model.frames[f].body;
    Motion<double> v0{};
    if (b >= 0) v0 = apply_motion_inv(ws.X0[b], ws.v[b]);
    const Vec3<double> origin{p[3 * f], p[3 * f + 1], p[3 * f + 2]};
    const Vec3<double> lin = v0.lin + cross(v0.ang, origin);
    const double expected[6] = {lin.x, lin.y, lin.z, v0.ang.x, v0.ang.y, v0.ang.z};
    for (int row = 0; row < 6; ++row) {
      double Jv = 0;
      for (int c = 0; c < nv; ++c) Jv += J[(6 * static_cast<std::size_t>(f) + row) * nv + c] * v[c];
      worst = std::max(worst, std::abs(Jv - expected[row]));
      largest = std::max(largest, std::abs(expected[row]));
    }
  }
  EXPECT_LT(worst, 1e-12 * nv * std::max(1.0, largest)) << "largest entry " << largest;
  EXPECT_GT(largest, 0.1);
}

// Jdot v at qdd = 0 is the time derivative of J(q(t)) v along q(t) = q (+) t v, in the base's
// axes; in the frame's own it is that derivative expressed in them (R^T Jdot_world v), so that
// J_local qdd + Jdot_v_local is the frame's acceleration in its own axes.
TEST_P(FrameJacobians, BiasAccelerationsAreTheDerivativeOfJAlongTheMotion) {
  const Model<double> model = with_frames(GetParam().make());
  const int nv = model.nv, nf = static_cast<int>(model.frames.size());
  Workspace<double> ws(model);
  const auto [q, v] = random_q_v(model, 6);
  std::vector<double> d(nv), qp(model.nq), qm(model.nq);
  std::vector<double> R(9 * nf), p(3 * nf), Jp(6 * nf * nv), Jm(Jp.size()), world(6 * nf),
      local(6 * nf);
  frame_placements<double>(model, ws, q, R, p);
  frame_bias_accelerations<double>(model, ws, q, v, JacobianAxes::World, world);
  frame_bias_accelerations<double>(model, ws, q, v, JacobianAxes::Local, local);
  const double h = 1e-6;
  for (int k = 0; k < nv; ++k) d[k] = h * v[k];
  integrate<double>(model, q, d, qp);
  for (int k = 0; k < nv; ++k) d[k] = -h * v[k];
  integrate<double>(model, q, d, qm);
  frame_jacobians<double>(model, ws, qp, JacobianAxes::World, Jp);
  frame_jacobians<double>(model, ws, qm, JacobianAxes::World, Jm);
  double worst = 0, largest = 0;
  for (int f = 0; f < nf; ++f) {
    Eigen::Matrix<double, 6, 1> expected;
    for (int row = 0; row < 6; ++row) {
      double plus = 0, minus = 0;
      for (int c = 0; c < nv; ++c) {
        plus += Jp[(6 * static_cast<std::size_t>(f) + row) * nv + c] * v[c];
        minus += Jm[(6 * static_cast<std::size_t>(f) + row) * nv + c] * v[c];
      }
      expected[row] = (plus - minus) / (2 * h);
    }
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Rf(&R[9 * f]);
    Eigen::Matrix<double, 6, 1> expected_local;
    expected_local << Rf.transpose() * expected.head<3>(), Rf.transpose() * expected.tail<3>();
    for (int row = 0; row < 6; ++row) {
      worst = std::max({worst, std::abs(world[6 * f + row] - expected[row]),
                        std::abs(local[6 * f + row] - expected_local[row])});
      largest = std::max(largest, std::abs(expected[row]));
    }
  }
  EXPECT_LT(worst, 1e-6 * std::max(1.0, largest)) << "largest entry " << largest;
  EXPECT_GT(largest, 0.1);
}

// The centre of mass against the potential energy (kinematics.hpp: V = -g . sum m_i c_i, taken
// with unit gravities along x, y and z), its Jacobian against central differences, and each
// column of the centroidal momentum matrix against kinematics.hpp's momentum at v = that unit
// velocity, moved from the base origin to the centre of mass.
TEST_P(FrameJacobians, CentreOfMassAndCentroidalMomentum) {
  Model<double> model = GetParam().make();
  const int nv = model.nv;
  Workspace<double> ws(model);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<double> q(model.nq), v(nv, 0), d(nv, 0), qp(model.nq), qm(model.nq);
  for (double& x : q) x = u(rng);
  normalize_configuration<double>(model, q);
  std::vector<double> c(3), Jc(3 * nv), cp(3), cm(3), Jp(Jc.size()), A(6 * nv), h(6);
  com<double>(model, ws, q, c, Jc);
  double mass = 0;
  for (const RigidInertia<double>& I : model.I) mass += I.m;
  ASSERT_GT(mass, 0);
  for (int axis = 0; axis < 3; ++axis) {
    Model<double> pulled = model;
    pulled.gravity = {axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0};
    forward_kinematics<double>(pulled, ws, q, v);
    EXPECT_NEAR(c[axis], -potential_energy(pulled, ws) / mass, 1e-12 * (1 + std::abs(c[axis])));
  }
  const double step = 1e-6;
  double worst = 0, largest = 0;
  for (int k = 0; k < nv; ++k) {
    std::fill(d.begin(), d.end(), 0.0);
    d[k] = step;
    integrate<double>(model, q, d, qp);
    d[k] = -step;
    integrate<double>(model, q, d, qm);
    com<double>(model, ws, qp, cp, Jp);
    com<double>(model, ws, qm, cm, Jp);
    for (int row = 0; row < 3; ++row) {
      const double expected = (cp[row] - cm[row]) / (2 * step);
      worst = std::max(worst, std::abs(Jc[row * nv + k] - expected));
      largest = std::max(largest, std::abs(expected));
    }
  }
  EXPECT_LT(worst, 1e-7 * std::max(1.0, largest)) << "largest entry " << largest;
  EXPECT_GT(largest, 0.01);

  std::vector<double> w(nv);
  for (double& x : w) x = u(rng);
  centroidal<double>(model, ws, q, w, A, h);
  const Eigen::Vector3d centre(c[0], c[1], c[2]);
  double momentum_scale = 0;
  std::vector<double> expected_h(6, 0.0);
  worst = 0;
  for (int k = 0; k < nv; ++k) {
    std::fill(v.begin(), v.end(), 0.0);
    v[k] = 1;
    forward_kinematics<double>(model, ws, q, v);
    const Force<double> m = momentum(model, ws);
    const Eigen::Vector3d lin(m.lin.x, m.lin.y, m.lin.z);
    const Eigen::Vector3d ang = Eigen::Vector3d(m.ang.x, m.ang.y, m.ang.z) - centre.cross(lin);
    for (int row = 0; row < 6; ++row) {
      const double expected = row < 3 ? lin[row] : ang[row - 3];
      worst = std::max(worst, std::abs(A[row * nv + k] - expected));
      momentum_scale = std::max(momentum_scale, std::abs(expected));
      expected_h[row] += expected * w[k];
    }
  }
  for (int row = 0; row < 6; ++row) worst = std::max(worst, std::abs(h[row] - expected_h[row]));
  EXPECT_LT(worst, 1e-12 * nv * momentum_scale) << "largest entry " << momentum_scale;
  EXPECT_GT(momentum_scale, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Models, FrameJacobians, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
