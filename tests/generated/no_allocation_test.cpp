// Generated functions touch no heap: counted by replacing the global allocation functions.
#include <array>

#include <gtest/gtest.h>

#include "atlas_double_dynamics.hpp"
#include "planar5_float_dynamics.hpp"
#include "romeo_locked_double_dynamics.hpp"
#include "spatial_chain12_float_dynamics.hpp"
#include "test_support.hpp"
#include "ur5_double_dynamics.hpp"

namespace {

using dyngen::test::AllocationCounter;

/// Calls every function of one generated package on a random state; returns the allocations.
template <class S, int NQ, int NV, class Rnea, class Crba, class Aba>
std::size_t allocations(Rnea rnea, Crba crba, Aba aba) {
  dyngen::test::Random rng(7);
  std::array<S, NQ> q;
  std::array<S, NV> v, a, tau, qdd;
  std::array<S, NV * NV> M;
  for (S& x : q) x = static_cast<S>(rng.uniform(-3, 3));
  for (S& x : v) x = static_cast<S>(rng.uniform(-3, 3));
  for (S& x : a) x = static_cast<S>(rng.uniform(-3, 3));
  const AllocationCounter counter;
  rnea(q.data(), v.data(), a.data(), tau.data());
  crba(q.data(), M.data());
  aba(q.data(), v.data(), tau.data(), qdd.data());
  return counter.count();
}

}  // namespace

TEST(GeneratedAllocation, CounterSeesAllocations) {
  const AllocationCounter counter;
  // a direct call: a new-expression whose result is unused may be elided by the compiler
  void* p = ::operator new(32);
  ::operator delete(p);
  EXPECT_EQ(counter.count(), 1u);
}

TEST(GeneratedAllocation, NoneInGeneratedFunctions) {
  EXPECT_EQ((allocations<double, ur5_double::nq, ur5_double::nv>(
                ur5_double::rnea, ur5_double::crba, ur5_double::aba)),
            0u);
  EXPECT_EQ((allocations<double, atlas_double::nq, atlas_double::nv>(
                atlas_double::rnea, atlas_double::crba, atlas_double::aba)),
            0u);
  EXPECT_EQ((allocations<double, romeo_locked_double::nq, romeo_locked_double::nv>(
                romeo_locked_double::rnea, romeo_locked_double::crba, romeo_locked_double::aba)),
            0u);
  EXPECT_EQ((allocations<float, planar5_float::nq, planar5_float::nv>(
                planar5_float::rnea, planar5_float::crba, planar5_float::aba)),
            0u);
  EXPECT_EQ((allocations<float, spatial_chain12_float::nq, spatial_chain12_float::nv>(
                spatial_chain12_float::rnea, spatial_chain12_float::crba,
                spatial_chain12_float::aba)),
            0u);
}
