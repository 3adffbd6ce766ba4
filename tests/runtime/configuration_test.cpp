// integrate and difference (configuration.hpp) against what defines them: integrate(q, v) is
// where the constant body velocity v carries q in unit time (the flow of configuration_rate,
// here by RK4), and difference inverts it both ways, the shorter way round; their Jacobians
// against central differences in tangent coordinates. On a humanoid with a
// free joint and eight ball joints (MJCF), solo12 on a free joint, and ur5, at rotation angles
// from 1e-9 rad (the series) through the series' cut-overs to near pi.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

struct Robot {
  std::string file;
  bool floating_base;
};

std::vector<Robot> robots() {
  return {{"mjcf/ball.xml", false}, {"solo12.urdf", true}, {"ur5.urdf", false}};
}

Model<double> load(const Robot& r) {
  gen::LoadOptions o;
  o.floating_base = r.floating_base;
  return gen::load_robot(test::model_path(r.file), o).model;
}

using Vector = std::vector<double>;

Vector integrated(const Model<double>& m, const Vector& q, const Vector& v) {
  Vector out(m.nq);
  integrate<double>(m, q, v, out);
  return out;
}

Vector differenced(const Model<double>& m, const Vector& q0, const Vector& q1) {
  Vector out(m.nv);
  difference<double>(m, q0, q1, out);
  return out;
}

/// v with each free and ball joint's rotation vector scaled to length `angle`.
Vector with_angles(const Model<double>& m, Vector v, double angle) {
  for (int i = 0; i < m.nbodies; ++i) {
    const int o = quaternion_offset(m.joint_type[i]);
    if (o < 0) continue;
    double* w = &v[m.v_index[i] + o];
    const double n = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (int k = 0; k < 3; ++k) w[k] *= angle / n;
  }
  return v;
}

/// max |a - b| over q's entries, each quaternion compared with b's or its negative (the same
/// rotation).
double q_distance(const Model<double>& m, const Vector& a, const Vector& b) {
  double d = 0;
  for (int i = 0; i < m.nbodies; ++i) {
    const int o = quaternion_offset(m.joint_type[i]);
    const int n = o < 0 ? 1 : o + 4, start = m.q_index[i];
    for (int k = 0; k < (o < 0 ? 1 : o); ++k)
      d = std::max(d, std::abs(a[start + k] - b[start + k]));
    if (o < 0) continue;
    double same = 0, opposite = 0;
    for (int k = o; k < n; ++k) {
      same = std::max(same, std::abs(a[start + k] - b[start + k]));
      opposite = std::max(opposite, std::abs(a[start + k] + b[start + k]));
    }
    d = std::max(d, std::min(same, opposite));
  }
  return d;
}

double max_abs_difference(const Vector& a, const Vector& b) {
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

const double angles[] = {1e-9, 1e-4, 0.999, 1.0, 1.001, 1.999, 2.0, 2.001, 3.1};

TEST(Configuration, DifferenceInvertsIntegrate) {
  for (const Robot& r : robots()) {
    const Model<double> m = load(r);
    test::Random rng(11);
    for (int s = 0; s < 20; ++s)
      for (const double angle : angles) {
        const Vector q = test::random_state(m, rng).q;
        const Vector v = with_angles(m, rng.vector(m.nv, -2, 2), angle);
        const Vector back = differenced(m, q, integrated(m, q, v));
        EXPECT_LT(max_abs_difference(back, v), 1e-13) << r.file << " angle " << angle;
      }
  }
}

TEST(Configuration, IntegrateInvertsDifferenceTheShorterWayRound) {
  for (const Robot& r : robots()) {
    const Model<double> m = load(r);
    test::Random rng(12);
    for (int s = 0; s < 200; ++s) {
      const Vector q0 = test::random_state(m, rng).q, q1 = test::random_state(m, rng).q;
      const Vector d = differenced(m, q0, q1);
      EXPECT_LT(q_distance(m, integrated(m, q0, d), q1), 1e-13) << r.file;
      for (int i = 0; i < m.nbodies; ++i) {
        const int o = quaternion_offset(m.joint_type[i]);
        if (o < 0) continue;
        const double* w = &d[m.v_index[i] + o];
        EXPECT_LE(std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), std::numbers::pi + 1e-15);
      }
    }
    // from q to itself: zero, exactly
    const Vector q = test::random_state(m, rng).q;
    EXPECT_EQ(max_abs_difference(differenced(m, q, q), Vector(m.nv, 0.0)), 0) << r.file;
  }
}

/// q carried by the constant velocity v for unit time: RK4 on qdot = configuration_rate(q, v)
/// in n steps, the quaternions normalised at the end.
Vector flow(const Model<double>& m, Vector q, const Vector& v, int n) {
  const double h = 1.0 / n;
  auto rate = [&](const Vector& x) {
    Vector qd(m.nq);
    configuration_rate<double>(m, x, v, qd);
    return qd;
  };
  auto step = [&](const Vector& x, const Vector& k, double f) {
    Vector y = x;
    for (int j = 0; j < m.nq; ++j) y[j] += f * k[j];
    return y;
  };
  for (int s = 0; s < n; ++s) {
    const Vector k1 = rate(q), k2 = rate(step(q, k1, h / 2)), k3 = rate(step(q, k2, h / 2)),
                 k4 = rate(step(q, k3, h));
    for (int j = 0; j < m.nq; ++j) q[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  normalize_configuration<double>(m, q);
  return q;
}

// RK4's error at 2000 steps is about 1e-14 for these rates; 3e-12 leaves room for rounding over
// the steps, and a wrong coefficient of V(w) (the free joints' translation) is off by 1e-2
TEST(Configuration, IntegrateIsTheFlowOfAConstantVelocity) {
  for (const Robot& r : robots()) {
    const Model<double> m = load(r);
    test::Random rng(13);
    for (int s = 0; s < 3; ++s)
      for (const double angle : {0.5, 2.5}) {
        const Vector q = test::random_state(m, rng).q;
        const Vector v = with_angles(m, rng.vector(m.nv, -2, 2), angle);
        EXPECT_LT(q_distance(m, integrated(m, q, v), flow(m, q, v, 2000)), 3e-12)
            << r.file << " angle " << angle;
      }
  }
}

/// Column j of a Jacobian in tangent coordinates by central differences: (f(+h e_j) -
/// f(-h e_j)) / 2h, f returning a tangent vector.
template <class F>
Vector central_column(int nv, int j, double h, const F& f) {
  Vector e(nv, 0.0);
  e[j] = h;
  const Vector plus = f(e);
  for (double& x : e) x = -x;
  const Vector minus = f(e);
  Vector column(nv);
  for (int r = 0; r < nv; ++r) column[r] = (plus[r] - minus[r]) / (2 * h);
  return column;
}

/// max over entries of |J - Jfd| with Jfd's columns from column(j).
template <class F>
double jacobian_error(const Vector& J, int nv, const F& column) {
  double worst = 0;
  for (int j = 0; j < nv; ++j) {
    const Vector c = column(j);
    for (int r = 0; r < nv; ++r) worst = std::max(worst, std::abs(J[r * nv + j] - c[r]));
  }
  return worst;
}

// h = 1e-5: truncation about h^2 times the third derivatives (order 1 here), rounding about
// 1e-16 / h; a wrong sign or block is off by order 1
constexpr double h = 1e-5, fd_bound = 1e-8;

TEST(Configuration, IntegrateDerivativesMatchCentralDifferences) {
  for (const Robot& r : robots()) {
    const Model<double> m = load(r);
    const int nv = m.nv;
    test::Random rng(14);
    for (const double angle : angles) {
      const Vector q = test::random_state(m, rng).q;
      const Vector v = with_angles(m, rng.vector(nv, -2, 2), angle);
      Vector dq(nv * nv), dv(nv * nv);
      integrate_derivatives<double>(m, q, v, dq, dv);
      const Vector end = integrated(m, q, v);
      const double by_q = jacobian_error(dq, nv, [&](int j) {
        return central_column(nv, j, h, [&](const Vector& e) {
          return differenced(m, end, integrated(m, integrated(m, q, e), v));
        });
      });
      const double by_v = jacobian_error(dv, nv, [&](int j) {
        return central_column(nv, j, h, [&](const Vector& e) {
          Vector ve = v;
          for (int k = 0; k < nv; ++k) ve[k] += e[k];
          return differenced(m, end, integrated(m, q, ve));
        });
      });
      EXPECT_LT(by_q, fd_bound) << r.file << " angle " << angle;
      EXPECT_LT(by_v, fd_bound) << r.file << " angle " << angle;
    }
  }
}

TEST(Configuration, DifferenceDerivativesMatchCentralDifferences) {
  for (const Robot& r : robots()) {
    const Model<double> m = load(r);
    const int nv = m.nv;
    test::Random rng(15);
    for (const double angle : angles) {
      // q_target at the angle's distance from q, and from pairs of random configurations
      const Vector q = test::random_state(m, rng).q;
      for (const Vector& q1 : {integrated(m, q, with_angles(m, rng.vector(nv, -2, 2), angle)),
                               test::random_state(m, rng).q}) {
        Vector d0(nv * nv), d1(nv * nv);
        difference_derivatives<double>(m, q, q1, d0, d1);
        const double by_q = jacobian_error(d0, nv, [&](int j) {
          return central_column(
              nv, j, h, [&](const Vector& e) { return differenced(m, integrated(m, q, e), q1); });
        });
        const double by_target = jacobian_error(d1, nv, [&](int j) {
          return central_column(
              nv, j, h, [&](const Vector& e) { return differenced(m, q, integrated(m, q1, e)); });
        });
        EXPECT_LT(by_q, fd_bound) << r.file << " angle " << angle;
        EXPECT_LT(by_target, fd_bound) << r.file << " angle " << angle;
      }
    }
  }
}

}  // namespace
}  // namespace dyngen
