// The analytical derivatives against forward-mode differentiation of the value algorithms
// (dyngen::test::Dual through rnea<Dual>): a different algebra on the same model.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "dual.hpp"
#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using D = test::Dual<double>;
constexpr double eps = std::numeric_limits<double>::epsilon();

/// q moved along tangent direction c to first order, as a dual number: a revolute or prismatic
/// entry by e, a free joint's pose M by M exp(e d) with d its c-th column (linear then angular,
/// body frame), so position p + e R d_lin and quaternion q (x) (1, e d_ang / 2); a ball joint's
/// quaternion alike.
std::vector<D> tangent(const Model<double>& model, const std::vector<double>& q, int c) {
  std::vector<D> x;
  for (const double qi : q) x.emplace_back(qi, 0.0);
  for (int i = 0; i < model.nbodies; ++i) {
    const int k = model.v_index[i], qk = model.q_index[i];
    if (c < k || c >= k + joint_nv(model.joint_type[i])) continue;
    const int o = quaternion_offset(model.joint_type[i]);
    if (o < 0) {
      x[qk].dx = 1;
      continue;
    }
    const double* w = &q[qk + o];
    const Mat3<double> R = quaternion_rotation(w[0], w[1], w[2], w[3]);
    if (c - k < o) {
      const double d[3] = {c - k == 0 ? 1.0 : 0.0, c - k == 1 ? 1.0 : 0.0, c - k == 2 ? 1.0 : 0.0};
      const Vec3<double> Rd = mul(R, Vec3<double>{d[0], d[1], d[2]});
      x[qk].dx = Rd.x, x[qk + 1].dx = Rd.y, x[qk + 2].dx = Rd.z;
    } else {
      // (w, v) (x) (1, u/2): dw = -v.u / 2, dv = (w u + v x u) / 2
      const int a = c - k - o;  // the angular column
      const Vec3<double> u{a == 0 ? 1.0 : 0.0, a == 1 ? 1.0 : 0.0, a == 2 ? 1.0 : 0.0};
      const Vec3<double> v{w[1], w[2], w[3]};
      const Vec3<double> dv = scale(scale(u, w[0]) + cross(v, u), 0.5);
      x[qk + o].dx = -0.5 * dot(v, u);
      x[qk + o + 1].dx = dv.x, x[qk + o + 2].dx = dv.y, x[qk + o + 3].dx = dv.z;
    }
  }
  return x;
}

std::vector<D> constant(const std::vector<double>& x) {
  std::vector<D> d;
  for (const double xi : x) d.emplace_back(xi, 0.0);
  return d;
}

struct Case {
  std::string name;
  std::function<Model<double>()> make;
};

std::vector<Case> cases() {
  std::vector<Case> all;
  for (const bool planar : {true, false})
    for (const int n : {1, 2, 7}) {
      const std::uint64_t seed = 2000 + n + (planar ? 0 : 100);
      all.push_back({std::string(planar ? "planar" : "spatial") + "_chain_" + std::to_string(n),
                     [=] { return test::make_random_chain(n, seed, planar); }});
    }
  all.push_back({"all_joints", [] {
                   return gen::load_robot(test::model_path("coverage/all_joints.urdf")).model;
                 }});
  for (const bool floating : {false, true})
    all.push_back({floating ? "ball_chain_floating" : "ball_chain",
                   [=] { return test::load_model("coverage/ball_chain.yaml", floating); }});
  for (const test::RobotFile& robot : test::robot_files()) {
    all.push_back({robot.name, [=] { return test::load_for_aba(robot); }});
    all.push_back({robot.name + "_floating", [=] { return test::load_for_aba(robot, true); }});
  }
  return all;
}

class Derivatives : public ::testing::TestWithParam<Case> {
 protected:
  void report(const char* what, double value) const {
    std::cout << "[ measured ] " << GetParam().name << ": " << what << " " << value << "\n";
  }
};

// Error in units of nv eps times the largest entry of the matrices (the dual's): the two
// algorithms sum different terms, so they agree to the rounding of the largest of them; a
// column that is zero in exact arithmetic (a joint whose axis keeps tau_i independent of it)
// carries rounding noise of that size. Measured at most 3.4 (spatial_chain_2); a wrong term is
// off by O(1) relative.
constexpr double bound_neps = 16;
// Forward dynamics multiplies by M^-1, so its errors carry cond(M) too: they are measured in
// units of nv eps max|entry| cond(M). Measured at most 3.6 (spatial_chain_2, cond(M) 4; the
// rest below 2.5); a wrong term gives at least 1 / (nv eps cond(M)), above 1e5 for every model
// here.
constexpr double aba_bound_neps_cond = 16;

double condition_number(const Model<double>& model, Workspace<double>& ws,
                        const std::vector<double>& q) {
  const int n = model.nv;
  std::vector<double> M(n * n);
  crba<double>(model, ws, q, M);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(test::to_eigen(M, n),
                                                           Eigen::EigenvaluesOnly);
  return eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
}

/// Columns of dtau/dq and dtau/dv by forward-mode differentiation of rnea, row-major.
void forward_mode(const Model<double>& model, const Model<D>& dual, Workspace<D>& ws,
                  const test::State& s, std::vector<double>& dq, std::vector<double>& dv) {
  const int n = model.nv;
  std::vector<D> tau(n);
  for (int c = 0; c < n; ++c) {
    std::vector<D> qd = constant(s.qd);
    rnea<D>(dual, ws, tangent(model, s.q, c), qd, constant(s.qdd), tau);
    for (int r = 0; r < n; ++r) dq[r * n + c] = tau[r].dx;
    qd[c].dx = 1;
    rnea<D>(dual, ws, constant(s.q), qd, constant(s.qdd), tau);
    for (int r = 0; r < n; ++r) dv[r * n + c] = tau[r].dx;
  }
}

double max_abs(const std::vector<double>& x) {
  double m = 0;
  for (const double e : x) m = std::max(m, std::abs(e));
  return m;
}

/// max |a - b| / (n eps scale)
double scaled_error(const std::vector<double>& a, const std::vector<double>& b, int n,
                    double scale) {
  double err = 0;
  for (std::size_t k = 0; k < a.size(); ++k) err = std::max(err, std::abs(a[k] - b[k]));
  return err / (n * eps * scale);
}

TEST_P(Derivatives, RneaDerivativesMatchForwardModeDifferentiation) {
  const Model<double> model = GetParam().make();
  const Model<D> dual = model.cast<D>();
  const int n = model.nv;
  Workspace<double> ws(model);
  Workspace<D> dws(dual);
  test::Random rng(7);
  std::vector<double> dq(n * n), dv(n * n), fq(n * n), fv(n * n);
  double worst = 0;
  for (int sample = 0; sample < 5; ++sample) {
    const test::State s = test::random_state(model, rng);
    rnea_derivatives<double>(model, ws, s.q, s.qd, s.qdd, dq, dv);
    forward_mode(model, dual, dws, s, fq, fv);
    // dtau/dv is zero for a single joint; its terms are of the size of dtau/dq's
    const double scale = std::max(max_abs(fq), max_abs(fv));
    const double eq = scaled_error(dq, fq, n, scale), ev = scaled_error(dv, fv, n, scale);
    worst = std::max({worst, eq, ev});
    EXPECT_LE(eq, bound_neps) << "dtau_dq at sample " << sample;
    EXPECT_LE(ev, bound_neps) << "dtau_dv at sample " << sample;
  }
  report("rnea_derivatives vs dual numbers, error / (nv eps max|entry|)", worst);
}

TEST_P(Derivatives, TangentColumnsAreThoseOfIntegrate) {
  // central differences of rnea along integrate(q, +-h e_c), the q (+) d the README documents
  const Model<double> model = GetParam().make();
  const int n = model.nv;
  Workspace<double> ws(model);
  test::Random rng(9);
  const test::State s = test::random_state(model, rng);
  std::vector<double> dq(n * n), dv(n * n), d(n), qp(model.nq), qm(model.nq), tp(n), tm(n);
  rnea_derivatives<double>(model, ws, s.q, s.qd, s.qdd, dq, dv);
  const double h = 1e-6;
  double worst = 0;
  for (int c = 0; c < n; ++c) {
    std::fill(d.begin(), d.end(), 0.0);
    d[c] = h;
    integrate<double>(model, s.q, d, qp);
    d[c] = -h;
    integrate<double>(model, s.q, d, qm);
    rnea<double>(model, ws, qp, s.qd, s.qdd, tp);
    rnea<double>(model, ws, qm, s.qd, s.qdd, tm);
    for (int r = 0; r < n; ++r)
      worst = std::max(worst, std::abs((tp[r] - tm[r]) / (2 * h) - dq[r * n + c]));
  }
  const double scale = std::max(max_abs(dq), 1.0);
  report("rnea_derivatives vs central differences along integrate, error / max|entry|",
         worst / scale);
  EXPECT_LE(worst / scale, 1e-6);  // truncation h^2 and rounding eps / h: about 1e-9
}

TEST_P(Derivatives, AbaDerivativesMatchForwardModeDifferentiation) {
  // forward mode through aba itself along q (tangent), v and tau
  const Model<double> model = GetParam().make();
  const Model<D> dual = model.cast<D>();
  const int n = model.nv;
  Workspace<double> ws(model);
  Workspace<D> dws(dual);
  test::Random rng(8);
  std::vector<double> dq(n * n), dv(n * n), Minv(n * n), fq(n * n), fv(n * n), ft(n * n);
  std::vector<D> qdd(n);
  double worst = 0;
  for (int sample = 0; sample < 5; ++sample) {
    const test::State s = test::random_state(model, rng);
    aba_derivatives<double>(model, ws, s.q, s.qd, s.tau, dq, dv, Minv);
    for (int c = 0; c < n; ++c) {
      std::vector<D> qd = constant(s.qd), tau = constant(s.tau);
      aba<D>(dual, dws, tangent(model, s.q, c), qd, tau, qdd);
      for (int r = 0; r < n; ++r) fq[r * n + c] = qdd[r].dx;
      qd[c].dx = 1;
      aba<D>(dual, dws, constant(s.q), qd, tau, qdd);
      for (int r = 0; r < n; ++r) fv[r * n + c] = qdd[r].dx;
      qd[c].dx = 0;
      tau[c].dx = 1;
      aba<D>(dual, dws, constant(s.q), qd, tau, qdd);
      for (int r = 0; r < n; ++r) ft[r * n + c] = qdd[r].dx;
    }
    const double cond = condition_number(model, ws, s.q);
    const double scale = std::max(max_abs(fq), max_abs(fv)) * cond;
    const double eq = scaled_error(dq, fq, n, scale), ev = scaled_error(dv, fv, n, scale),
                 et = scaled_error(Minv, ft, n, max_abs(ft) * cond);
    worst = std::max({worst, eq, ev, et});
    EXPECT_LE(eq, aba_bound_neps_cond) << "dqdd_dq at sample " << sample;
    EXPECT_LE(ev, aba_bound_neps_cond) << "dqdd_dv at sample " << sample;
    EXPECT_LE(et, aba_bound_neps_cond) << "Minv at sample " << sample;
  }
  report("aba_derivatives vs dual numbers, error / (nv eps max|entry| cond(M))", worst);
}

TEST_P(Derivatives, RootTranslationsLeaveDtauDqZeroAndTheProductSkipsThem) {
  // aba_derivatives' product leaves out the columns of d tau / dq that a root joint's
  // translations give (workspace.hpp): it must get the bits of the product over all their rows
  const Model<double> model = GetParam().make();
  const int n = model.nv;
  Workspace<double> ws(model);
  int translations = 0;
  for (int i = 0; i < model.nbodies; ++i)
    if (model.parent[i] < 0)
      translations += model.joint_type[i] == JointType::Free        ? 3
                      : model.joint_type[i] == JointType::Prismatic ? 1
                                                                    : 0;
  int skipped = 0;
  for (int c = 0; c < n; ++c)
    skipped += ws.product_begin[0][c] == ws.product_begin[0][c + 1] ? 1 : 0;
  EXPECT_EQ(skipped, translations);
  test::Random rng(10);
  std::vector<double> dq(n * n), dv(n * n), Minv(n * n), full(n * n);
  for (int sample = 0; sample < 5; ++sample) {
    const test::State s = test::random_state(model, rng);
    aba_derivatives<double>(model, ws, s.q, s.qd, s.tau, dq, dv, Minv);
    for (int c = 0; c < n; ++c) {
      if (ws.product_begin[0][c] != ws.product_begin[0][c + 1]) continue;
      for (int r = 0; r < n; ++r) ASSERT_EQ(ws.dtau_dq[r * n + c], 0.0) << r << ", " << c;
    }
    // d tau / dv's table lists every row of the paths and subtrees
    kernels::neg_product(n, ws.product_begin[1].data(), ws.product_rows[1].data(), Minv.data(),
                         ws.dtau_dq.data(), full.data());
    for (int e = 0; e < n * n; ++e)
      ASSERT_EQ(std::signbit(dq[e]), std::signbit(full[e])) << e;
    EXPECT_EQ(dq, full) << "sample " << sample;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, Derivatives, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace dyngen
