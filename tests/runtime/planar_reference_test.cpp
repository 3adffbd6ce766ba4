// The hand-written planar chain of bench/planar_reference.hpp (the competitor whose operations
// bench/work_counts.cpp counts) against the runtime: tau, M and qdd on make_chain's planar
// chains of 2, 5 and 12 links and on the documented five-link case, at seeded random states.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "op_counter.hpp"
#include "planar_reference.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using bench::Counted;
using bench::PlanarChain;

constexpr int states_per_chain = 50;
constexpr double tolerance = 1e-12;  // relative, in the norm

std::vector<std::string> chain_specs() {
  return {std::string(PLANAR_CHAIN_DIR) + "/planar_chain2.yaml",
          std::string(PLANAR_CHAIN_DIR) + "/planar_chain5.yaml",
          std::string(PLANAR_CHAIN_DIR) + "/planar_chain12.yaml", test::model_path("planar5.yaml")};
}

double error(const std::vector<double>& x, const std::vector<double>& reference) {
  return test::relative_error(test::to_eigen(x), test::to_eigen(reference));
}

class PlanarReference : public ::testing::TestWithParam<std::string> {};

TEST_P(PlanarReference, AgreesWithTheRuntime) {
  const Model<double> model = gen::load_robot(GetParam()).model;
  const int n = model.nv;
  PlanarChain<double> planar(model);
  ASSERT_EQ(planar.dofs(), n);
  Workspace<double> ws(model);
  test::Random rng(20261121 + n);
  double worst_tau = 0, worst_M = 0, worst_qdd = 0;
  for (int k = 0; k < states_per_chain; ++k) {
    const test::State s = test::random_state(model, rng);
    std::vector<double> tau(n), M(n * n), qdd(n), tau_ref(n), M_ref(n * n), qdd_ref(n);
    planar.rnea(s.q.data(), s.qd.data(), s.qdd.data(), tau.data());
    planar.crba(s.q.data(), M.data());
    planar.aba(s.q.data(), s.qd.data(), s.tau.data(), qdd.data());
    rnea<double>(model, ws, s.q, s.qd, s.qdd, tau_ref);
    crba<double>(model, ws, s.q, M_ref);
    aba<double>(model, ws, s.q, s.qd, s.tau, qdd_ref);
    worst_tau = std::max(worst_tau, error(tau, tau_ref));
    worst_M = std::max(worst_M, error(M, M_ref));
    worst_qdd = std::max(worst_qdd, error(qdd, qdd_ref));
  }
  EXPECT_LT(worst_tau, tolerance);
  EXPECT_LT(worst_M, tolerance);
  EXPECT_LT(worst_qdd, tolerance);
  char worst[96];
  std::snprintf(worst, sizeof worst, "tau %.2g, M %.2g, qdd %.2g", worst_tau, worst_M, worst_qdd);
  RecordProperty("worst_relative_errors", worst);
}

// The counting scalar changes nothing but the counters: the same operations in the same order.
TEST_P(PlanarReference, CountedComputesTheSameBits) {
  const Model<double> model = gen::load_robot(GetParam()).model;
  const int n = model.nv;
  PlanarChain<double> planar(model);
  PlanarChain<Counted> counted(model);
  test::Random rng(7);
  const test::State s = test::random_state(model, rng);
  const std::vector<Counted> q(s.q.begin(), s.q.end()), qd(s.qd.begin(), s.qd.end()),
      qdd(s.qdd.begin(), s.qdd.end()), tau(s.tau.begin(), s.tau.end());
  std::vector<double> out(n * n);
  std::vector<Counted> counted_out(n * n);
  auto expect_same = [&](const char* what, int size) {
    for (int k = 0; k < size; ++k)
      EXPECT_EQ(out[k], counted_out[k].value) << what << " entry " << k;
  };
  planar.rnea(s.q.data(), s.qd.data(), s.qdd.data(), out.data());
  counted.rnea(q.data(), qd.data(), qdd.data(), counted_out.data());
  expect_same("tau", n);
  planar.crba(s.q.data(), out.data());
  counted.crba(q.data(), counted_out.data());
  expect_same("M", n * n);
  planar.aba(s.q.data(), s.qd.data(), s.tau.data(), out.data());
  counted.aba(q.data(), qd.data(), tau.data(), counted_out.data());
  expect_same("qdd", n);
}

/// The file's name without its directory and extension.
std::string chain_name(const ::testing::TestParamInfo<std::string>& info) {
  const std::string& path = info.param;
  const std::size_t slash = path.find_last_of('/'), dot = path.rfind('.');
  return path.substr(slash + 1, dot - slash - 1);
}

INSTANTIATE_TEST_SUITE_P(Chains, PlanarReference, ::testing::ValuesIn(chain_specs()), chain_name);

TEST(PlanarReference, CountsEveryOperationOnce) {
  bench::CountScope scope;
  Counted x = 2.0, y = 3.0;
  x = x * y + x / y - (-x);
  x = sin(x) + cos(y) + sqrt(y);
  const bench::OpTally& c = scope.counts();
  EXPECT_EQ(c.add, 4);
  EXPECT_EQ(c.mul, 1);
  EXPECT_EQ(c.div, 1);
  EXPECT_EQ(c.neg, 1);
  EXPECT_EQ(c.sin, 1);
  EXPECT_EQ(c.cos, 1);
  EXPECT_EQ(c.sqrt, 1);
}

TEST(PlanarReference, RefusesWhatIsNotAPlanarChain) {
  EXPECT_THROW(PlanarChain<double>(test::make_random_chain(4, 1, false)), std::invalid_argument);
  // planar, but its joint frames are turned and its prismatic joints slide across the links
  EXPECT_THROW(PlanarChain<double>(test::make_random_chain(4, 1, true)), std::invalid_argument);
}

}  // namespace
}  // namespace dyngen
