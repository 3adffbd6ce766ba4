// The frame functions in double against the truth: central differences of the runtime's
// frame_placements and com on MPFR numbers (256 bits), with a step of 2^-60 along
// dyngen::integrate, which leaves them exact to about 1e-36, on shared and stiff robots with all
// their frames. J is the first derivative of the placements along each direction of v, Jdot v
// their second derivative along the motion at qdd = 0, Jc the first derivative of the centre of
// mass; a floating robot's centroidal momentum matrix is the first six rows of the MPFR mass
// matrix (CRBA) moved to the centre of mass. Errors are norm-wise relative (Frobenius, all
// frames at once; Jdot v and h = A v, which may cancel, relative to their terms' size when that
// is larger) and printed on lines starting with "measured".
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/reference.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using numerics::Exact;

constexpr double eps = std::numeric_limits<double>::epsilon();

struct Robot {
  std::string path;
  bool floating_base;
};

/// Every URDF in tests/models on a fixed and on a floating base, and the stiff robots whose
/// geometry or mass spread bears on frames (tests/models/stiff/README.md): links down to 1.8e-15
/// of the first (tapered50_0p5), masses 1e6 apart (alternating20, light_limbs), inertias 1e-9
/// apart (thin_rods12).
std::vector<Robot> robots() {
  std::vector<Robot> all;
  for (const test::RobotFile& file : test::robot_files())
    for (const bool floating : {false, true}) all.push_back({file.path, floating});
  for (const std::string file :
       {"tapered50_0p5.yaml", "tapered50_0p9.yaml", "alternating20.yaml", "thin_rods12.yaml"})
    all.push_back({test::model_path("stiff/" + file), false});
  all.push_back({test::model_path("stiff/light_limbs.urdf"), true});
  return all;
}

/// A robot with all its frames, a random state, and both on MPFR numbers, with each free
/// joint's quaternion rescaled to unit length there so that R is a rotation and dR R^T is skew.
struct RobotAtState {
  explicit RobotAtState(const Robot& robot) : model(load(robot)), exact(model), ews(exact.model()) {
    mpfr::mpreal::set_default_prec(exact.bits());
    test::Random rng(13);
    s = test::random_state(model, rng);
    q = numerics::widen<double>(s.q);
    v = numerics::widen<double>(s.qd);
    normalize_configuration<Exact>(exact.model(), q);
  }

  static Model<double> load(const Robot& robot) {
    gen::LoadOptions options;
    options.floating_base = robot.floating_base;
    options.mimic_independent = true;
    options.all_frames = true;
    return gen::load_robot(robot.path, options).model;
  }

  std::string name(const Robot& robot) const {
    return std::filesystem::path(robot.path).filename().string() +
           (robot.floating_base ? " floating" : "") + " (nv " + std::to_string(model.nv) + ", " +
           std::to_string(model.frames.size()) + " frames)";
  }

  Model<double> model;
  numerics::ExactDynamics exact;
  Workspace<Exact> ews;
  numerics::State s;
  std::vector<Exact> q, v;
};

/// The difference step, after RobotAtState has set MPFR's precision.
Exact step() { return mpfr::ldexp(Exact(1), -60); }

/// The frames' rotations (row-major, 9 per frame) and origins (3 per frame) at q.
struct Placements {
  std::vector<Exact> R, p;
};

Placements placements(RobotAtState& c, const std::vector<Exact>& q) {
  const std::size_t nf = c.model.frames.size();
  Placements out{std::vector<Exact>(9 * nf), std::vector<Exact>(3 * nf)};
  frame_placements<Exact>(c.exact.model(), c.ews, q, out.R, out.p);
  return out;
}

/// Frame f's motion from the derivatives dR and dp of its placement (R, p): (dp, w) with
/// [w] = dR R^T in the base's axes, or both times R^T in the frame's own (frames.hpp's Local is
/// the base-axes quantity expressed in the frame's axes). For the second derivatives,
/// d2R R^T = [dw] + [w]^2 whose skew part is [dw], so the same gives (d2p, dw).
std::array<Exact, 6> motion(const Placements& at, const std::vector<Exact>& dR,
                            const std::vector<Exact>& dp, int f, JacobianAxes axes) {
  const Exact* R = &at.R[9 * f];
  const Exact* B = &dR[9 * f];
  Exact D[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      D[3 * i + j] =
          B[3 * i] * R[3 * j] + B[3 * i + 1] * R[3 * j + 1] + B[3 * i + 2] * R[3 * j + 2];
  std::array<Exact, 6> m = {dp[3 * f],         dp[3 * f + 1],     dp[3 * f + 2],
                            (D[7] - D[5]) / 2, (D[2] - D[6]) / 2, (D[3] - D[1]) / 2};
  if (axes == JacobianAxes::World) return m;
  std::array<Exact, 6> local;
  for (int k = 0; k < 6; k += 3)
    for (int i = 0; i < 3; ++i)
      local[k + i] = R[i] * m[k] + R[3 + i] * m[k + 1] + R[6 + i] * m[k + 2];
  return local;
}

/// qp, qm = q moved by +h and -h along direction col of v (integrate).
void neighbours(const RobotAtState& c, int col, const Exact& h, std::vector<Exact>& qp,
                std::vector<Exact>& qm) {
  std::vector<Exact> d(c.model.nv, Exact(0));
  d[col] = h;
  integrate<Exact>(c.exact.model(), c.q, d, qp);
  d[col] = -h;
  integrate<Exact>(c.exact.model(), c.q, d, qm);
}

constexpr JacobianAxes both_axes[] = {JacobianAxes::World, JacobianAxes::Local};

const char* axes_name(JacobianAxes axes) { return axes == JacobianAxes::World ? "world" : "local"; }

/// ||x - ref||_2 / max(||ref||_2, size), taken exactly: the error relative to the size of the
/// terms a result is summed from when it may cancel to less than they are.
double error_relative_to(const std::vector<double>& x, const std::vector<Exact>& ref,
                         const Exact& size) {
  Exact diff = 0, norm = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    diff += (Exact(x[k]) - ref[k]) * (Exact(x[k]) - ref[k]);
    norm += ref[k] * ref[k];
  }
  return (mpfr::sqrt(diff) / std::max(mpfr::sqrt(norm), size)).toDouble();
}

// Bounds about 4 times the largest error measured over every robot here at seven random states
// (seeds 1-6 and 13): J 3.2 eps (romeo floating, local), Jdot v 5.8 eps of its size (tapered50,
// local), Jc 2.4 eps (panda), A 4.7 eps (panda floating), h 2.3 eps of ||A|| ||v||. None grows
// with nv or with the frames' depth.
constexpr double jacobian_bound = 12;
constexpr double bias_bound = 24;
constexpr double com_bound = 10;
constexpr double centroidal_bound = 20;

TEST(FramesAccuracy, JacobiansAreTheDerivativesOfThePlacements) {
  for (const Robot& robot : robots()) {
    RobotAtState c(robot);
    const int nv = c.model.nv, nf = static_cast<int>(c.model.frames.size());
    const Exact h = step();
    std::vector<Exact> qp(c.q.size()), qm(c.q.size());
    std::vector<std::vector<Exact>> reference(2, std::vector<Exact>(6 * std::size_t(nf) * nv));
    for (int col = 0; col < nv; ++col) {
      neighbours(c, col, h, qp, qm);
      const Placements plus = placements(c, qp), minus = placements(c, qm), at = placements(c, c.q);
      std::vector<Exact> dR(at.R.size()), dp(at.p.size());
      for (std::size_t k = 0; k < dR.size(); ++k) dR[k] = (plus.R[k] - minus.R[k]) / (2 * h);
      for (std::size_t k = 0; k < dp.size(); ++k) dp[k] = (plus.p[k] - minus.p[k]) / (2 * h);
      for (int a = 0; a < 2; ++a)
        for (int f = 0; f < nf; ++f) {
          const std::array<Exact, 6> m = motion(at, dR, dp, f, both_axes[a]);
          for (int row = 0; row < 6; ++row)
            reference[a][(6 * std::size_t(f) + row) * nv + col] = m[row];
        }
    }
    Workspace<double> ws(c.model);
    std::vector<double> J(reference[0].size());
    std::cout << "measured " << c.name(robot) << ":";
    for (int a = 0; a < 2; ++a) {
      frame_jacobians<double>(c.model, ws, c.s.q, both_axes[a], J);
      const double error = numerics::relative_error(J, reference[a]);
      std::cout << " frame_jacobians " << axes_name(both_axes[a]) << " " << error << " ("
                << error / eps << " eps)";
      EXPECT_LE(error, jacobian_bound * eps) << robot.path << " " << axes_name(both_axes[a]);
    }
    std::cout << "\n";
  }
}

// Along q(t) = q (+) t v with v constant, qdd = 0: a free joint's v is its body's velocity in
// the body's coordinates, whose derivative is the body's spatial acceleration there (the
// v x v term vanishes), which ABA reports as qdd; integrate's SE(3) exponential moves with that
// velocity held constant. So the frame's acceleration is J qdd + Jdot v = Jdot v, and its
// classical acceleration and angular acceleration are the second derivatives of the placement.
// In the frame's axes the runtime gives these expressed there, R^T (p'', w'), which is not the
// derivative of J_local v = R^T (p', w): that is R^T (p'', w') - (R^T w) x J_local v.
TEST(FramesAccuracy, BiasAccelerationsAreTheSecondDerivativesAlongTheMotion) {
  for (const Robot& robot : robots()) {
    RobotAtState c(robot);
    const int nv = c.model.nv, nf = static_cast<int>(c.model.frames.size());
    const Exact h = step();
    std::vector<Exact> d(nv), qp(c.q.size()), qm(c.q.size());
    for (int k = 0; k < nv; ++k) d[k] = h * c.v[k];
    integrate<Exact>(c.exact.model(), c.q, d, qp);
    for (int k = 0; k < nv; ++k) d[k] = -h * c.v[k];
    integrate<Exact>(c.exact.model(), c.q, d, qm);
    const Placements plus = placements(c, qp), minus = placements(c, qm), at = placements(c, c.q);
    std::vector<Exact> dR(at.R.size()), d2R(at.R.size()), dp(at.p.size()), d2p(at.p.size());
    for (std::size_t k = 0; k < dR.size(); ++k) {
      dR[k] = (plus.R[k] - minus.R[k]) / (2 * h);
      d2R[k] = (plus.R[k] - 2 * at.R[k] + minus.R[k]) / (h * h);
    }
    for (std::size_t k = 0; k < dp.size(); ++k) {
      dp[k] = (plus.p[k] - minus.p[k]) / (2 * h);
      d2p[k] = (plus.p[k] - 2 * at.p[k] + minus.p[k]) / (h * h);
    }
    // The runtime adds w x v (v the origin's velocity) to the bodies' spatial bias
    // accelerations, terms of size |w| |v| that cancel to less when one joint's rate is small
    // beside another's (the double pendulum reaches 25 eps of its result at other seeds); the
    // error is relative to that size when it is the larger.
    Exact centripetal = 0;
    for (int f = 0; f < nf; ++f) {
      const std::array<Exact, 6> m = motion(at, dR, dp, f, JacobianAxes::World);
      centripetal +=
          (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]) * (m[3] * m[3] + m[4] * m[4] + m[5] * m[5]);
    }
    centripetal = mpfr::sqrt(centripetal);
    Workspace<double> ws(c.model);
    std::vector<double> Jdot_v(6 * std::size_t(nf));
    std::vector<Exact> reference(Jdot_v.size());
    std::cout << "measured " << c.name(robot) << ":";
    for (const JacobianAxes axes : both_axes) {
      for (int f = 0; f < nf; ++f) {
        const std::array<Exact, 6> m = motion(at, d2R, d2p, f, axes);
        for (int row = 0; row < 6; ++row) reference[6 * std::size_t(f) + row] = m[row];
      }
      frame_bias_accelerations<double>(c.model, ws, c.s.q, c.s.qd, axes, Jdot_v);
      const double error = error_relative_to(Jdot_v, reference, centripetal);
      std::cout << " frame_bias_accelerations " << axes_name(axes) << " " << error << " ("
                << error / eps << " eps; " << numerics::relative_error(Jdot_v, reference) / eps
                << " eps of the result)";
      EXPECT_LE(error, bias_bound * eps) << robot.path << " " << axes_name(axes);
    }
    std::cout << "\n";
  }
}

TEST(FramesAccuracy, CentreOfMassJacobianIsTheDerivativeOfTheCentre) {
  for (const Robot& robot : robots()) {
    RobotAtState c(robot);
    const int nv = c.model.nv;
    const Exact h = step();
    std::vector<Exact> qp(c.q.size()), qm(c.q.size()), cp(3), cm(3),
        unused(3 * std::size_t(nv)), reference(3 * std::size_t(nv));
    for (int col = 0; col < nv; ++col) {
      neighbours(c, col, h, qp, qm);
      com<Exact>(c.exact.model(), c.ews, qp, cp, unused);
      com<Exact>(c.exact.model(), c.ews, qm, cm, unused);
      for (int row = 0; row < 3; ++row) reference[row * nv + col] = (cp[row] - cm[row]) / (2 * h);
    }
    Workspace<double> ws(c.model);
    std::vector<double> centre(3), Jc(reference.size());
    com<double>(c.model, ws, c.s.q, centre, Jc);
    const double error = numerics::relative_error(Jc, reference);
    std::cout << "measured " << c.name(robot) << ": com Jc " << error << " (" << error / eps
              << " eps)\n";
    EXPECT_LE(error, com_bound * eps) << robot.path;
  }
}

// Orin, Goswami & Lee (2013): on a floating base, the free joint's rows of the mass matrix map
// v to the robot's momentum in the root body's coordinates (linear P_b first, then the angular
// L_b about its origin), so A = [E^T P_b; E^T (L_b - c_b x P_b)] with E the root's rotation and
// c_b the centre of mass in its coordinates, read off the same rows: M[0:3, 3:6] = -[m c_b]x.
TEST(FramesAccuracy, CentroidalMomentumMatrixIsTheMassMatrixsRootRowsAtTheCentre) {
  for (const Robot& robot : robots()) {
    if (!robot.floating_base) continue;
    RobotAtState c(robot);
    const int nv = c.model.nv;
    ASSERT_EQ(c.model.joint_type[0], JointType::Free) << robot.path;
    std::vector<Exact> M(std::size_t(nv) * nv), zero(nv, Exact(0));
    crba<Exact>(c.exact.model(), c.ews, c.q, M);
    forward_kinematics<Exact>(c.exact.model(), c.ews, c.q, zero);
    const Mat3<Exact> E = c.ews.X0[0].E;
    const Exact mass = M[0];
    const Vec3<Exact> centre{M[nv + 5] / mass, M[2 * nv + 3] / mass, M[4] / mass};
    std::vector<Exact> reference(6 * std::size_t(nv)), h_reference(6, Exact(0));
    for (int col = 0; col < nv; ++col) {
      const Vec3<Exact> P{M[col], M[nv + col], M[2 * nv + col]};
      const Vec3<Exact> L{M[3 * nv + col], M[4 * nv + col], M[5 * nv + col]};
      const Vec3<Exact> lin = mul_T(E, P), ang = mul_T(E, L - cross(centre, P));
      const Exact column[6] = {lin.x, lin.y, lin.z, ang.x, ang.y, ang.z};
      for (int row = 0; row < 6; ++row) {
        reference[row * nv + col] = column[row];
        h_reference[row] += column[row] * c.v[col];
      }
    }
    Workspace<double> ws(c.model);
    std::vector<double> A(reference.size()), momentum(6);
    centroidal<double>(c.model, ws, c.s.q, c.s.qd, A, momentum);
    const double error = numerics::relative_error(A, reference);
    // h = A v sums terms up to ||A|| ||v||, which may cancel to less
    Exact A_norm = 0, v_norm = 0;
    for (const Exact& x : reference) A_norm += x * x;
    for (const Exact& x : c.v) v_norm += x * x;
    const double h_error = error_relative_to(momentum, h_reference, mpfr::sqrt(A_norm * v_norm));
    std::cout << "measured " << c.name(robot) << ": centroidal A " << error << " (" << error / eps
              << " eps), h " << h_error << " (" << h_error / eps << " eps)\n";
    EXPECT_LE(error, centroidal_bound * eps) << robot.path;
    EXPECT_LE(h_error, centroidal_bound * eps) << robot.path;
  }
}

}  // namespace
}  // namespace dyngen
