// Once a Workspace exists, rnea, crba and aba allocate nothing (Pinocchio's
// set_is_malloc_allowed check), in double and in float.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <new>

#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

TEST(AllocationCounter, CountsEveryKindOfAllocation) {
  // the counter itself, so that a zero below means something
  struct alignas(64) Overaligned {
    double x[8];
  };
  test::AllocationCounter c;
  EXPECT_EQ(c.count(), 0u);
  const auto one = std::make_unique<double>(1.0);
  EXPECT_EQ(c.count(), 1u);
  const auto array = std::make_unique<double[]>(10);
  EXPECT_EQ(c.count(), 2u);
  const auto aligned = std::make_unique<Overaligned>();
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned.get()) % 64, 0u);
  EXPECT_EQ(c.count(), 3u);
  const std::unique_ptr<double> nothrow(new (std::nothrow) double(2.0));
  EXPECT_EQ(c.count(), 4u);
  const std::vector<double> vector(100);
  EXPECT_EQ(c.count(), 5u);
}

template <class S>
void expect_no_allocation(const Model<double>& model_double, const std::string& name) {
  const Model<S> model = model_double.template cast<S>();
  Workspace<S> ws(model);
  test::Random rng(61);
  const test::State s = test::random_state(model_double, rng);
  const std::vector<S> q = test::cast_vector<S>(s.q), qd = test::cast_vector<S>(s.qd),
                       qdd = test::cast_vector<S>(s.qdd), tau = test::cast_vector<S>(s.tau);
  std::vector<S> out(model.nv), M(model.nv * model.nv);

  test::AllocationCounter c;
  rnea<S>(model, ws, q, qd, qdd, out);
  EXPECT_EQ(c.count(), 0u) << name << ": rnea";
  crba<S>(model, ws, q, M);
  EXPECT_EQ(c.count(), 0u) << name << ": crba";
  aba<S>(model, ws, q, qd, tau, out);
  EXPECT_EQ(c.count(), 0u) << name << ": aba";
}

TEST(NoAllocation, Ur5) {
  const Model<double> model = gen::load_robot(test::model_path("ur5.urdf")).model;
  expect_no_allocation<double>(model, "ur5 double");
  expect_no_allocation<float>(model, "ur5 float");
}

TEST(NoAllocation, TwelveLinkChain) {
  const Model<double> model = test::make_random_chain(12, 62, false);
  expect_no_allocation<double>(model, "12-link chain double");
  expect_no_allocation<float>(model, "12-link chain float");
}

}  // namespace
}  // namespace dyngen
