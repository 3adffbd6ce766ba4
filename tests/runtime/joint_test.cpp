// The joint model (joint.hpp) against dense definitions: XJ(q) X_tree with XJ = rot(R(k, q)^T)
// for revolute joints (R from Eigen's angle-axis) and xlt(k q) for prismatic ones; S qd and
// S^T f, and which columns of S translate.
#include "dyngen/joint.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>
#include <numbers>

#include "test_support.hpp"

namespace dyngen {
namespace {

using test::dense;
using test::skew;
using Matrix3 = Eigen::Matrix3d;
using Matrix6 = test::Matrix6<double>;
using Vector6 = test::Vector6<double>;

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double pi = std::numbers::pi;

/// A one-body model with the given joint and a random tree transform.
Model<double> one_joint(JointType type, const Vec3<double>& axis, test::Random& rng) {
  const Eigen::Quaterniond quat(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1),
                                rng.uniform(-1, 1));
  const Matrix3 E = quat.normalized().toRotationMatrix();
  Model<double> model;
  model.nbodies = model.nq = model.nv = 1;
  model.parent = {-1};
  model.joint_type = {type};
  model.joint_axis = {axis};
  model.X_tree = {
      {{E(0, 0), E(0, 1), E(0, 2), E(1, 0), E(1, 1), E(1, 2), E(2, 0), E(2, 1), E(2, 2)},
       {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)}}};
  model.I = {{1, {}, {1, 1, 1, 0, 0, 0}}};
  model.q_index = {0};
  model.v_index = {0};
  if (type == JointType::Free) model.nq = 7, model.nv = 6;
  return model;
}

/// XJ(q) X_tree from its definition (RBDA Table 4.1): the child frame is the parent's turned
/// by q about k, or moved by k q.
Matrix6 dense_joint_transform(const Model<double>& model, double q) {
  const Eigen::Vector3d k = dense(model.joint_axis[0]);
  Matrix6 XJ = Matrix6::Identity();
  if (is_revolute(model.joint_type[0])) {
    const Matrix3 E = Eigen::AngleAxisd(q, k).toRotationMatrix().transpose();
    XJ.topLeftCorner<3, 3>() = E;
    XJ.bottomRightCorner<3, 3>() = E;
  } else {
    XJ.bottomLeftCorner<3, 3>() = -skew(Eigen::Vector3d(k * q));
  }
  return XJ * dense(model.X_tree[0]);
}

/// Largest entry-wise error relative to the reference's largest entry (or 1).
double error(const Matrix6& actual, const Matrix6& reference) {
  return (actual - reference).cwiseAbs().maxCoeff() /
         std::max(1.0, reference.cwiseAbs().maxCoeff());
}

struct AxisCase {
  JointType type;
  Vec3<double> axis;
};

const AxisCase axis_cases[] = {
    {JointType::RevoluteX, {1, 0, 0}},         {JointType::RevoluteX, {-1, 0, 0}},
    {JointType::RevoluteY, {0, 1, 0}},         {JointType::RevoluteY, {0, -1, 0}},
    {JointType::RevoluteZ, {0, 0, 1}},         {JointType::RevoluteZ, {0, 0, -1}},
    {JointType::Revolute, {0.48, -0.6, 0.64}}, {JointType::Revolute, {0, 0, 1}},
    {JointType::Prismatic, {0, 0, 1}},         {JointType::Prismatic, {0.48, -0.6, 0.64}},
};

TEST(Joint, TransformMatchesDefinition) {
  test::Random rng(1);
  for (const AxisCase& c : axis_cases) {
    double worst = 0;
    for (int k = 0; k < 200; ++k) {
      const Model<double> model = one_joint(c.type, c.axis, rng);
      const double q = rng.uniform(-2 * pi, 2 * pi);
      worst = std::max(worst,
                       error(dense(joint_transform(model, 0, &q)), dense_joint_transform(model, q)));
    }
    // a handful of products per entry, and a rotation E orthogonal to a few eps, which the
    // prismatic identity E skew(E^T k q) = skew(k q) E magnifies by |q| <= 2 pi (measured: at
    // most 2 eps for revolute joints, 5 eps for prismatic ones)
    EXPECT_LE(worst, 16 * eps) << joint_type_name(c.type) << " axis " << dense(c.axis).transpose();
  }
}

TEST(Joint, AxisKindsHaveExactZerosAndOnes) {
  // With X_tree = identity, an axis-aligned joint's rotation keeps its axis exactly.
  test::Random rng(2);
  Model<double> model = one_joint(JointType::RevoluteX, {1, 0, 0}, rng);
  model.X_tree[0] = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
  const double q = 0.7;
  for (const AxisCase& c : axis_cases) {
    if (c.type == JointType::Revolute || c.type == JointType::Prismatic) continue;
    model.joint_type[0] = c.type;
    model.joint_axis[0] = c.axis;
    const Matrix3 E = dense(joint_transform(model, 0, &q).E);
    const Eigen::Vector3d k = dense(c.axis);
    EXPECT_EQ(E * k, k) << joint_type_name(c.type);
    EXPECT_EQ(E.transpose() * k, k) << joint_type_name(c.type);
  }
}

TEST(Joint, MotionAndProjection) {
  test::Random rng(3);
  for (const AxisCase& c : axis_cases) {
    const Model<double> model = one_joint(c.type, c.axis, rng);
    Vector6 S = Vector6::Zero();
    (is_revolute(c.type) ? S.head<3>() : S.tail<3>()) = dense(c.axis);
    for (int k = 0; k < 20; ++k) {
      const double qd = rng.uniform(-3, 3);
      const double entries[6] = {qd};  // as many as the free-joint branch reads (-Warray-bounds)
      EXPECT_EQ(dense(joint_motion(model, 0, entries)), (S * qd).eval());
      EXPECT_EQ(dense(joint_column(model, 0, 0)), S);
      EXPECT_EQ(is_translation_column(c.type, 0), S.head<3>().isZero());
      EXPECT_EQ(dense(joint_force(model, 0, entries)), (S * qd).eval());
      const Force<double> f{{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)},
                            {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)}};
      double STf = 0;
      joint_project(model, 0, f, &STf);
      EXPECT_NEAR(STf, S.dot(dense(f)), 4 * eps);
    }
  }
}

// A free joint: XJ = rot(R^T) xlt(p) for the rotation R of the quaternion, S = [0 1; 1 0]
// (v entries are linear, then angular; spatial vectors angular, then linear).
TEST(Joint, FreeJointMatchesDefinition) {
  test::Random rng(4);
  Matrix6 S = Matrix6::Zero();
  S.topRightCorner<3, 3>().setIdentity();
  S.bottomLeftCorner<3, 3>().setIdentity();
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    const Model<double> model = one_joint(JointType::Free, {0, 0, 0}, rng);
    const Eigen::Quaterniond quat = Eigen::Quaterniond(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                                       rng.uniform(-1, 1), rng.uniform(-1, 1))
                                        .normalized();
    const Eigen::Vector3d p(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    const double q[7] = {p.x(), p.y(), p.z(), quat.w(), quat.x(), quat.y(), quat.z()};
    const Matrix3 E = quat.toRotationMatrix().transpose();
    Matrix6 XJ = Matrix6::Zero();
    XJ.topLeftCorner<3, 3>() = E;
    XJ.bottomRightCorner<3, 3>() = E;
    XJ.bottomLeftCorner<3, 3>() = -E * skew(p);
    worst = std::max(worst, error(dense(joint_transform(model, 0, q)),
                                  (XJ * dense(model.X_tree[0])).eval()));

    double qd[6];
    for (double& x : qd) x = rng.uniform(-3, 3);
    const Eigen::Map<const Vector6> qd6(qd);
    EXPECT_EQ(dense(joint_motion(model, 0, qd)), (S * qd6).eval());
    EXPECT_EQ(dense(joint_force(model, 0, qd)), (S * qd6).eval());
    for (int d = 0; d < 6; ++d) {
      EXPECT_EQ(dense(joint_column(model, 0, d)), S.col(d));
      EXPECT_EQ(is_translation_column(JointType::Free, d), S.col(d).head<3>().isZero()) << d;
    }
    const Force<double> f{{qd[0], qd[1], qd[2]}, {qd[3], qd[4], qd[5]}};
    double STf[6];
    joint_project(model, 0, f, STf);
    EXPECT_EQ(Eigen::Map<const Vector6>(STf), (S.transpose() * dense(f)).eval());
  }
  EXPECT_LE(worst, 16 * eps);
}

}  // namespace
}  // namespace dyngen
