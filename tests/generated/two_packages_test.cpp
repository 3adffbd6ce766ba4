// Two packages in one program whose kernels differ, as packages of two dyngen versions would
// (issue 46): dispatch_solo12 as dyngen wrote it, compiled with the load-time dispatch, and
// kernels_altered, the same robot's aba_derivatives with a neg_product that negates its result
// once more (alter_kernels.cmake), compiled for the baseline. Had the two shared a definition,
// the linker would have kept one for both; each must compute with its own: the first bit for bit
// as the runtime, the second with d qdd / dq and d qdd / dv negated, exactly, where M^-1 d tau
// is all they are.
#include <gtest/gtest.h>

#include <dyngen/aba_derivatives.hpp>
#include <dyngen/numerics/random.hpp>
#include <vector>

#include "dispatch_solo12_dynamics.hpp"
#include "dispatch_solo12_model.hpp"
#include "kernels_altered_dynamics.hpp"

namespace {

TEST(TwoPackages, EachKeepsItsOwnKernels) {
  const dyngen::Model<double> model = dispatch_solo12::runtime_model();
  static_assert(dispatch_solo12::nv == kernels_altered::nv);
  constexpr int nv = dispatch_solo12::nv, nn = nv * nv;
  dyngen::Workspace<double> ws(model);
  dyngen::numerics::Random rng(46);
  for (int k = 0; k < 20; ++k) {
    const dyngen::numerics::State s = dyngen::numerics::random_state(model, rng);
    std::vector<double> dq(nn), dv(nn), Minv(nn), a_dq(nn), a_dv(nn), a_Minv(nn), b_dq(nn),
        b_dv(nn), b_Minv(nn);
    dyngen::aba_derivatives<double>(model, ws, s.q, s.qd, s.tau, dq, dv, Minv);
    dispatch_solo12::aba_derivatives(s.q.data(), s.qd.data(), s.tau.data(), a_dq.data(),
                                     a_dv.data(), a_Minv.data());
    kernels_altered::aba_derivatives(s.q.data(), s.qd.data(), s.tau.data(), b_dq.data(),
                                     b_dv.data(), b_Minv.data());
    int negated = 0;
    for (int i = 0; i < nn; ++i) {
      EXPECT_EQ(a_dq[i], dq[i]) << "state " << k << ", entry " << i;
      EXPECT_EQ(a_dv[i], dv[i]) << "state " << k << ", entry " << i;
      EXPECT_EQ(a_Minv[i], Minv[i]) << "state " << k << ", entry " << i;
      EXPECT_EQ(b_Minv[i], Minv[i]) << "state " << k << ", entry " << i;
      EXPECT_EQ(b_dq[i], -dq[i]) << "state " << k << ", entry " << i;
      EXPECT_EQ(b_dv[i], -dv[i]) << "state " << k << ", entry " << i;
      negated += dq[i] != 0;
    }
    EXPECT_GT(negated, nv) << "too few non-zero entries to tell the kernels apart";
  }
}

}  // namespace
