// dyngen_batch_bench (bench/README.md, "Batches"): states per second on one core of rnea, crba and
// aba for the robots of bench/CMakeLists.txt's batch entries (ur5, solo12 and atlas, fixed and
// floating): the generated scalar functions, in double and in float, beside the batch functions
// of dyngen --batch (4 and 8 lanes of double and of float, built for AVX2), f_many over
// many_states states, the runtime, MuJoCo and orocos-KDL; and joint_trig beside joint_trig_batch,
// the sines and cosines that every function computes first. The inputs change every call: a pool
// of seeded random states, or of batches of them, cycled through. Before timing, every batch and
// _many function is checked against its package's scalar function, lane by lane and bit for bit
// (+0 and -0 equal), and the generated double code, the runtime, MuJoCo and KDL against the
// runtime to 1e-8 relative as dyngen_bench checks them, so that a broken build fails instead of
// being timed. Then it prints and, given a path, writes a Markdown table.
//
// usage: dyngen_batch_bench [Google Benchmark flags] [TABLE.md]
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "batch_packages.hpp"
#include "median_collector.hpp"
#include "peer_code.hpp"

namespace dyngen::bench {
namespace {

constexpr int pool_states = 256;   // cycled through one by one or in batches, as dyngen_bench's
constexpr int many_states = 1024;  // per call of f_many
constexpr std::uint64_t seed = 20261127;
constexpr double tolerance = 1e-8;  // relative, against the runtime, as dyngen_bench's

const std::vector<Algorithm>& algorithms = compared_algorithms();

/// The table's columns: what is timed, one benchmark each.
enum Column {
  ScalarDouble,
  BatchD4,
  BatchD8,
  ScalarFloat,
  BatchF4,
  BatchF8,
  ManyD4,
  ManyF8,
  Runtime,
  Mujoco,
  Kdl
};
constexpr int column_count = Kdl + 1;
constexpr const char* column_names[] = {"scalar_double", "batch_d4", "batch_d8", "scalar_float",
                                        "batch_f4",      "batch_f8", "many_d4",  "many_f8",
                                        "runtime",       "mujoco",   "kdl"};
constexpr const char* column_titles[] = {"double",  "d4",      "d8",      "float",  "f4", "f8",
                                         "many d4", "many f8", "runtime", "MuJoCo", "KDL"};

/// The inputs of states in one scalar type, in batches of lanes: entry i of state b * lanes + l
/// at [(b * n + i) * lanes + l], n = nq for q and nv for the others (f_batch's structure of
/// arrays). With lanes = 1, state s at [s * n + i]: the layout of f and of f_many.
template <class Scalar>
struct Inputs {
  int lanes, nq, nv;
  std::vector<Scalar> q, qd, qdd, tau;

  Inputs(const std::vector<State>& states, int count, int lanes, int nq, int nv)
      : lanes(lanes),
        nq(nq),
        nv(nv),
        q(count * nq),
        qd(count * nv),
        qdd(count * nv),
        tau(count * nv) {
    for (int s = 0; s < count; ++s) {
      put(states[s].q, nq, s, q);
      put(states[s].qd, nv, s, qd);
      put(states[s].qdd, nv, s, qdd);
      put(states[s].tau, nv, s, tau);
    }
  }

  void put(const std::vector<double>& x, int n, int s, std::vector<Scalar>& y) const {
    for (int i = 0; i < n; ++i)
      y[((s / lanes) * n + i) * lanes + s % lanes] = static_cast<Scalar>(x[i]);
  }
};

/// Call k of f, a scalar or a batch function: state or batch k of in; the output into out.
template <class Scalar>
void call(const Dynamics<Scalar>& f, Algorithm a, const Inputs<Scalar>& in, int k, Scalar* out) {
  const int q0 = k * in.nq * in.lanes, v0 = k * in.nv * in.lanes;  // call k's first entries
  switch (a) {
    case Computes::Other: break;
    case Computes::InverseDynamics: f.rnea(&in.q[q0], &in.qd[v0], &in.qdd[v0], out); break;
    case Computes::MassMatrix: f.crba(&in.q[q0], out); break;
    case Computes::ForwardDynamics: f.aba(&in.q[q0], &in.qd[v0], &in.tau[v0], out); break;
  }
}

/// f_many on every state of in, which holds them one after the other.
template <class Scalar>
void call(const ManyDynamics<Scalar>& f, Algorithm a, const Inputs<Scalar>& in, Scalar* out) {
  const long count = static_cast<long>(in.q.size()) / in.nq;
  switch (a) {
    case Computes::Other: break;
    case Computes::InverseDynamics:
      f.rnea(count, in.q.data(), in.qd.data(), in.qdd.data(), out);
      break;
    case Computes::MassMatrix: f.crba(count, in.q.data(), out); break;
    case Computes::ForwardDynamics:
      f.aba(count, in.q.data(), in.qd.data(), in.tau.data(), out);
      break;
  }
}

/// One package's functions and their inputs: the scalar function on one state a call, the
/// batch function on one batch a call, f_many on many_states states.
template <class Scalar>
struct Generated {
  const BatchPackage<Scalar>& package;
  Inputs<Scalar> states;   // many_states, one after the other; the first pool_states cycled
  Inputs<Scalar> batches;  // pool_states, in batches of package.lanes
  std::vector<Scalar> out;

  Generated(const BatchPackage<Scalar>& p, const Model<double>& model,
            const std::vector<State>& random_states)
      : package(p),
        states(random_states, many_states, 1, model.nq, model.nv),
        batches(random_states, pool_states, p.lanes, model.nq, model.nv),
        out(many_states * model.nv * model.nv) {}

  int batch_count() const { return pool_states / package.lanes; }

  void scalar(Algorithm a, int k) { call(package.scalar, a, states, k, out.data()); }
  void batch(Algorithm a, int k) { call(package.batch, a, batches, k, out.data()); }
  void many(Algorithm a) { call(package.many, a, states, out.data()); }
  void trig(int k) { package.scalar.joint_trig(&states.q[k * states.nq]); }
  void trig_batch(int k) { package.batch.joint_trig(&batches.q[k * batches.nq * package.lanes]); }

  /// Batch 0 lane by lane, and f_many state by state, against the scalar function: equal values
  /// (the same bits, or zeros of either sign), else it throws.
  void check(Algorithm a, const std::string& name) const {
    const int n = output_size(a, states.nv), lanes = package.lanes;
    std::vector<Scalar> batch_out(n * lanes), many_out(n * many_states), state_out(n);
    call(package.batch, a, batches, 0, batch_out.data());
    call(package.many, a, states, many_out.data());
    for (int s = 0; s < many_states; ++s) {
      call(package.scalar, a, states, s, state_out.data());
      for (int i = 0; i < n; ++i) {
        const char* differs = s < lanes && !(batch_out[i * lanes + s] == state_out[i]) ? "batch"
                              : !(many_out[s * n + i] == state_out[i])                 ? "many"
                                                                                       : nullptr;
        if (differs)
          throw std::runtime_error(name + ": " + differs + " differs from the scalar function " +
                                   "at state " + std::to_string(s) + ", entry " +
                                   std::to_string(i));
      }
    }
  }
};

std::vector<State> random_states(const Model<double>& model) {
  Random rng(seed);
  std::vector<State> states;
  for (int k = 0; k < many_states; ++k) states.push_back(numerics::random_state(model, rng));
  return states;
}

gen::LoadOptions load_options(const BatchRobot& r) {
  gen::LoadOptions o;
  o.floating_base = r.floating_base;
  o.mimic_independent = true;  // as robot_package gives dyngen
  return o;
}

/// Everything timed for one robot with one base; the benchmarks keep references into it.
struct Subject {
  const BatchRobot& entry;
  gen::Robot robot;
  std::vector<State> states;  // many_states; the first pool_states cycled through
  Generated<double> d4, d8;
  Generated<float> f4, f8;
  RuntimeCode runtime;
  MujocoCode mujoco;
  KdlCode kdl;

  explicit Subject(const BatchRobot& r)
      : entry(r),
        robot(gen::load_robot(r.input, load_options(r))),
        states(random_states(robot.model)),
        d4(r.d4, robot.model, states),
        d8(r.d8, robot.model, states),
        f4(r.f4, robot.model, states),
        f8(r.f8, robot.model, states),
        runtime(robot.model, states),
        mujoco(robot, r.input, r.floating_base, states),
        kdl(robot, r.input, r.floating_base, seed, pool_states) {}

  std::string name() const { return std::string(entry.robot) + "_" + entry.base; }
};

std::string benchmark_name(const Subject& s, const char* function, Column c) {
  return s.name() + "/" + function + "/" + column_names[c];
}

/// States computed by one call of each benchmark, by name.
std::map<std::string, int> states_per_call;

/// Registers run(k) for k = 0, 1, ..., calls - 1, 0, ...: one call computes `states` states.
template <class Run>
void add(const std::string& name, int states, int calls, Run run) {
  states_per_call[name] = states;
  benchmark::RegisterBenchmark(name.c_str(), [run, calls](benchmark::State& st) {
    int k = 0;
    for (auto _ : st) {
      run(k);
      benchmark::ClobberMemory();
      k = k + 1 == calls ? 0 : k + 1;
    }
  });
}

/// Checks every implementation of one subject (see the file's head), then registers its
/// benchmarks.
void check_and_add(Subject& s) {
  const int d4 = s.d4.package.lanes, d8 = s.d8.package.lanes, f4 = s.f4.package.lanes,
            f8 = s.f8.package.lanes;
  for (const Algorithm a : algorithms) {
    const char* f = algorithm_name(a);
    s.d4.check(a, benchmark_name(s, f, BatchD4));
    s.d8.check(a, benchmark_name(s, f, BatchD8));
    s.f4.check(a, benchmark_name(s, f, BatchF4));
    s.f8.check(a, benchmark_name(s, f, BatchF8));
    for (int k = 0; k < 4; ++k) {
      s.d4.scalar(a, k);
      const std::vector<double> expected = reference(s.robot.model, a, s.states[k]);
      const double errors[] = {
          test::relative_error(Eigen::Map<const Eigen::VectorXd>(s.d4.out.data(), expected.size()),
                               vec(expected)),
          s.runtime.error(a, k), s.mujoco.error(a, k), s.kdl.has(a) ? s.kdl.error(a, k) : 0};
      const Column columns[] = {ScalarDouble, Runtime, Mujoco, Kdl};
      for (int e = 0; e < 4; ++e)
        if (!(errors[e] <= tolerance))
          throw std::runtime_error(benchmark_name(s, f, columns[e]) + ": relative difference " +
                                   std::to_string(errors[e]) + " from the runtime at state " +
                                   std::to_string(k));
    }
    add(benchmark_name(s, f, ScalarDouble), 1, pool_states, [&s, a](int k) { s.d4.scalar(a, k); });
    add(benchmark_name(s, f, BatchD4), d4, s.d4.batch_count(),
        [&s, a](int k) { s.d4.batch(a, k); });
    add(benchmark_name(s, f, BatchD8), d8, s.d8.batch_count(),
        [&s, a](int k) { s.d8.batch(a, k); });
    add(benchmark_name(s, f, ScalarFloat), 1, pool_states, [&s, a](int k) { s.f4.scalar(a, k); });
    add(benchmark_name(s, f, BatchF4), f4, s.f4.batch_count(),
        [&s, a](int k) { s.f4.batch(a, k); });
    add(benchmark_name(s, f, BatchF8), f8, s.f8.batch_count(),
        [&s, a](int k) { s.f8.batch(a, k); });
    add(benchmark_name(s, f, ManyD4), many_states, 1, [&s, a](int) { s.d4.many(a); });
    add(benchmark_name(s, f, ManyF8), many_states, 1, [&s, a](int) { s.f8.many(a); });
    add(benchmark_name(s, f, Runtime), 1, pool_states, [&s, a](int k) { s.runtime.run(a, k); });
    add(benchmark_name(s, f, Mujoco), 1, pool_states, [&s, a](int k) { s.mujoco.run(a, k); });
    if (s.kdl.has(a))
      add(benchmark_name(s, f, Kdl), 1, pool_states, [&s, a](int k) { s.kdl.run(a, k); });
  }
  const char* trig = "joint_trig";
  add(benchmark_name(s, trig, ScalarDouble), 1, pool_states, [&s](int k) { s.d4.trig(k); });
  add(benchmark_name(s, trig, BatchD4), d4, s.d4.batch_count(),
      [&s](int k) { s.d4.trig_batch(k); });
  add(benchmark_name(s, trig, BatchD8), d8, s.d8.batch_count(),
      [&s](int k) { s.d8.trig_batch(k); });
  add(benchmark_name(s, trig, ScalarFloat), 1, pool_states, [&s](int k) { s.f4.trig(k); });
  add(benchmark_name(s, trig, BatchF4), f4, s.f4.batch_count(),
      [&s](int k) { s.f4.trig_batch(k); });
  add(benchmark_name(s, trig, BatchF8), f8, s.f8.batch_count(),
      [&s](int k) { s.f8.trig_batch(k); });
}

std::string format(std::optional<double> x, const char* spec) {
  return dyngen::bench::format(x, spec, "-");
}

/// Millions of states per second, to three digits.
std::string format_rate(std::optional<double> x) {
  return format(x, x && *x >= 100 ? "%.0f" : "%.3g");
}

/// The table's rows: the compared algorithms, then joint_trig (the sines and cosines alone).
std::vector<const char*> table_functions() {
  std::vector<const char*> functions;
  for (const Algorithm a : algorithms) functions.push_back(algorithm_name(a));
  functions.push_back("joint_trig");
  return functions;
}

/// The tables of the run: states per second and the speed-ups; the share of sin and cos.
std::string table(const std::vector<std::unique_ptr<Subject>>& subjects,
                  const std::map<std::string, double>& ns) {
  // millions of states per second
  const auto rate = [&](const Subject& s, const char* f, Column c) -> std::optional<double> {
    const std::string name = benchmark_name(s, f, c);
    const auto it = ns.find(name);
    if (it == ns.end()) return std::nullopt;
    return states_per_call.at(name) * 1e3 / it->second;
  };
  const auto ratio = [](std::optional<double> x, std::optional<double> y) -> std::optional<double> {
    if (!x || !y) return std::nullopt;
    return *x / *y;
  };
  std::ostringstream md;
  md << "| robot | base | nv | function |";
  for (const char* title : column_titles) md << " " << title << " |";
  md << " d4 / double | d8 / double | f4 / float | f8 / float | f8 / double |\n|---|---|---:|---|";
  for (int c = 0; c < column_count + 5; ++c) md << "---:|";
  md << "\n";
  for (const auto& s : subjects) {
    for (const char* f : table_functions()) {
      std::optional<double> r[column_count];
      for (int c = 0; c < column_count; ++c) r[c] = rate(*s, f, static_cast<Column>(c));
      if (!r[ScalarDouble]) continue;  // filtered out
      md << "| " << s->entry.robot << " | " << s->entry.base << " | " << s->robot.model.nv << " | "
         << f << " |";
      for (int c = 0; c < column_count; ++c) md << " " << format_rate(r[c]) << " |";
      const std::optional<double> ratios[] = {
          ratio(r[BatchD4], r[ScalarDouble]), ratio(r[BatchD8], r[ScalarDouble]),
          ratio(r[BatchF4], r[ScalarFloat]), ratio(r[BatchF8], r[ScalarFloat]),
          ratio(r[BatchF8], r[ScalarDouble])};
      for (const auto& x : ratios) md << " " << format(x, "%.2f") << " |";
      md << "\n";
    }
  }
  md << "\nShare of sin and cos: the time of `joint_trig` (`joint_trig_batch` in the batch "
        "columns: the sine and cosine of every revolute joint) over the function's time in the "
        "same column. A function computes only the angles it reads (its banner's sin count), in "
        "runs of consecutive joints, so where it reads fewer the share is an estimate.\n\n"
        "| robot | base | function | double | d4 | d8 | float | f4 | f8 |\n"
        "|---|---|---|---:|---:|---:|---:|---:|---:|\n";
  const Column generated[] = {ScalarDouble, BatchD4, BatchD8, ScalarFloat, BatchF4, BatchF8};
  for (const auto& s : subjects)
    for (const Algorithm a : algorithms) {
      const char* f = algorithm_name(a);
      if (!rate(*s, f, ScalarDouble)) continue;  // filtered out
      md << "| " << s->entry.robot << " | " << s->entry.base << " | " << f << " |";
      for (const Column c : generated) {
        const auto share = ratio(rate(*s, f, c), rate(*s, "joint_trig", c));
        md << " " << format(share ? std::optional(100 * *share) : std::nullopt, "%.0f%%") << " |";
      }
      md << "\n";
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
  try {
    for (const BatchRobot& r : batch_robots()) {
      std::printf("loading and checking %s %s\n", r.robot, r.base);
      std::fflush(stdout);
      subjects.push_back(std::make_unique<Subject>(r));
      check_and_add(*subjects.back());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dyngen_batch_bench: %s\n", e.what());
    return 1;
  }
  std::printf(
      "batch and many functions equal the scalar ones lane by lane; the generated code, "
      "the runtime, MuJoCo and KDL agree with the runtime to %.0e; timing\n",
      tolerance);
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
        << "# dyngen batch benchmark\n\nMillions of states per second on one core (CPU time of "
           "one call, median over repetitions, and the states it computes); "
        << pool_states << " seeded random states cycled through, one by one or in batches; "
        << cpu.num_cpus << " CPUs at " << cpu.cycles_per_second / 1e6 << " MHz; MuJoCo "
        << mj_versionString() << ", orocos-KDL 1.5.1; " << date
        << ". double and float: the generated scalar functions (one state a call); d4, d8, f4, "
           "f8: `f_batch` of `dyngen --batch 4` or `8`, in double or float (`--scalar float`); "
           "many d4 and many f8: `f_many` over "
        << many_states
        << " states stored one after the other (the transposition into lanes and back "
           "included); every package built with -O3 -ffp-contract=off -mavx2. runtime, MuJoCo "
           "and KDL as in dyngen_bench, one state a call (KDL: no mass matrix or forward "
           "dynamics of a tree). joint_trig rows: `joint_trig` and `joint_trig_batch`. Ratios "
           "are of states per second. bench/README.md, \"Batches\", says what each column "
           "calls.\n\n"
        << md;
  }
  benchmark::Shutdown();
  return 0;
}
