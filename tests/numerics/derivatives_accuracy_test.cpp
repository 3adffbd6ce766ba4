// The derivatives in double against the truth: central differences of the runtime's own rnea and
// aba on MPFR numbers (reference_bits, at least 256), with a step of 2^-60 along
// dyngen::integrate and v, which leaves them exact to about 1e-36, on shared and stiff robots
// and on ball joints (whose columns, like a free joint's, are tangent directions).
// Errors are norm-wise relative (Frobenius) and printed on lines starting with "measured".
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/conditioning.hpp"
#include "dyngen/numerics/reference.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using numerics::Exact;

struct Robot {
  std::string file;  // in tests/models
  bool floating_base;
};

const std::vector<Robot> robots = {
    {"ur5.urdf", false},          {"iiwa14.urdf", false},
    {"solo12.urdf", true},        {"atlas.urdf", true},
    {"stiff/alternating20.yaml", false}, {"stiff/thin_rods12.yaml", false},
    {"stiff/light_limbs.urdf", true},    {"stiff/tapered50_0p9.yaml", false},
    {"coverage/ball_chain.yaml", true},  {"mjcf/ball.xml", false},
};

/// Columns of d f / dq (along integrate) and d f / dv by central differences in MPFR.
template <class F>
void central_differences(const Model<Exact>& model, const std::vector<Exact>& q,
                         const std::vector<Exact>& v, F f, std::vector<Exact>& dq,
                         std::vector<Exact>& dv) {
  const int n = model.nv;
  const Exact h = mpfr::ldexp(Exact(1), -60);
  std::vector<Exact> d(n, Exact(0)), qp(q.size()), qm(q.size());
  dq.assign(static_cast<std::size_t>(n) * n, Exact(0));
  dv.assign(static_cast<std::size_t>(n) * n, Exact(0));
  for (int c = 0; c < n; ++c) {
    d[c] = h;
    integrate<Exact>(model, q, d, qp);
    d[c] = -h;
    integrate<Exact>(model, q, d, qm);
    d[c] = 0;
    const std::vector<Exact> fp = f(qp, v), fm = f(qm, v);
    std::vector<Exact> vp = v, vm = v;
    vp[c] += h;
    vm[c] -= h;
    const std::vector<Exact> gp = f(q, vp), gm = f(q, vm);
    for (int r = 0; r < n; ++r) {
      dq[static_cast<std::size_t>(r) * n + c] = (fp[r] - fm[r]) / (2 * h);
      dv[static_cast<std::size_t>(r) * n + c] = (gp[r] - gm[r]) / (2 * h);
    }
  }
}

// Bounds from the measurements with a margin of about 4: inverse dynamics' derivatives lose no
// more than rounding (measured at most 1.2e-15, 0.87 nv eps on ur5), forward dynamics' carry
// the digits its pivots lose (measured at most 2.2 eps 10^digits_lost, alternating20; thin_rods12
// loses 10.7 digits and keeps 1.5e-5).
constexpr double rnea_bound_neps = 4;
constexpr double aba_bound = 8;  // in units of eps 10^(digits ABA may lose)

TEST(DerivativesAccuracy, AgainstMpfrCentralDifferences) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  for (const Robot& robot : robots) {
    gen::LoadOptions options;
    options.floating_base = robot.floating_base;
    options.mimic_independent = true;
    const Model<double> model = gen::load_robot(test::model_path(robot.file), options).model;
    const int n = model.nv;
    const numerics::Conditioning cond = numerics::estimate_conditioning(model, 16, 1);
    numerics::ExactDynamics exact(model, numerics::reference_bits(cond.aba_digits_lost()));
    mpfr::mpreal::set_default_prec(exact.bits());
    Workspace<Exact> ews(exact.model());
    test::Random rng(11);
    numerics::State s = test::random_state(model, rng);
    numerics::set_consistent_torques(exact, s);
    const std::vector<Exact> q = numerics::widen<double>(s.q), v = numerics::widen<double>(s.qd),
                             a = numerics::widen<double>(s.qdd),
                             tau = numerics::widen<double>(s.tau);
    std::vector<Exact> out(n), rq, rv, fq, fv;
    central_differences(exact.model(), q, v,
                        [&](const std::vector<Exact>& x, const std::vector<Exact>& y) {
                          rnea<Exact>(exact.model(), ews, x, y, a, out);
                          return out;
                        },
                        rq, rv);
    central_differences(exact.model(), q, v,
                        [&](const std::vector<Exact>& x, const std::vector<Exact>& y) {
                          aba<Exact>(exact.model(), ews, x, y, tau, out);
                          return out;
                        },
                        fq, fv);

    Workspace<double> ws(model);
    const std::size_t nn = static_cast<std::size_t>(n) * n;
    std::vector<double> dq(nn), dv(nn), Dq(nn), Dv(nn), Minv(nn);
    rnea_derivatives<double>(model, ws, s.q, s.qd, s.qdd, dq, dv);
    aba_derivatives<double>(model, ws, s.q, s.qd, s.tau, Dq, Dv, Minv);
    const double rnea_error =
        std::max(numerics::relative_error(dq, rq), numerics::relative_error(dv, rv));
    const double aba_error =
        std::max(numerics::relative_error(Dq, fq), numerics::relative_error(Dv, fv));
    const double aba_scale = eps * std::pow(10.0, cond.aba_digits_lost());
    std::cout << "measured " << robot.file << (robot.floating_base ? " floating" : "")
              << ": rnea_derivatives " << rnea_error << " (" << rnea_error / (n * eps)
              << " nv eps), aba_derivatives " << aba_error << " (" << aba_error / aba_scale
              << " eps 10^" << cond.aba_digits_lost() << ")\n";
    EXPECT_LE(rnea_error, rnea_bound_neps * n * eps) << robot.file;
    EXPECT_LE(aba_error, aba_bound * aba_scale) << robot.file;
  }
}

}  // namespace
}  // namespace dyngen
