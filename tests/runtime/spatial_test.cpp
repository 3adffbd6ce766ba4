// Every kernel of spatial.hpp against its dense 6x6 (or 3x3) definition from Featherstone's
// spatial_v2, on seeded random arguments with entries in [-1, 1].
#include "dyngen/spatial.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>

#include "test_support.hpp"

namespace dyngen {
namespace {

using test::crf;
using test::crm;
using test::dense;
using test::skew;
using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;
using Vector6 = test::Vector6<double>;
using Matrix6 = test::Matrix6<double>;

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr int samples = 500;

/// Random arguments for the kernels.
class Sampler {
 public:
  explicit Sampler(std::uint64_t seed) : rng_(seed) {}
  double scalar() { return rng_.uniform(-1, 1); }
  Vec3<double> vec() { return {scalar(), scalar(), scalar()}; }
  Mat3<double> mat() {
    return {scalar(), scalar(), scalar(), scalar(), scalar(),
            scalar(), scalar(), scalar(), scalar()};
  }
  Sym3<double> sym() { return {scalar(), scalar(), scalar(), scalar(), scalar(), scalar()}; }
  Motion<double> motion() { return {vec(), vec()}; }
  Force<double> force() { return {vec(), vec()}; }
  /// A rotation from a random unit quaternion, through Eigen rather than the runtime.
  Mat3<double> rotation() {
    const Eigen::Quaterniond quat =
        Eigen::Quaterniond(scalar(), scalar(), scalar(), scalar()).normalized();
    const Matrix3 R = quat.toRotationMatrix();
    return {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)};
  }
  Xform<double> xform() { return {rotation(), vec()}; }
  RigidInertia<double> rigid() { return {rng_.uniform(0.1, 1), vec(), sym()}; }
  ArticulatedInertia<double> articulated() { return {sym(), mat(), sym()}; }

 private:
  test::Random rng_;
};

/// Largest entry-wise error, in multiples of eps times the reference's largest entry (or 1).
template <class A, class B>
double error_in_eps(const A& actual, const B& reference) {
  const double scale = std::max(1.0, reference.cwiseAbs().maxCoeff());
  return (actual - reference).cwiseAbs().maxCoeff() / (eps * scale);
}

// Each kernel is a few dot products of at most a dozen terms of entries <= 1, so a correct one
// is within a few eps of the dense product (measured: at most 7, for X^T I X); a wrong term or
// sign is off by O(1), some 1e15 eps.
constexpr double bound_eps = 32;

TEST(Spatial, AdditionAndSubtractionAreExact) {
  Sampler s(1);
  for (int k = 0; k < samples; ++k) {
    const Vec3<double> a = s.vec(), b = s.vec();
    EXPECT_EQ(dense(a + b), (dense(a) + dense(b)).eval());
    EXPECT_EQ(dense(a - b), (dense(a) - dense(b)).eval());
    const Motion<double> m1 = s.motion(), m2 = s.motion();
    EXPECT_EQ(dense(m1 + m2), (dense(m1) + dense(m2)).eval());
    const Force<double> f1 = s.force(), f2 = s.force();
    EXPECT_EQ(dense(f1 + f2), (dense(f1) + dense(f2)).eval());
    EXPECT_EQ(dense(f1 - f2), (dense(f1) - dense(f2)).eval());
    const Mat3<double> A = s.mat(), B = s.mat();
    EXPECT_EQ(dense(A + B), (dense(A) + dense(B)).eval());
    const Sym3<double> P = s.sym(), Q = s.sym();
    EXPECT_EQ(dense(P + Q), (dense(P) + dense(Q)).eval());
    const RigidInertia<double> I1 = s.rigid(), I2 = s.rigid();
    EXPECT_EQ(dense(I1 + I2), (dense(I1) + dense(I2)).eval());
    const ArticulatedInertia<double> A1 = s.articulated(), A2 = s.articulated();
    EXPECT_EQ(dense(A1 + A2), (dense(A1) + dense(A2)).eval());
  }
}

TEST(Spatial, VectorProducts) {
  Sampler s(2);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Vec3<double> a = s.vec(), b = s.vec();
    const double k_scale = s.scalar();
    EXPECT_EQ(dense(scale(a, k_scale)), (dense(a) * k_scale).eval());
    worst = std::max(worst, std::abs(dot(a, b) - dense(a).dot(dense(b))) / eps);
    worst = std::max(worst, error_in_eps(dense(cross(a, b)), dense(a).cross(dense(b))));
    worst = std::max(worst, error_in_eps(dense(cross(a, b)), skew(dense(a)) * dense(b)));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, MatrixProducts) {
  Sampler s(3);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Mat3<double> A = s.mat(), B = s.mat();
    const Sym3<double> P = s.sym();
    const Vec3<double> v = s.vec();
    worst = std::max(worst, error_in_eps(dense(mul(A, v)), dense(A) * dense(v)));
    worst = std::max(worst, error_in_eps(dense(mul_T(A, v)), dense(A).transpose() * dense(v)));
    worst = std::max(worst, error_in_eps(dense(mul(P, v)), dense(P) * dense(v)));
    worst = std::max(worst, error_in_eps(dense(mul(A, B)), dense(A) * dense(B)));
    worst = std::max(worst, error_in_eps(dense(mul_skew(A, v)), dense(A) * skew(dense(v))));
    worst = std::max(worst, error_in_eps(dense(mul_skew(P, v)), dense(P) * skew(dense(v))));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, RotateTransposed) {
  Sampler s(4);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Mat3<double> E = s.rotation(), A = s.mat();
    const Sym3<double> P = s.sym();
    const Matrix3 Ed = dense(E);
    worst = std::max(worst, error_in_eps(dense(rotate_T(E, P)), Ed.transpose() * dense(P) * Ed));
    worst = std::max(worst, error_in_eps(dense(rotate_T(E, A)), Ed.transpose() * dense(A) * Ed));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, ApplyMotionIsXTimesM) {
  Sampler s(5);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Xform<double> X = s.xform();
    const Motion<double> m = s.motion();
    worst = std::max(worst, error_in_eps(dense(apply_motion(X, m)), dense(X) * dense(m)));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, ApplyForceTransposedIsXTransposeTimesF) {
  Sampler s(6);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Xform<double> X = s.xform();
    const Force<double> f = s.force();
    worst =
        std::max(worst, error_in_eps(dense(apply_force_T(X, f)), dense(X).transpose() * dense(f)));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, DenseTransformIsPluckerTransform) {
  // The dense reference itself: X^-1 = [E^T 0; skew(r) E^T E^T] (RBDA eq. 2.26), and the
  // force transform X* = X^-T.
  Sampler s(7);
  for (int k = 0; k < 20; ++k) {
    const Xform<double> X = s.xform();
    const Matrix3 ET = dense(X.E).transpose();
    Matrix6 inverse;
    inverse << ET, Matrix3::Zero(), skew(dense(X.r)) * ET, ET;
    EXPECT_LE(error_in_eps(dense(X) * inverse, Matrix6::Identity()), bound_eps);
  }
}

TEST(Spatial, ComposeIsProduct) {
  Sampler s(8);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Xform<double> X_ab = s.xform(), X_bc = s.xform();
    worst = std::max(worst, error_in_eps(dense(compose(X_ab, X_bc)), dense(X_ab) * dense(X_bc)));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, RigidInertiaTransformIsXTransposeIX) {
  Sampler s(9);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Xform<double> X = s.xform();
    const RigidInertia<double> I = s.rigid();
    const Matrix6 Xd = dense(X);
    worst =
        std::max(worst, error_in_eps(dense(apply_inertia_T(X, I)), Xd.transpose() * dense(I) * Xd));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, ArticulatedInertiaTransformIsXTransposeIX) {
  Sampler s(10);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Xform<double> X = s.xform();
    const ArticulatedInertia<double> A = s.articulated();
    const Matrix6 Xd = dense(X);
    worst =
        std::max(worst, error_in_eps(dense(apply_inertia_T(X, A)), Xd.transpose() * dense(A) * Xd));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, InertiaTimesMotion) {
  Sampler s(11);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Motion<double> m = s.motion();
    const RigidInertia<double> I = s.rigid();
    const ArticulatedInertia<double> A = s.articulated();
    worst = std::max(worst, error_in_eps(dense(mul(I, m)), dense(I) * dense(m)));
    worst = std::max(worst, error_in_eps(dense(mul(A, m)), dense(A) * dense(m)));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, RigidInertiaAsArticulatedIsExact) {
  Sampler s(12);
  for (int k = 0; k < samples; ++k) {
    const RigidInertia<double> I = s.rigid();
    EXPECT_EQ(dense(articulated(I)), dense(I));
  }
}

TEST(Spatial, CrossProducts) {
  Sampler s(13);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Motion<double> v = s.motion(), m = s.motion();
    const Force<double> f = s.force();
    worst = std::max(worst, error_in_eps(dense(cross_motion(v, m)), crm(dense(v)) * dense(m)));
    worst = std::max(worst, error_in_eps(dense(cross_force(v, f)), crf(dense(v)) * dense(f)));
  }
  EXPECT_LE(worst, bound_eps);
}

TEST(Spatial, CrossProductsAreInvariantUnderTransforms) {
  // X (v x m) = (X v) x (X m) and X* (v x* f) = (X v) x* (X* f), all through the runtime's
  // kernels: ties the cross products to the transform convention, so a sign flipped
  // consistently in a kernel and in its dense definition is still caught. X* = X^-T is
  // applied as (X^-1)^T with X^-1 = rot(E^T) xlt(-E r).
  Sampler s(14);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    const Xform<double> X = s.xform();
    const Mat3<double>& E = X.E;
    const Xform<double> X_inv{{E.xx, E.yx, E.zx, E.xy, E.yy, E.zy, E.xz, E.yz, E.zz},
                              scale(mul(E, X.r), -1.0)};
    const Motion<double> v = s.motion(), m = s.motion();
    const Force<double> f = s.force();
    worst =
        std::max(worst, error_in_eps(dense(cross_motion(apply_motion(X, v), apply_motion(X, m))),
                                     dense(apply_motion(X, cross_motion(v, m)))));
    worst = std::max(worst,
                     error_in_eps(dense(cross_force(apply_motion(X, v), apply_force_T(X_inv, f))),
                                  dense(apply_force_T(X_inv, cross_force(v, f)))));
  }
  // two chains of products of entries up to ~3 in size: a few times the single-kernel bound
  EXPECT_LE(worst, 4 * bound_eps);
}

// solve() against Eigen's LDL^T with pivoting, on positive definite matrices B B^T + 0.1 1
// (condition numbers up to about 1e3); the error bound is the usual eps cond(A) one.
TEST(Spatial, SolveArticulatedInertia) {
  Sampler s(12);
  double worst = 0;
  for (int k = 0; k < samples; ++k) {
    Matrix6 B;
    for (int e = 0; e < 36; ++e) B(e / 6, e % 6) = s.scalar();
    const Matrix6 A = B * B.transpose() + 0.1 * Matrix6::Identity();
    const ArticulatedInertia<double> IA{{A(0, 0), A(1, 1), A(2, 2), A(0, 1), A(0, 2), A(1, 2)},
                                        {A(0, 3), A(0, 4), A(0, 5), A(1, 3), A(1, 4), A(1, 5),
                                         A(2, 3), A(2, 4), A(2, 5)},
                                        {A(3, 3), A(4, 4), A(5, 5), A(3, 4), A(3, 5), A(4, 5)}};
    ASSERT_EQ(dense(IA), A);
    const Force<double> b = s.force();
    const Vector6 reference = A.ldlt().solve(dense(b));
    const double cond = A.norm() * A.inverse().norm();
    worst = std::max(worst, error_in_eps(dense(solve(IA, b)), reference) / cond);
  }
  EXPECT_LE(worst, 4.0);
}

}  // namespace
}  // namespace dyngen
