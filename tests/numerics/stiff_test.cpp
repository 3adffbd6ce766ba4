// Stiff and extreme cases against the MPFR reference: the robots of tests/models/stiff (tapered
// chains, neighbours 1e6 apart in mass, rods spinning about their long axis, light hands and
// feet on a heavy floating base; see its README) and the shared robots, at random, stretched
// (q = 0), folded, fast (1e3 rad/s) and far-wound (q ~ 1e6 rad) states. RNEA, CRBA, ABA and
// CRBA + LDL^T run in double and in float; their norm-wise relative errors are held to bounds
// set from the measured errors with a stated margin, and the conditioning estimate is held to
// predicting them. Every figure is printed on a line starting with "measured". The reference is
// the runtime itself on MPFR numbers, so the bounds catch losses of precision; an algorithm's
// own mistake shows here only as ABA against CRBA + LDL^T (algorithms_test checks the algebra).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/conditioning.hpp"
#include "dyngen/numerics/ldlt.hpp"
#include "dyngen/numerics/reference.hpp"
#include "test_support.hpp"

namespace dyngen {
namespace {

using numerics::Exact;
using numerics::State;

/// Unit roundoff: half the distance from 1 to the next number.
template <class S>
constexpr double unit_roundoff = std::numeric_limits<S>::epsilon() / 2;

template <class S>
constexpr const char* scalar_name = std::is_same_v<S, double> ? "double" : "float";

/// Whether scalar S holds the model: a float model whose constants underflow is another robot,
/// with links of no inertia, where ABA divides by zero.
template <class S>
bool represents(const numerics::Conditioning& cond) {
  return std::is_same_v<S, double> || cond.float_unrepresentable == 0;
}

/// A number with three significant digits.
std::string sci(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

// ---- the robots ---------------------------------------------------------------------------

/// A robot of tests/models/stiff and its velocity size, as the README documents them.
struct StiffRobot {
  std::string file;
  bool floating_base;
  int nv;
};

const std::vector<StiffRobot> stiff_robots = {
    {"tapered50_0p5.yaml", false, 50},   {"tapered50_0p7.yaml", false, 50},
    {"tapered50_0p9.yaml", false, 50},   {"tapered100_0p5.yaml", false, 100},
    {"tapered100_0p7.yaml", false, 100}, {"tapered100_0p9.yaml", false, 100},
    {"tapered200_0p5.yaml", false, 200}, {"tapered200_0p7.yaml", false, 200},
    {"tapered200_0p9.yaml", false, 200}, {"alternating20.yaml", false, 20},
    {"thin_rods12.yaml", false, 12},     {"light_limbs.urdf", true, 28},
};

Model<double> load_stiff(const StiffRobot& robot) {
  gen::LoadOptions options;
  options.floating_base = robot.floating_base;
  return gen::load_robot(test::model_path("stiff/" + robot.file), options).model;
}

TEST(StiffRobots, LoadWithTheDocumentedSizeAndAbaDefined) {
  for (const StiffRobot& robot : stiff_robots) {
    const Model<double> model = load_stiff(robot);
    EXPECT_EQ(model.nv, robot.nv) << robot.file;
    EXPECT_TRUE(gen::joints_blocking_aba(model).empty()) << robot.file;
  }
}

// The reference runs the same algorithms and loses the same digits, which reference_bits adds
// back: at its precision and at 256 bits more, forward dynamics agrees to 30 digits on every
// stiff robot (tapered200_0p5 loses 120 digits: 256 bits alone would leave it none).
TEST(StiffRobots, ReferenceIsConvergedAtItsPrecision) {
  for (const StiffRobot& robot : stiff_robots) {
    const Model<double> model = load_stiff(robot);
    const numerics::Conditioning cond = numerics::estimate_conditioning(model, 16, 1);
    const int bits = numerics::reference_bits(cond.aba_digits_lost());
    numerics::ExactDynamics reference(model, bits), finer(model, bits + 256);
    test::Random rng(3);
    State s = test::random_state(model, rng);
    numerics::set_consistent_torques(finer, s);
    const std::vector<Exact> a = reference.aba(s.q, s.qd, s.tau), b = finer.aba(s.q, s.qd, s.tau);
    Exact diff = 0, norm = 0;
    for (std::size_t k = 0; k < a.size(); ++k) diff += (a[k] - b[k]) * (a[k] - b[k]), norm += b[k] * b[k];
    const double difference = mpfr::sqrt(diff / norm).toDouble();
    std::cout << "measured " << robot.file << ": reference " << bits << " bits, relative difference to "
              << bits + 256 << " bits " << sci(difference) << "\n";
    EXPECT_LT(difference, 1e-30) << robot.file;
  }
}

// ---- the states ---------------------------------------------------------------------------

enum class StateKind { Random, Stretched, Folded, Fast, FarWound };
constexpr StateKind state_kinds[] = {StateKind::Random, StateKind::Stretched, StateKind::Folded,
                                     StateKind::Fast, StateKind::FarWound};

const char* kind_name(StateKind kind) {
  switch (kind) {
    case StateKind::Random: return "random";
    case StateKind::Stretched: return "stretched";
    case StateKind::Folded: return "folded";
    case StateKind::Fast: return "fast";
    case StateKind::FarWound: return "far-wound";
  }
  return "?";
}

constexpr double folded_angle = std::numbers::pi - 0.01;  // each link turned back on its parent
constexpr double fast_speed = 1e3;                         // rad/s (m/s for a free joint)
constexpr double far_angle = 1e6;                          // rad

/// A random state (random_state) with the kind's change to qd or to the q of revolute joints
/// (prismatic ones are stretched too, otherwise they keep their random q, as free joints keep
/// their random position and orientation). Torques are set later.
State make_state(const Model<double>& model, StateKind kind, test::Random& rng) {
  State s = test::random_state(model, rng);
  for (int i = 0; i < model.nbodies; ++i) {
    if (model.joint_type[i] == JointType::Free) continue;
    double& q = s.q[model.q_index[i]];
    if (kind == StateKind::Stretched) q = 0;
    if (!is_revolute(model.joint_type[i])) continue;
    if (kind == StateKind::Folded) q = i % 2 == 0 ? folded_angle : -folded_angle;
    if (kind == StateKind::FarWound) q += far_angle;
  }
  if (kind == StateKind::Fast)
    for (double& v : s.qd) v = rng.uniform(-fast_speed, fast_speed);
  return s;
}

// ---- errors -------------------------------------------------------------------------------

enum Algorithm { Rnea, Crba, Aba, CrbaLdlt, algorithm_count };
constexpr const char* algorithm_names[] = {"rnea", "crba", "aba", "crba+ldlt"};

/// Relative errors by algorithm.
using Errors = std::array<double, algorithm_count>;

/// The exact outputs at one state: tau = RNEA(q, qd, qdd), M(q), qdd = ABA(q, qd, tau).
struct Reference {
  std::vector<Exact> tau, M, qdd;
};

Reference reference(numerics::ExactDynamics& exact, const State& s) {
  return {exact.rnea(s.q, s.qd, s.qdd), exact.crba(s.q), exact.aba(s.q, s.qd, s.tau)};
}

/// How the exact torques split into tau = M qdd + h, h = RNEA(q, qd, 0) (gravity and velocity
/// products).
struct TorqueSplit {
  double bias_ratio;    // ||h|| / ||M qdd||: forward dynamics subtracts h from tau, losing this
  double cancellation;  // (||M qdd|| + ||h||) / ||tau||: RNEA adds M qdd and h, losing this
};

TorqueSplit torque_split(numerics::ExactDynamics& exact, const State& s, const Reference& ref) {
  const std::vector<Exact> h = exact.rnea(s.q, s.qd, std::vector<double>(s.qd.size(), 0.0));
  Exact hh = 0, Mqdd = 0, tau = 0;
  for (std::size_t k = 0; k < h.size(); ++k) {
    hh += h[k] * h[k];
    Mqdd += (ref.tau[k] - h[k]) * (ref.tau[k] - h[k]);
    tau += ref.tau[k] * ref.tau[k];
  }
  return {mpfr::sqrt(hh / Mqdd).toDouble(),
          ((mpfr::sqrt(Mqdd) + mpfr::sqrt(hh)) / mpfr::sqrt(tau)).toDouble()};
}

/// The runtime in scalar S on the model's constants rounded to S.
template <class S>
class Runtime {
 public:
  explicit Runtime(const Model<double>& model)
      : model_(model.cast<S>()), ws_(model_), ldlt_(model_) {}

  /// Errors of the four algorithms at the state (its values rounded to S) against `ref`.
  Errors errors(const State& s, const Reference& ref) {
    const int n = model_.nv;
    const std::vector<S> q = test::cast_vector<S>(s.q), qd = test::cast_vector<S>(s.qd),
                         qdd = test::cast_vector<S>(s.qdd), tau = test::cast_vector<S>(s.tau);
    std::vector<S> tau_out(n), M(static_cast<std::size_t>(n) * n), qdd_aba(n), qdd_ldlt(n);
    rnea<S>(model_, ws_, q, qd, qdd, tau_out);
    crba<S>(model_, ws_, q, M);
    aba<S>(model_, ws_, q, qd, tau, qdd_aba);
    numerics::crba_ldlt_forward_dynamics<S>(model_, ldlt_, q, qd, tau, qdd_ldlt);
    Errors e;
    e[Rnea] = numerics::relative_error(tau_out, ref.tau);
    e[Crba] = numerics::relative_error(M, ref.M);
    e[Aba] = numerics::relative_error(qdd_aba, ref.qdd);
    e[CrbaLdlt] = numerics::relative_error(qdd_ldlt, ref.qdd);
    return e;
  }

 private:
  Model<S> model_;
  Workspace<S> ws_;
  numerics::LdltWorkspace<S> ldlt_;
};

// ---- the bounds ---------------------------------------------------------------------------
// Each bound is a measured property with a margin of about 3 (u is the unit roundoff of the
// scalar, 1.1e-16 for double and 6.0e-8 for float; the figures are the largest over every
// robot, state and scalar here, printed as "errors / bound scales").

// RNEA: a sum of inertial and bias torques, with no solve: its error is a few u times the
// cancellation of that sum, whatever the conditioning (measured at most 18 u times the
// cancellation, tapered50_0p9 in double).
constexpr double rnea_bound_u = 50;

// CRBA: sums of composite inertias, little cancellation in the norm, not growing with n
// (measured at most 8.7 u, alternating20 in double).
constexpr double crba_bound_u = 32;

// ABA and CRBA + LDL^T both lose the digits of ABA's smallest pivot (aba_digits_lost, from the
// conditioning estimate's random samples) and the bias ratio to the subtraction of h: at every
// state their error is below forward_dynamics_bound_u u 10^aba_digits_lost max(1, bias ratio)
// wherever that is below 1 (measured at most 101, alternating20 stretched in float: its pivots
// at q = 0 are smaller than at the random samples).
constexpr double forward_dynamics_bound_u = 300;

// The conditioning estimate predicts forward dynamics' error: over random states (those it
// samples) the worst error of ABA and of CRBA + LDL^T is below prediction_factor times
// 10^-(digits kept) = u 10^aba_digits_lost where that is below 1. Unless the robot is graded
// (its articulated inertias span graded_inertia_range or more), it is also above 1 /
// prediction_factor times that, or above 1 / prediction_factor where no digit is predicted to
// remain (measured: 0.035 to 65 times the prediction, solo12 and alternating20 in float; where
// no digit is predicted, at least 1: none, as predicted). On the graded tapered chains (spans of
// 2e14 and more) the errors are 1e-4 to 1e-105 times the prediction: with classical
// accelerations (rnea.hpp) their bias forces carry no cancelling linear-velocity terms, and the
// pivots' digits are an upper bound only.
constexpr double prediction_factor = 200;
constexpr double graded_inertia_range = 1e10;

// digits_lost (cond(M) or 1 / pivot_min, the larger) bounds every algorithm: over random states
// each error is below digits_lost_bound_u u 10^digits_lost (measured at most 1.6, the double
// pendulum in float; for the stiff robots at most 0.04, cond(M) being far above 1 / pivot_min).
constexpr double digits_lost_bound_u = 5;

// ABA is as accurate as CRBA + LDL^T: where both keep a digit, their worst errors are within a
// factor aba_vs_ldlt_factor of each other (measured: ABA's 0.44 times, iiwa14 in float, to 3.3
// times, iiwa14 floating in double).
constexpr double aba_vs_ldlt_factor = 8;

// ---- the test -----------------------------------------------------------------------------

struct Case {
  std::string name;
  std::function<Model<double>()> load;
  int states_per_kind;  // the MPFR reference's CRBA costs O(n^2) per state
};

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

std::vector<Case> cases() {
  std::vector<Case> all;
  for (const StiffRobot& robot : stiff_robots) {
    std::string name = robot.file.substr(0, robot.file.find('.'));
    if (robot.floating_base) name += "_floating";
    const int states = robot.nv <= 30 ? 10 : robot.nv <= 50 ? 6 : robot.nv <= 100 ? 3 : 2;
    all.push_back({name, [=] { return load_stiff(robot); }, states});
  }
  for (const test::RobotFile& robot : test::robot_files()) {
    all.push_back({robot.name, [=] { return test::load_for_aba(robot); }, 6});
    all.push_back({robot.name + "_floating", [=] { return test::load_for_aba(robot, true); }, 6});
  }
  return all;
}

constexpr std::size_t kind_count = std::size(state_kinds);

/// One scalar's worst errors, by state kind, and the largest ratios of errors to the bounds'
/// scales.
struct Tally {
  std::array<Errors, kind_count> by_kind{};
  Errors all{};
  double rnea = 0, crba = 0, forward_dynamics = 0;  // error / the bound's scale

  const Errors& random() const { return by_kind[static_cast<int>(StateKind::Random)]; }
};

/// Checks one state's errors in scalar S against the bounds and adds them to the tally.
template <class S>
void check_and_tally(const std::string& where, const numerics::Conditioning& cond,
                     StateKind kind, const TorqueSplit& split, const Errors& e, Tally& tally) {
  const double u = unit_roundoff<S>;
  const bool representable = represents<S>(cond);
  for (const Algorithm a : {Rnea, Crba, Aba, CrbaLdlt}) {
    if (representable || a == Rnea || a == Crba) {
      EXPECT_TRUE(std::isfinite(e[a])) << where << " " << algorithm_names[a];
    }
  }

  const double rnea_scale = u * split.cancellation;
  EXPECT_LE(e[Rnea], rnea_bound_u * rnea_scale) << where;
  EXPECT_LE(e[Crba], crba_bound_u * u) << where;
  const double fd_scale =
      u * std::pow(10.0, cond.aba_digits_lost()) * std::max(1.0, split.bias_ratio);
  if (representable && forward_dynamics_bound_u * fd_scale < 1) {
    EXPECT_LE(e[Aba], forward_dynamics_bound_u * fd_scale) << where;
    EXPECT_LE(e[CrbaLdlt], forward_dynamics_bound_u * fd_scale) << where;
    tally.forward_dynamics = std::max({tally.forward_dynamics, e[Aba] / fd_scale,
                                       e[CrbaLdlt] / fd_scale});
  }
  tally.rnea = std::max(tally.rnea, e[Rnea] / rnea_scale);
  tally.crba = std::max(tally.crba, e[Crba] / u);
  Errors& of_kind = tally.by_kind[static_cast<int>(kind)];
  for (const Algorithm a : {Rnea, Crba, Aba, CrbaLdlt}) {
    of_kind[a] = std::max(of_kind[a], e[a]);
    tally.all[a] = std::max(tally.all[a], e[a]);
  }
}

class Stiff : public ::testing::TestWithParam<Case> {
 protected:
  void print(const std::string& line) const {
    std::cout << "measured " << GetParam().name << ": " << line << "\n";
  }

  /// Prints one scalar's figures and holds its worst errors to the conditioning's prediction.
  template <class S>
  void report_and_predict(const numerics::Conditioning& cond, const Tally& tally,
                          const std::array<double, kind_count>& bias_ratio) const {
    const std::string scalar = scalar_name<S>;
    for (const StateKind kind : state_kinds) {
      const Errors& e = tally.by_kind[static_cast<int>(kind)];
      print(scalar + " " + kind_name(kind) + ": rnea " + sci(e[Rnea]) + ", crba " + sci(e[Crba]) +
            ", aba " + sci(e[Aba]) + ", crba+ldlt " + sci(e[CrbaLdlt]) + " (bias ratio up to " +
            sci(bias_ratio[static_cast<int>(kind)]) + ")");
    }
    const double u = unit_roundoff<S>;
    const double predicted = u * std::pow(10.0, cond.aba_digits_lost());
    const double lost = u * std::pow(10.0, cond.digits_lost());
    const Errors& random = tally.random();
    print(scalar + " worst: aba " + sci(tally.all[Aba]) + ", crba+ldlt " +
          sci(tally.all[CrbaLdlt]) + " (aba / crba+ldlt " +
          sci(tally.all[Aba] / tally.all[CrbaLdlt]) + ")");
    print(scalar + " random states: aba " + sci(random[Aba]) + ", crba+ldlt " +
          sci(random[CrbaLdlt]) + "; predicted u 10^aba_digits_lost " + sci(predicted) +
          " (errors / prediction " + sci(random[Aba] / predicted) + ", " +
          sci(random[CrbaLdlt] / predicted) + "); largest error / (u 10^digits_lost) " +
          sci(*std::max_element(random.begin(), random.end()) / lost));
    print(scalar + " errors / bound scales: rnea " + sci(tally.rnea) + ", crba " +
          sci(tally.crba) + ", forward dynamics " + sci(tally.forward_dynamics));

    for (const Algorithm a : {Rnea, Crba, Aba, CrbaLdlt}) {
      if (represents<S>(cond) || a == Rnea || a == Crba) {
        EXPECT_LE(random[a], digits_lost_bound_u * lost) << scalar << " " << algorithm_names[a];
      }
    }
    const bool graded = cond.inertia_range >= graded_inertia_range;
    for (const Algorithm a : {Aba, CrbaLdlt}) {
      if (predicted < 1) {
        EXPECT_LE(random[a], prediction_factor * predicted) << scalar << " " << algorithm_names[a];
      }
      if (graded) continue;
      if (predicted < 1) {
        EXPECT_GE(random[a], predicted / prediction_factor) << scalar << " " << algorithm_names[a];
      } else {
        EXPECT_GE(random[a], 1 / prediction_factor) << scalar << " " << algorithm_names[a];
      }
    }
    if (tally.all[Aba] < 1 && tally.all[CrbaLdlt] < 1) {
      EXPECT_LE(tally.all[Aba], aba_vs_ldlt_factor * tally.all[CrbaLdlt]) << scalar;
      EXPECT_LE(tally.all[CrbaLdlt], aba_vs_ldlt_factor * tally.all[Aba]) << scalar;
    }
  }
};

TEST_P(Stiff, ErrorsFollowTheConditioning) {
  const Case& c = GetParam();
  const Model<double> model = c.load();
  // the generator's samples and seed, so that the figures are those dyngen prints
  const numerics::Conditioning cond = numerics::estimate_conditioning(model, 16, 1);
  print("nv " + std::to_string(model.nv) + ", cond(M) max " + sci(cond.cond_M_max) + " median " +
        sci(cond.cond_M_median) + ", pivot_min " + sci(cond.pivot_min) + " at " +
        cond.pivot_joint + ", digits_lost " + sci(cond.digits_lost()) + ", aba_digits_lost " +
        sci(cond.aba_digits_lost()) + ", inertia_range " + sci(cond.inertia_range) +
        ", float_unrepresentable " +
        std::to_string(cond.float_unrepresentable));

  numerics::ExactDynamics exact(model, numerics::reference_bits(cond.aba_digits_lost()));
  Runtime<double> runtime_double(model);
  Runtime<float> runtime_float(model);
  Tally tally_double, tally_float;
  std::array<double, kind_count> bias_ratio{};
  test::Random rng(2);  // not the estimate's seed: the states are new to it
  for (const StateKind kind : state_kinds)
    for (int k = 0; k < c.states_per_kind; ++k) {
      State s = make_state(model, kind, rng);
      numerics::set_consistent_torques(exact, s);
      const Reference ref = reference(exact, s);
      const TorqueSplit split = torque_split(exact, s, ref);
      // float's inputs are the state rounded to float; its reference is computed there
      const State s_float = numerics::round_to_float(s);
      const Reference ref_float = reference(exact, s_float);
      const std::string where = c.name + " " + kind_name(kind) + " state " + std::to_string(k);
      check_and_tally<double>(where + " double", cond, kind, split,
                              runtime_double.errors(s, ref), tally_double);
      check_and_tally<float>(where + " float", cond, kind, torque_split(exact, s_float, ref_float),
                             runtime_float.errors(s_float, ref_float), tally_float);
      double& bias = bias_ratio[static_cast<int>(kind)];
      bias = std::max(bias, split.bias_ratio);
    }
  report_and_predict<double>(cond, tally_double, bias_ratio);
  report_and_predict<float>(cond, tally_float, bias_ratio);
}

INSTANTIATE_TEST_SUITE_P(Robots, Stiff, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace dyngen
