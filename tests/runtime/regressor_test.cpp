// The inertial-parameter regressor (dyngen/regressor.hpp) against RNEA: Y pi + armature a must
// be RNEA's tau, and each column of Y must be the central difference of RNEA in that parameter
// (RNEA with the body's inertia changed, exact up to rounding since tau is linear in it), on
// arms, floating robots, ball, mimic and armature joints.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

/// max |x - y| / max(1, max |scale|)
double scaled_error(const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<double>& scale) {
  double diff = 0, size = 1;
  for (std::size_t k = 0; k < x.size(); ++k) {
    diff = std::max(diff, std::abs(x[k] - y[k]));
    size = std::max(size, std::abs(scale[k]));
  }
  return diff / size;
}

/// Body i's inertia with its standard parameter p moved by h.
RigidInertia<double> moved(RigidInertia<double> I, int p, double h) {
  double pi[parameters_per_body];
  inertial_parameters(I, pi);
  pi[p] += h;
  return {pi[0], {pi[1], pi[2], pi[3]}, {pi[4], pi[6], pi[9], pi[5], pi[7], pi[8]}};
}

class Regressor : public ::testing::TestWithParam<std::pair<const char*, bool>> {};

TEST_P(Regressor, IsRneaLinearInTheBodiesParameters) {
  const Model<double> model = test::load_model(GetParam().first, GetParam().second);
  const int n = model.nv, columns = parameters_per_body * model.nbodies;
  Workspace<double> ws(model);
  std::vector<double> pi(static_cast<std::size_t>(columns));
  for (int i = 0; i < model.nbodies; ++i)
    inertial_parameters(model.I[i], &pi[static_cast<std::size_t>(parameters_per_body * i)]);
  test::Random rng(7);
  double product = 0, column = 0;
  std::vector<double> Y(static_cast<std::size_t>(n) * columns), tau(n), Ypi(n), plus(n), minus(n);
  for (int sample = 0; sample < 4; ++sample) {
    const test::State s = test::random_state(model, rng);
    regressor<double>(model, ws, s.q, s.qd, s.qdd, Y);
    rnea<double>(model, ws, s.q, s.qd, s.qdd, tau);
    for (int k = 0; k < n; ++k) {
      double sum = model.armature.empty() ? 0.0 : model.armature[k] * s.qdd[k];
      for (int c = 0; c < columns; ++c) sum += Y[static_cast<std::size_t>(k) * columns + c] * pi[c];
      Ypi[k] = sum;
    }
    product = std::max(product, scaled_error(Ypi, tau, tau));
    // each column by central differences of RNEA in its parameter, h = 0.5 (their rounding
    // is that of the torques they subtract)
    for (int c = 0; c < columns; ++c) {
      const int i = c / parameters_per_body, p = c % parameters_per_body;
      Model<double> changed = model;
      changed.I[i] = moved(model.I[i], p, 0.5);
      rnea<double>(changed, ws, s.q, s.qd, s.qdd, plus);
      changed.I[i] = moved(model.I[i], p, -0.5);
      rnea<double>(changed, ws, s.q, s.qd, s.qdd, minus);
      std::vector<double> fd(n), y(n);
      for (int k = 0; k < n; ++k) {
        fd[k] = plus[k] - minus[k];
        y[k] = Y[static_cast<std::size_t>(k) * columns + c];
      }
      column = std::max(column, scaled_error(y, fd, plus));
    }
  }
  std::cout << "[ measured ] " << GetParam().first << (GetParam().second ? " floating" : "")
            << " (" << model.nbodies << " bodies): |Y pi + armature a - rnea| " << product
            << ", Y's columns against central differences of rnea " << column << "\n";
  EXPECT_LE(product, 1e-12);
  EXPECT_LE(column, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Robots, Regressor,
                         ::testing::Values(std::pair{"ur5.urdf", false},
                                           std::pair{"iiwa14.urdf", false},
                                           std::pair{"panda.urdf", false},
                                           std::pair{"solo12.urdf", true},
                                           std::pair{"atlas.urdf", true},
                                           std::pair{"coverage/all_joints.urdf", false},
                                           std::pair{"coverage/ball_chain.yaml", true},
                                           std::pair{"coverage/mimic_gripper.urdf", true}),
                         [](const auto& info) {
                           return test::case_name(info.param.first, info.param.second);
                         });

}  // namespace
}  // namespace dyngen
