// dyngen_frames_bench (bench/README.md, "Frames"): the generated frame_placements,
// frame_jacobians, frame_accelerations, com and centroidal of the packages of
// bench/CMakeLists.txt's frame entries, beside the runtime's same functions, orocos-KDL's solvers
// and MuJoCo's pipeline for the same quantities. ns per call on seeded random states that change
// every call. Before timing, every implementation is checked against the runtime at one state,
// so that a benchmark of wrong code fails instead of passing. Then it prints and, given a path,
// writes a Markdown table: the medians, the ratios over the generated code and the operations of
// one call (add, mul, div, neg, sin and cos), generated and runtime; and the time of the
// generated joint_trig alone, the sines and cosines that both the generated code and the runtime
// pay in every function.
//
// usage: dyngen_frames_bench [Google Benchmark flags] [TABLE.md]
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <kdl/chainjnttojacdotsolver.hpp>
#include <kdl/jntarrayvel.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treejnttojacsolver.hpp>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "dyngen/numerics/random.hpp"
#include "emit.hpp"
#include "frame_packages.hpp"
#include "kdl_peer.hpp"
#include "median_collector.hpp"
#include "mujoco_peer.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace dyngen::bench {
namespace {

using numerics::Random;
using numerics::State;

constexpr int state_count = 64;  // cycled through, so the inputs change every call
constexpr std::uint64_t seed = 20261126;
constexpr double tolerance = 1e-8;  // relative, against the runtime, as dyngen_bench's

enum Function { Placements, Jacobians, Accelerations, Com, Centroidal };
constexpr Function functions[] = {Placements, Jacobians, Accelerations, Com, Centroidal};
constexpr const char* function_names[] = {"frame_placements", "frame_jacobians",
                                          "frame_accelerations", "com", "centroidal"};

enum Implementation { Generated, Runtime, Kdl, Mujoco };
constexpr const char* implementation_names[] = {"generated", "runtime", "kdl", "mujoco"};

Eigen::Map<const Eigen::VectorXd> vec(const std::vector<double>& x) {
  return {x.data(), static_cast<Eigen::Index>(x.size())};
}

Eigen::MatrixXd rows(const std::vector<double>& x, int r, int c, int offset = 0) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      x.data() + offset, r, c);
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> names;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) names.push_back(name);
  return names;
}

/// The two output arrays of one call, in dyngen's layout (frames.hpp): R, p; J; Jdot_v; c, Jc;
/// A, h.
struct Outputs {
  std::vector<double> first, second;

  Outputs(Function f, int nv, int nframes) {
    const std::size_t sizes[][2] = {{9u * nframes, 3u * nframes},
                                    {6u * nframes * nv, 0},
                                    {6u * nframes, 0},
                                    {3, 3u * nv},
                                    {6u * nv, 6}};
    first.resize(sizes[f][0]), second.resize(sizes[f][1]);
  }
};

/// The runtime's function f at (q, v).
void runtime_call(const Model<double>& model, Workspace<double>& ws, Function f,
                  std::span<const double> q, std::span<const double> v, Outputs& out) {
  switch (f) {
    case Placements: frame_placements<double>(model, ws, q, out.first, out.second); break;
    case Jacobians: frame_jacobians<double>(model, ws, q, JacobianAxes::World, out.first); break;
    case Accelerations:
      frame_bias_accelerations<double>(model, ws, q, v, JacobianAxes::World, out.first);
      break;
    case Com: com<double>(model, ws, q, out.first, out.second); break;
    case Centroidal: centroidal<double>(model, ws, q, v, out.first, out.second); break;
  }
}

/// Everything timed for one package; the implementations keep references into it.
struct Subject {
  const FramePackage& package;
  gen::Robot robot;
  std::vector<std::string> frames;
  std::vector<State> states;
  Workspace<double> ws;
  std::vector<Outputs> out;  // per function

  explicit Subject(const FramePackage& p)
      : package(p),
        robot(gen::load_robot(p.input, options(p))),
        frames(split(p.frames)),
        ws(robot.model) {
    Random rng(seed);
    for (int k = 0; k < state_count; ++k) states.push_back(numerics::random_state(model(), rng));
    for (Function f : functions) out.emplace_back(f, model().nv, nframes());
  }

  const Model<double>& model() const { return robot.model; }
  int nframes() const { return static_cast<int>(frames.size()); }

  static gen::LoadOptions options(const FramePackage& p) {
    gen::LoadOptions o;
    o.floating_base = p.floating_base;
    o.mimic_independent = true;
    o.frames = split(p.frames);
    return o;
  }

  void generated(Function f, int k) {
    const State& s = states[k];
    Outputs& o = out[f];
    switch (f) {
      case Placements: package.frame_placements(s.q.data(), o.first.data(), o.second.data()); break;
      case Jacobians: package.frame_jacobians(s.q.data(), o.first.data()); break;
      case Accelerations:
        package.frame_accelerations(s.q.data(), s.qd.data(), o.first.data());
        break;
      case Com: package.com(s.q.data(), o.first.data(), o.second.data()); break;
      case Centroidal:
        package.centroidal(s.q.data(), s.qd.data(), o.first.data(), o.second.data());
        break;
    }
  }

  void runtime(Function f, int k) {
    runtime_call(model(), ws, f, states[k].q, states[k].qd, out[f]);
  }
};

/// MuJoCo's functions for each quantity, on a copy of the peer's model (tests/peers/mujoco) with
/// its own mjData. Each call copies the state into mjData, as a caller would. Frames are the
/// URDF links' bodies (the peer keeps every link a body). Gravity is off: mj_rnePostConstraint
/// starts the world's acceleration at -gravity, and nothing else here reads it.
///   frame_placements:    mj_kinematics; xmat and xpos of each frame's body.
///   frame_jacobians:     mj_kinematics, mj_comPos (mj_jac reads cdof and subtree_com), mj_jacBody.
///   frame_accelerations: mj_kinematics, mj_comPos, mj_comVel, mj_rnePostConstraint (cacc, with
///                        qacc the free joint's bias: dyngen's qdd = 0), mj_objectAcceleration
///                        (mjOBJ_XBODY: at the body's origin).
///   com:                 mj_kinematics, mj_comPos (subtree_com), mj_jacSubtreeCom.
///   centroidal:          mj_kinematics, mj_comPos, mj_comVel, mj_subtreeVel: the momentum h
///                        only (subtree_linvel times mass, subtree_angmom); MuJoCo has no
///                        centroidal momentum matrix A.
class MujocoFrames {
 public:
  MujocoFrames(Subject& s)
      : subject_(s),
        peer_(s.package.input, s.model(), s.robot.locked, s.package.floating_base),
        m_(mj_copyModel(nullptr, peer_.mj()), mj_deleteModel),
        d_(nullptr, mj_deleteData) {
    mjModel* m = m_.get();
    mju_zero3(m->opt.gravity);
    d_.reset(mj_makeData(m));
    root_ = peer_.body(0);  // the subtree of dyngen's first body: every body that moves
    for (const std::string& name : s.frames) {
      const int body = mj_name2id(m, mjOBJ_BODY, name.c_str());
      if (body < 0) throw std::runtime_error("MuJoCo has no body " + name);
      body_.push_back(body);
    }
    for (const State& state : s.states) {
      const std::vector<double> qpos = peer_.qpos(state.q);
      const Eigen::VectorXd qvel = peer_.velocity_map(state.q) * vec(state.qd),
                            qacc = peer_.free_joint_bias(state.q, state.qd);
      qpos_.insert(qpos_.end(), qpos.begin(), qpos.end());
      qvel_.insert(qvel_.end(), qvel.begin(), qvel.end());
      qacc_.insert(qacc_.end(), qacc.begin(), qacc.end());
    }
    const int nv = m->nv, nf = s.nframes();
    R_.resize(9 * nf), p_.resize(3 * nf), jacp_.resize(3 * nf * nv), jacr_.resize(3 * nf * nv);
    acc_.resize(6 * nf);
  }

  void run(Function f, int k) {
    const mjModel* m = m_.get();
    mjData* d = d_.get();
    const int nq = m->nq, nv = m->nv, nf = static_cast<int>(body_.size());
    mju_copy(d->qpos, &qpos_[k * nq], nq);
    mj_kinematics(m, d);
    if (f != Placements) mj_comPos(m, d);
    switch (f) {
      case Placements:
        for (int i = 0; i < nf; ++i) {
          mju_copy(&R_[9 * i], d->xmat + 9 * body_[i], 9);
          mju_copy3(&p_[3 * i], d->xpos + 3 * body_[i]);
        }
        break;
      case Jacobians:
        for (int i = 0; i < nf; ++i)
          mj_jacBody(m, d, &jacp_[3 * i * nv], &jacr_[3 * i * nv], body_[i]);
        break;
      case Accelerations:
        mju_copy(d->qvel, &qvel_[k * nv], nv);
        mju_copy(d->qacc, &qacc_[k * nv], nv);
        mj_comVel(m, d);
        mj_rnePostConstraint(m, d);
        for (int i = 0; i < nf; ++i)
          mj_objectAcceleration(m, d, mjOBJ_XBODY, body_[i], &acc_[6 * i], 0);
        break;
      case Com:
        mju_copy3(c_, d->subtree_com + 3 * root_);
        mj_jacSubtreeCom(m, d, jacp_.data(), root_);
        break;
      case Centroidal:
        mju_copy(d->qvel, &qvel_[k * nv], nv);
        mj_comVel(m, d);
        mj_subtreeVel(m, d);
        mju_scl3(h_, d->subtree_linvel + 3 * root_, m->body_subtreemass[root_]);
        mju_copy3(h_ + 3, d->subtree_angmom + 3 * root_);
        break;
    }
  }

  /// Relative difference to the runtime at state k, in dyngen's coordinates: J = J_mujoco A with
  /// v_mujoco = A v (mujoco_peer.hpp); mj_objectAcceleration gives angular, then linear.
  double error(Function f, int k) {
    run(f, k);
    const State& s = subject_.states[k];
    Workspace<double> ws(subject_.model());
    Outputs expected(f, subject_.model().nv, subject_.nframes());
    runtime_call(subject_.model(), ws, f, s.q, s.qd, expected);
    const Eigen::MatrixXd A = peer_.velocity_map(s.q);
    const int nv = m_->nv, nf = static_cast<int>(body_.size());
    Eigen::VectorXd got(expected.first.size() + expected.second.size());
    switch (f) {
      case Placements: got << vec(R_), vec(p_); break;
      case Jacobians:
        for (int i = 0; i < nf; ++i) {
          Eigen::MatrixXd J(6, nv);
          J << rows(jacp_, 3, nv, 3 * i * nv), rows(jacr_, 3, nv, 3 * i * nv);
          got.segment(6 * i * nv, 6 * nv) = (J * A).reshaped<Eigen::RowMajor>();
        }
        break;
      case Accelerations:
        for (int i = 0; i < nf; ++i)
          got.segment(6 * i, 6) << vec(acc_).segment(6 * i + 3, 3), vec(acc_).segment(6 * i, 3);
        break;
      case Com:
        got << Eigen::Map<const Eigen::Vector3d>(c_),
            (rows(jacp_, 3, nv) * A).reshaped<Eigen::RowMajor>();
        break;
      case Centroidal:
        return test::relative_error(Eigen::Map<const Eigen::VectorXd>(h_, 6), vec(expected.second));
    }
    Eigen::VectorXd want(got.size());
    want << vec(expected.first), vec(expected.second);
    return test::relative_error(got, want);
  }

 private:
  Subject& subject_;
  test::mujoco_peer::MujocoRobot peer_;
  std::unique_ptr<mjModel, decltype(&mj_deleteModel)> m_;
  std::unique_ptr<mjData, decltype(&mj_deleteData)> d_;
  int root_;
  std::vector<int> body_;                          // [nframes]
  std::vector<double> qpos_, qvel_, qacc_;         // state k at k * nq or k * nv
  std::vector<double> R_, p_, jacp_, jacr_, acc_;  // per frame
  mjtNum c_[3], h_[6];
};

/// orocos-KDL's solvers on the peer's tree (tests/peers/kdl: a floating base as a virtual 6-DoF
/// chain) and its own random states, drawn in KDL's coordinates:
///   frame_placements:    TreeFkSolverPos_recursive::JntToCart for each frame;
///   frame_jacobians:     TreeJntToJacSolver::JntToJac for each frame (reference point at the
///                        segment's tip, base axes: JacobianAxes::World);
///   frame_accelerations: ChainJntToJacDotSolver on the chain to the frame (its hybrid
///                        representation: base axes at the tip), for a fixed base with one frame;
///                        KDL has none for a tree.
/// KDL has no centre of mass or centroidal momentum.
class KdlFrames {
 public:
  explicit KdlFrames(const Subject& s)
      : subject_(s),
        tree_(test::kdl::load_tree(s.package.input, s.robot.locked, s.package.floating_base)),
        fk_(tree_),
        jac_(tree_) {
    const Vec3<double>& g = s.model().gravity;
    const std::vector<std::string> names = test::kdl::tree_dynamics(tree_, g)->joint_names();
    const unsigned n = static_cast<unsigned>(names.size());
    Random rng(seed);
    for (int k = 0; k < state_count; ++k) {
      pairs_.push_back(test::kdl::random_state_pair(s.model(), names, rng));
      q_.emplace_back(n);
      q_.back().data = pairs_.back().q_kdl;
    }
    placements_.resize(s.frames.size());
    jacobians_.assign(s.frames.size(), KDL::Jacobian(n));
    if (!s.package.floating_base && s.frames.size() == 1) {
      chain_.emplace();
      if (!tree_.getChain(tree_.getRootSegment()->first, s.frames[0], *chain_))
        throw std::runtime_error("KDL has no chain to " + s.frames[0]);
      jacdot_ = std::make_unique<KDL::ChainJntToJacDotSolver>(*chain_);
      // the chain's joints in the tree's coordinates, matched by name
      std::vector<int> index;
      for (const KDL::Segment& segment : chain_->segments)
        if (segment.getJoint().getType() != KDL::Joint::None)
          index.push_back(static_cast<int>(
              std::find(names.begin(), names.end(), segment.getJoint().getName()) - names.begin()));
      for (const test::kdl::StatePair& pair : pairs_) {
        KDL::JntArrayVel chain_state(static_cast<unsigned>(index.size()));
        for (std::size_t j = 0; j < index.size(); ++j) {
          chain_state.q(j) = pair.q_kdl[index[j]];
          chain_state.qdot(j) = pair.qd_kdl[index[j]];
        }
        chain_states_.push_back(chain_state);
      }
    }
  }

  bool has(Function f) const {
    return f == Placements || f == Jacobians || (f == Accelerations && jacdot_);
  }

  void run(Function f, int k) {
    const std::vector<std::string>& frames = subject_.frames;
    switch (f) {
      case Placements:
        for (std::size_t i = 0; i < frames.size(); ++i)
          fk_.JntToCart(q_[k], placements_[i], frames[i]);
        break;
      case Jacobians:
        for (std::size_t i = 0; i < frames.size(); ++i)
          jac_.JntToJac(q_[k], jacobians_[i], frames[i]);
        break;
      case Accelerations: jacdot_->JntToJacDot(chain_states_[k], jdot_v_); break;
      case Com:
      case Centroidal: break;
    }
  }

  /// Relative difference to the runtime at KDL's state k: J_kdl = J G with v = G qd_kdl
  /// (kdl_peer.hpp).
  double error(Function f, int k) {
    run(f, k);
    const test::kdl::StatePair& s = pairs_[k];
    Workspace<double> ws(subject_.model());
    Outputs expected(f, subject_.model().nv, subject_.nframes());
    runtime_call(subject_.model(), ws, f, test::view(s.q), test::view(s.v), expected);
    const int nf = subject_.nframes(), nv = subject_.model().nv;
    Eigen::VectorXd got, want;
    switch (f) {
      case Placements:
        got.resize(12 * nf);
        for (int i = 0; i < nf; ++i) {
          for (int e = 0; e < 9; ++e) got[9 * i + e] = placements_[i].M.data[e];
          for (int e = 0; e < 3; ++e) got[9 * nf + 3 * i + e] = placements_[i].p[e];
        }
        want.resize(12 * nf);
        want << vec(expected.first), vec(expected.second);
        break;
      case Jacobians: {
        const int n = static_cast<int>(s.q_kdl.size());
        got.resize(6 * nf * n), want.resize(6 * nf * n);
        for (int i = 0; i < nf; ++i) {
          got.segment(6 * i * n, 6 * n) = jacobians_[i].data.reshaped<Eigen::RowMajor>();
          want.segment(6 * i * n, 6 * n) =
              (rows(expected.first, 6, nv, 6 * i * nv) * s.G).reshaped<Eigen::RowMajor>();
        }
        break;
      }
      case Accelerations:
        got.resize(6);
        got << jdot_v_.vel.x(), jdot_v_.vel.y(), jdot_v_.vel.z(), jdot_v_.rot.x(), jdot_v_.rot.y(),
            jdot_v_.rot.z();
        want = vec(expected.first);
        break;
      case Com:
      case Centroidal: return NAN;
    }
    return test::relative_error(got, want);
  }

 private:
  const Subject& subject_;
  KDL::Tree tree_;  // the solvers keep references to it and to chain_
  KDL::TreeFkSolverPos_recursive fk_;
  KDL::TreeJntToJacSolver jac_;
  std::optional<KDL::Chain> chain_;
  std::unique_ptr<KDL::ChainJntToJacDotSolver> jacdot_;
  std::vector<test::kdl::StatePair> pairs_;
  std::vector<KDL::JntArray> q_;
  std::vector<KDL::JntArrayVel> chain_states_;
  std::vector<KDL::Frame> placements_;
  std::vector<KDL::Jacobian> jacobians_;
  KDL::Twist jdot_v_;
};

std::string format(std::optional<double> x, const char* spec) {
  return dyngen::bench::format(x, spec, "n/a");
}

/// The generated functions against the runtime at one state, and each peer's function against
/// the runtime at one of its states: a model or frame that came out different fails the run.
void check(Subject& s, MujocoFrames& mujoco, KdlFrames& kdl) {
  Workspace<double> ws(s.model());
  for (Function f : functions) {
    Outputs expected(f, s.model().nv, s.nframes());
    runtime_call(s.model(), ws, f, s.states[0].q, s.states[0].qd, expected);
    s.generated(f, 0);
    const Outputs& got = s.out[f];
    const double errors[] = {
        std::max(
            test::relative_error(vec(got.first), vec(expected.first)),
            got.second.empty() ? 0 : test::relative_error(vec(got.second), vec(expected.second))),
        mujoco.error(f, 0), kdl.has(f) ? kdl.error(f, 0) : 0};
    const char* names[] = {"generated", "MuJoCo", "KDL"};
    const std::string kdl_error = kdl.has(f) ? format(errors[2], "%.1e") : "n/a";
    std::printf("check %-16s %-20s generated %.1e, MuJoCo %.1e, KDL %s\n", s.package.name,
                function_names[f], errors[0], errors[1], kdl_error.c_str());
    for (int e = 0; e < 3; ++e)
      if (!(errors[e] <= tolerance))
        throw std::runtime_error(std::string(s.package.name) + " " + function_names[f] + ": " +
                                 names[e] + " differs from the runtime by " +
                                 format(errors[e], "%.1e"));
  }
}

/// Operations of one call (add, mul, div, neg, sin and cos) of the generated function, as its
/// banner counts them, and of the runtime's (the unsimplified trace).
std::pair<long, long> operation_counts(const Model<double>& model, Function f) {
  return {gen::count_ops(gen::trace<double>(function_names[f], model)).total(),
          gen::count_ops(gen::trace<double>(function_names[f], model, false), false).total()};
}

std::string benchmark_name(const Subject& s, Function f, Implementation i) {
  return std::string(s.package.name) + "/" + function_names[f] + "/" + implementation_names[i];
}

/// The table of the run: ns per call, ratios over the generated code, operation counts.
std::string table(const std::vector<std::unique_ptr<Subject>>& subjects,
                  const std::map<std::string, double>& ns) {
  std::ostringstream md;
  md << "| robot | frames | nv | function | generated | runtime | KDL | MuJoCo "
        "| runtime / generated | KDL / generated | MuJoCo / generated | ops generated "
        "| ops runtime |\n"
     << "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& s : subjects) {
    for (Function f : functions) {
      std::optional<double> t[4];
      for (int i = 0; i < 4; ++i) {
        const auto it = ns.find(benchmark_name(*s, f, static_cast<Implementation>(i)));
        if (it != ns.end()) t[i] = it->second;
      }
      if (!t[Generated]) continue;  // filtered out
      const auto ratio = [&](int i) -> std::optional<double> {
        if (!t[i] || !t[Generated]) return std::nullopt;
        return *t[i] / *t[Generated];
      };
      const auto [generated_ops, runtime_ops] = operation_counts(s->model(), f);
      std::string frames = s->package.frames;
      for (char& c : frames)
        if (c == ',') c = ' ';
      md << "| " << s->package.name << " | " << frames << " | " << s->model().nv << " | "
         << function_names[f] << " | " << format(t[0], "%.1f") << " | " << format(t[1], "%.1f")
         << " | " << format(t[2], "%.1f") << " | " << format(t[3], "%.1f") << " | "
         << format(ratio(1), "%.2f") << " | " << format(ratio(2), "%.2f") << " | "
         << format(ratio(3), "%.2f") << " | " << generated_ops << " | " << runtime_ops << " |\n";
    }
  }
  md << "\nOf which sin and cos of q (the generated `joint_trig`, which every generated function "
        "calls first; the runtime computes the same sines and cosines):\n\n"
     << "| robot | joint_trig |\n|---|---:|\n";
  for (const auto& s : subjects) {
    const auto it = ns.find(std::string(s->package.name) + "/joint_trig/generated");
    if (it != ns.end())
      md << "| " << s->package.name << " | " << format(it->second, "%.1f") << " |\n";
  }
  return md.str();
}

}  // namespace
}  // namespace dyngen::bench

int main(int argc, char** argv) {
  using namespace dyngen::bench;
  benchmark::Initialize(&argc, argv);
  const char* table_path = argc > 1 ? argv[1] : nullptr;
  std::vector<std::unique_ptr<Subject>> subjects;
  std::vector<std::unique_ptr<MujocoFrames>> mujoco;
  std::vector<std::unique_ptr<KdlFrames>> kdl;
  for (const FramePackage& p : frame_packages()) {
    subjects.push_back(std::make_unique<Subject>(p));
    Subject* s = subjects.back().get();
    mujoco.push_back(std::make_unique<MujocoFrames>(*s));
    kdl.push_back(std::make_unique<KdlFrames>(*s));
    MujocoFrames* m = mujoco.back().get();
    KdlFrames* k = kdl.back().get();
    check(*s, *m, *k);
    for (Function f : functions) {
      const auto add = [&](Implementation i, auto run) {
        benchmark::RegisterBenchmark(benchmark_name(*s, f, i).c_str(),
                                     [run, s](benchmark::State& st) {
                                       int k = 0;
                                       for (auto _ : st) {
                                         run(k);
                                         benchmark::ClobberMemory();
                                         k = (k + 1) % state_count;
                                       }
                                     });
      };
      add(Generated, [s, f](int k) { s->generated(f, k); });
      add(Runtime, [s, f](int k) { s->runtime(f, k); });
      if (k->has(f)) add(Kdl, [k, f](int j) { k->run(f, j); });
      add(Mujoco, [m, f](int k) { m->run(f, k); });
    }
    const std::string trig = std::string(p.name) + "/joint_trig/generated";
    benchmark::RegisterBenchmark(trig.c_str(), [s](benchmark::State& st) {
      int k = 0;
      for (auto _ : st) {
        s->package.joint_trig(s->states[k].q.data());
        k = (k + 1) % state_count;
      }
    });
  }
  MedianCollector collector(MedianCollector::Clock::Cpu);
  benchmark::RunSpecifiedBenchmarks(&collector);
  const std::string md = table(subjects, collector.ns);
  std::printf("\n%s", md.c_str());
  if (table_path) {
    const benchmark::CPUInfo& cpu = benchmark::CPUInfo::Get();
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
    std::ofstream(table_path)
        << "# dyngen frames benchmark\n\nns of CPU time per call (median over repetitions), "
        << state_count << " seeded random states cycled through; " << cpu.num_cpus << " CPUs at "
        << cpu.cycles_per_second / 1e6 << " MHz; MuJoCo " << mj_versionString()
        << ", orocos-KDL 1.5.1; " << date
        << ". Ratios are times over the generated code's; ops: operations per call (add, mul, "
           "div, neg, sin, cos) of the generated code and of the runtime. n/a: the peer has no "
           "such function; MuJoCo's centroidal is the momentum h only (no matrix A). "
           "bench/README.md, \"Frames\", says what each column calls.\n\n"
        << md;
  }
  benchmark::Shutdown();
  return 0;
}
