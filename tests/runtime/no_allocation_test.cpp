// Once a Workspace exists, no algorithm of the table allocates (Pinocchio's
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
  // every algorithm of the table, with its arrays made before counting
  for (const AlgorithmSpec<S>& a : algorithm_table<S>()) {
    std::vector<std::vector<S>> x, y;
    for (const ArraySpec& in : a.inputs)
      x.push_back(test::cast_vector<S>(in.name == "q" ? s.q
                                       : in.name == "v" ? s.qd
                                       : in.name == "a" ? s.qdd
                                                        : s.tau));
    for (const ArraySpec& out : a.outputs) y.emplace_back(extent_size(out.extent, model));
    const std::vector<std::span<const S>> in(x.begin(), x.end());
    const std::vector<std::span<S>> out(y.begin(), y.end());
    test::AllocationCounter c;
    a.call(model, ws, in, out);
    EXPECT_EQ(c.count(), 0u) << name << ": " << a.name;
  }
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

TEST(NoAllocation, FloatingQuadruped) {
  gen::LoadOptions options;
  options.floating_base = true;
  const Model<double> model = gen::load_robot(test::model_path("solo12.urdf"), options).model;
  expect_no_allocation<double>(model, "solo12 floating double");
}

}  // namespace
}  // namespace dyngen
