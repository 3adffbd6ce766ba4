// dyngen's MJCF reader against MuJoCo on the same files (tests/models/mjcf): MuJoCo compiles
// each file itself, with every force dyngen does not model switched off, and its mass matrix
// (mj_fullM), inverse dynamics (mj_inverse's qfrc_inverse), forward dynamics (mj_forward's
// qacc) and site placements must match the runtime's on the model dyngen read, to a norm-wise
// relative error of 1e-9, at seeded random states. The files cover the orientation forms, angle
// units, default classes, multi-joint bodies, ref, armature, ball joints and inertia from geoms;
// two of MuJoCo Menagerie's models are read as published (MuJoCo gets stand-ins for their meshes).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "mujoco_peer.hpp"
#include "robot.hpp"
#include "test_support.hpp"

namespace dyngen::test {
namespace {

constexpr double tolerance = 1e-9;

struct MjDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
  void operator()(mjData* d) const { mj_deleteData(d); }
};

class MjcfPeer : public ::testing::TestWithParam<const char*> {};

/// "menagerie/go2.xml" -> "go2"
std::string file_name(const std::string& file) {
  const std::string stem = file.substr(file.rfind('/') + 1);
  return stem.substr(0, stem.find('.'));
}

TEST_P(MjcfPeer, DynamicsAndSitesMatchMujocosOwnCompilation) {
  const std::string path = model_path(std::string("mjcf/") + GetParam());
  gen::LoadOptions options;
  options.all_frames = true;
  const gen::Robot robot = gen::load_robot(path, options);
  const Model<double>& model = robot.model;
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("dyngen-mjcf-" + std::to_string(getpid()) + "-" + file_name(GetParam()));
  std::filesystem::remove_all(dir);
  const std::string copy = mujoco_peer::mujoco_mjcf(path, dir.string());
  std::array<char, 1000> error{};
  const std::unique_ptr<mjModel, MjDeleter> m(
      mj_loadXML(copy.c_str(), nullptr, error.data(), static_cast<int>(error.size())));
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(m) << error.data();
  m->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_EQUALITY | mjDSBL_FRICTIONLOSS |
                         mjDSBL_LIMIT | mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;
  const std::unique_ptr<mjData, MjDeleter> d(mj_makeData(m.get()));
  ASSERT_EQ(m->nv, model.nv);
  ASSERT_EQ(m->njnt, model.nbodies);
  std::vector<int> joint(model.nbodies);
  for (int i = 0; i < model.nbodies; ++i) {
    joint[i] = mj_name2id(m.get(), mjOBJ_JOINT, model.joint_name[i].c_str());
    // an unnamed joint is "joint<id>" in dyngen (a <freejoint/> often is)
    const std::string& name = model.joint_name[i];
    if (joint[i] < 0 && name.size() > 5 && name.rfind("joint", 0) == 0 &&
        name.find_first_not_of("0123456789", 5) == std::string::npos)
      joint[i] = std::stoi(name.substr(5));
    ASSERT_GE(joint[i], 0) << model.joint_name[i];
  }
  Workspace<double> ws(model);
  const int nv = model.nv;
  std::vector<double> M(nv * nv), tau(nv), qdd(nv), R(9 * model.frames.size()),
      p(3 * model.frames.size());
  double crba = 0, rnea = 0, aba = 0, sites = 0;
  Random rng(20261128);
  for (int sample = 0; sample < 20; ++sample) {
    const State s = random_state(model, rng);
    // v_mujoco = A v: a free joint's linear velocity is in world axes in MuJoCo
    const std::vector<double> pos = mujoco_peer::qpos(m.get(), model, joint, s.q);
    std::copy(pos.begin(), pos.end(), d->qpos);
    const Eigen::MatrixXd A = mujoco_peer::velocity_map(m.get(), model, joint, s.q);
    const Eigen::VectorXd bias = mujoco_peer::free_joint_bias(m.get(), model, joint, s.q, s.qd);
    const Eigen::VectorXd v = to_eigen(s.qd), a = to_eigen(s.qdd), t = to_eigen(s.tau);
    Eigen::Map<Eigen::VectorXd>(d->qvel, nv) = A * v;
    Eigen::Map<Eigen::VectorXd>(d->qacc, nv) = A * a + bias;
    mj_inverse(m.get(), d.get());
    Eigen::MatrixXd M_mj(nv, nv);
    mj_fullM(m.get(), M_mj.data(), d->qM);  // symmetric: row- or column-major alike
    const Eigen::VectorXd tau_mj = A.transpose() * Eigen::Map<Eigen::VectorXd>(d->qfrc_inverse, nv);
    Eigen::Map<Eigen::VectorXd>(d->qfrc_applied, nv) = A * t;
    mj_forward(m.get(), d.get());
    const Eigen::VectorXd qdd_mj =
        A.transpose() * (Eigen::Map<Eigen::VectorXd>(d->qacc, nv) - bias);

    dyngen::crba<double>(model, ws, s.q, M);
    dyngen::rnea<double>(model, ws, s.q, s.qd, s.qdd, tau);
    dyngen::aba<double>(model, ws, s.q, s.qd, s.tau, qdd);
    crba = std::max(crba, relative_error(to_eigen(M, nv), A.transpose() * M_mj * A));
    rnea = std::max(rnea, relative_error(to_eigen(tau), tau_mj));
    aba = std::max(aba, relative_error(to_eigen(qdd), qdd_mj));

    frame_placements<double>(model, ws, s.q, R, p);
    for (int site = 0; site < m->nsite; ++site) {
      const std::string name = mj_id2name(m.get(), mjOBJ_SITE, site);
      std::size_t f = 0;
      while (f < model.frames.size() && model.frames[f].name != name) ++f;
      ASSERT_LT(f, model.frames.size()) << name;
      const Eigen::Vector3d p_mj(d->site_xpos + 3 * site), p_dyngen(&p[3 * f]);
      const Eigen::Matrix3d R_mj = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
          d->site_xmat + 9 * site);
      const Eigen::Matrix3d R_dyngen =
          Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&R[9 * f]);
      sites = std::max({sites, relative_error(p_dyngen, p_mj), (R_dyngen - R_mj).norm()});
    }
  }
  EXPECT_LE(crba, tolerance);
  EXPECT_LE(rnea, tolerance);
  EXPECT_LE(aba, tolerance);
  EXPECT_LE(sites, tolerance);
  std::printf("measured %s (nv %d): crba %.2e, rnea %.2e, aba %.2e, sites %.2e against MuJoCo\n",
              GetParam(), nv, crba, rnea, aba, sites);
}

// Menagerie's files as published (tests/models/README.md): Unitree's go2 (a free base, armature
// 0.01 on every joint, from default classes) and Franka's panda without its hand (armature 0.1,
// fullinertia), both with mesh geoms.
INSTANTIATE_TEST_SUITE_P(Files, MjcfPeer,
                         ::testing::Values("arm.xml", "quadruped.xml", "ball.xml",
                                           "menagerie/go2.xml", "menagerie/panda_nohand.xml"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           return file_name(info.param);
                         });

}  // namespace
}  // namespace dyngen::test
