// Helpers shared by the test suites (runtime, generator, generated code): seeded random
// numbers and states (dyngen/numerics/random.hpp), random chains built through the runtime's
// ModelBuilder, the shared robot files, dense spatial algebra and a heap-allocation counter.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dyngen/model.hpp"
#include "dyngen/numerics/random.hpp"
#include "robot.hpp"

namespace dyngen::test {

using numerics::Random;
using numerics::random_state;
using numerics::random_unit_quaternion;
using numerics::State;

/// A random serial chain of n links built through dyngen::ModelBuilder, the same for the same
/// seed.
///
/// planar: joints about +z or -z (links along x, each joint at the end of the previous link),
/// about one in four prismatic along an in-plane axis, gravity (0, -9.81, 0), centres of mass
/// at 15-40% or 60-85% of the link length (never at half length) with a small lateral offset.
/// spatial: joint axes exactly +-x, +-y, +-z or general unit vectors (about half each), about
/// one in five prismatic, random rpy and xyz origins, random centres of mass, gravity
/// (0, 0, -9.81).
/// Both: masses in [0.2, 3) kg; rotational inertias positive definite and satisfying the
/// triangle inequality (they are those of a box-shaped mass distribution), in a random frame.
Model<double> make_random_chain(int n, std::uint64_t seed, bool planar);

/// The same values in another scalar type.
template <class T>
std::vector<T> cast_vector(const std::vector<double>& x) {
  return std::vector<T>(x.begin(), x.end());
}

/// Path of a file in tests/models.
std::string model_path(const std::string& file);

/// One of the shared robot URDFs in tests/models, the options it loads with (panda, pr2,
/// baxter and romeo have mimic joints) and those under which ABA is defined for it (romeo:
/// lock_massless too, since its hands have no mass and would make D_i = 0).
struct RobotFile {
  std::string name;  // file name without extension
  std::string path;
  gen::LoadOptions options;      // mimic joints accepted as independent joints, like the peers
  gen::LoadOptions aba_options;  // and romeo's massless joints locked
};

/// Every URDF in tests/models, in alphabetical order.
std::vector<RobotFile> robot_files();

/// Loads a robot file with its ABA options, on a floating base if asked.
Model<double> load_for_aba(const RobotFile& robot, bool floating_base = false);

/// A test's name for a file of tests/models on a fixed or floating base:
/// "coverage/ball_chain.yaml", true -> "ball_chain_floating".
std::string case_name(const std::string& file, bool floating_base);

/// The model of a file in tests/models with the default options, on a floating base and with a
/// frame on every link if asked.
Model<double> load_model(const std::string& file, bool floating_base = false,
                         bool all_frames = false);

// ---- dense definitions (Featherstone's spatial_v2), independent of the runtime's kernels ----

template <class S>
using Vector6 = Eigen::Matrix<S, 6, 1>;
template <class S>
using Matrix6 = Eigen::Matrix<S, 6, 6>;

template <class S>
Eigen::Matrix<S, 3, 1> dense(const Vec3<S>& v) {
  return {v.x, v.y, v.z};
}

template <class S>
Eigen::Matrix<S, 3, 3> dense(const Mat3<S>& A) {
  Eigen::Matrix<S, 3, 3> D;
  D << A.xx, A.xy, A.xz, A.yx, A.yy, A.yz, A.zx, A.zy, A.zz;
  return D;
}

template <class S>
Eigen::Matrix<S, 3, 3> dense(const Sym3<S>& A) {
  Eigen::Matrix<S, 3, 3> D;
  D << A.xx, A.xy, A.xz, A.xy, A.yy, A.yz, A.xz, A.yz, A.zz;
  return D;
}

/// skew(v) w = v x w
template <class S>
Eigen::Matrix<S, 3, 3> skew(const Eigen::Matrix<S, 3, 1>& v) {
  Eigen::Matrix<S, 3, 3> D;
  D << S(0), -v.z(), v.y(), v.z(), S(0), -v.x(), -v.y(), v.x(), S(0);
  return D;
}

template <class S>
Vector6<S> dense(const Motion<S>& m) {
  Vector6<S> d;
  d << dense(m.ang), dense(m.lin);
  return d;
}

template <class S>
Vector6<S> dense(const Force<S>& f) {
  Vector6<S> d;
  d << dense(f.ang), dense(f.lin);
  return d;
}

/// The motion transform X = rot(E) xlt(r) = [E 0; -E skew(r) E] (RBDA eq. 2.28).
template <class S>
Matrix6<S> dense(const Xform<S>& X) {
  const Eigen::Matrix<S, 3, 3> E = dense(X.E);
  Matrix6<S> D;
  D << E, Eigen::Matrix<S, 3, 3>::Zero(), -E * skew(dense(X.r)), E;
  return D;
}

/// [I skew(h); skew(h)^T m 1] with h = m c (RBDA eq. 2.63 about the frame origin).
template <class S>
Matrix6<S> dense(const RigidInertia<S>& I) {
  const Eigen::Matrix<S, 3, 3> H = skew(dense(I.h));
  Matrix6<S> D;
  D << dense(I.I), H, H.transpose(), I.m * Eigen::Matrix<S, 3, 3>::Identity();
  return D;
}

/// [I H; H^T M]
template <class S>
Matrix6<S> dense(const ArticulatedInertia<S>& A) {
  Matrix6<S> D;
  D << dense(A.I), dense(A.H), dense(A.H).transpose(), dense(A.M);
  return D;
}

/// crm(v): v x m = crm(v) m for motions (RBDA eq. 2.31).
template <class S>
Matrix6<S> crm(const Vector6<S>& v) {
  const Eigen::Matrix<S, 3, 3> w = skew<S>(v.template head<3>());
  Matrix6<S> D;
  D << w, Eigen::Matrix<S, 3, 3>::Zero(), skew<S>(v.template tail<3>()), w;
  return D;
}

/// crf(v) = -crm(v)^T: v x* f = crf(v) f for forces (RBDA eq. 2.32).
template <class S>
Matrix6<S> crf(const Vector6<S>& v) {
  return -crm(v).transpose();
}

/// A std::vector as an Eigen vector (a copy).
/// A span over an Eigen vector, for the runtime's functions.
inline std::span<const double> view(const Eigen::VectorXd& x) {
  return {x.data(), static_cast<std::size_t>(x.size())};
}
inline std::span<double> view(Eigen::VectorXd& x) {
  return {x.data(), static_cast<std::size_t>(x.size())};
}

/// ||x - reference|| / ||reference||, Euclidean (Frobenius for matrices).
inline double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).norm() / reference.norm();
}

template <class S>
Eigen::Matrix<S, Eigen::Dynamic, 1> to_eigen(const std::vector<S>& x) {
  return Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, 1>>(x.data(), x.size());
}

/// A row-major n x n array (the runtime's mass-matrix layout) as an Eigen matrix.
template <class S>
Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> to_eigen(const std::vector<S>& M, int n) {
  return Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      M.data(), n, n);
}

// ---- heap allocations -----------------------------------------------------------------------

/// Heap allocations (every replaced operator new and new[]) since the program started.
/// Defined by the dyngen_alloc_counter object library, which replaces the global allocation
/// functions; only test binaries that link it may call this.
std::size_t allocation_count();

/// Counts heap allocations between its construction and each call of count():
///
///   AllocationCounter c;
///   rnea<double>(model, ws, q, qd, qdd, tau);
///   EXPECT_EQ(c.count(), 0u);
///
/// Requires linking dyngen_alloc_counter. Counts allocations from every thread.
class AllocationCounter {
 public:
  AllocationCounter() : start_(allocation_count()) {}
  std::size_t count() const { return allocation_count() - start_; }

 private:
  std::size_t start_;
};

}  // namespace dyngen::test
