// dyngen_bench (README.md): RNEA, CRBA and ABA of the generated code, the runtime, MuJoCo and
// orocos-KDL for every package of packages.cpp, in ns per call on seeded random states that
// change every iteration. Each timed call is first checked against the runtime, so that all
// four compute the same quantity of the same model. With an output directory it then writes
// benchmarks.md (the table, with ratios to the generated code) and benchmarks.gp (a gnuplot
// script with its data: time and operation count against links for the chains).
//
// usage: dyngen_bench [Google Benchmark flags] [OUTPUT_DIR]
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <chrono>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dyngen/dyngen.hpp"
#include "median_collector.hpp"
#include "package.hpp"
#include "peer_code.hpp"
#include "robot.hpp"

namespace dyngen::bench {
namespace {

constexpr int state_count = 256;  // cycled through, so the inputs change every call
constexpr std::uint64_t seed = 20261121;
constexpr double tolerance = 1e-8;  // of the check against the runtime (the peers pass 1e-9)

const std::vector<Algorithm>& algorithms = compared_algorithms();
enum Implementation { Generated, Snapped, Unrolled, Copy, Runtime, Mujoco, Kdl };
constexpr const char* implementation_names[] = {"generated", "snapped", "unrolled", "copy",
                                                "runtime",   "mujoco",  "kdl"};

// Each implementation, this one and those of peer_code.hpp, has run(a, k), the timed call on
// state k, and error(a, k): run(a, k) and its relative difference from the runtime.

/// Generated code; the snapped code's model differs from the runtime's by less than 1e-10
/// (bench/README.md), far inside the check's tolerance.
class GeneratedCode {
 public:
  GeneratedCode(const Functions& f, const Model<double>& model, const std::vector<State>& states)
      : f_(f), model_(model), states_(states), out_(model.nv * model.nv) {}

  bool has(Algorithm) const { return f_.rnea != nullptr; }

  void run(Algorithm a, int k) { call(f_, a, states_[k], out_.data()); }

  double error(Algorithm a, int k) {
    run(a, k);
    const std::vector<double> expected = reference(model_, a, states_[k]);
    return test::relative_error(vec(out_).head(expected.size()), vec(expected));
  }

 private:
  const Functions& f_;
  const Model<double>& model_;
  const std::vector<State>& states_;
  std::vector<double> out_;
};

/// Everything timed for one package; the implementations keep references into it.
struct Subject {
  const Package& package;
  gen::Robot robot;
  std::vector<State> states;
  std::unique_ptr<GeneratedCode> generated, snapped, unrolled, copy;
  std::unique_ptr<RuntimeCode> runtime;
  std::unique_ptr<MujocoCode> mujoco;
  std::unique_ptr<KdlCode> kdl;
};

std::string benchmark_name(const Package& p, Algorithm a, Implementation i) {
  return std::string(p.name) + "/" + algorithm_name(a) + "/" + implementation_names[i];
}

/// Checks each algorithm of one implementation against the runtime on a few states, then
/// registers its benchmark.
template <class Code>
void add(const Package& p, Implementation i, Code* code) {
  for (const Algorithm a : algorithms) {
    if (!code->has(a)) continue;
    const std::string name = benchmark_name(p, a, i);
    for (int k = 0; k < 4; ++k)
      if (const double error = code->error(a, k); !(error <= tolerance))
        throw std::runtime_error(name + ": relative difference " + std::to_string(error) +
                                 " from the runtime at state " + std::to_string(k));
    benchmark::RegisterBenchmark(name.c_str(), [code, a](benchmark::State& st) {
      int k = 0;
      for (auto _ : st) {
        code->run(a, k);
        benchmark::ClobberMemory();
        k = (k + 1) % state_count;
      }
    })->Unit(benchmark::kNanosecond);
  }
}

std::unique_ptr<Subject> make_subject(const Package& p) {
  auto s = std::unique_ptr<Subject>(
      new Subject{p, gen::load_robot(p.input, load_options(p)), {}, {}, {}, {}, {}, {}, {}, {}});
  Random rng(seed);
  for (int k = 0; k < state_count; ++k)
    s->states.push_back(numerics::random_state(s->robot.model, rng));
  s->generated = std::make_unique<GeneratedCode>(p.generated, s->robot.model, s->states);
  s->snapped = std::make_unique<GeneratedCode>(p.snapped, s->robot.model, s->states);
  s->unrolled = std::make_unique<GeneratedCode>(p.unrolled, s->robot.model, s->states);
  s->copy = std::make_unique<GeneratedCode>(p.copy, s->robot.model, s->states);
  s->runtime = std::make_unique<RuntimeCode>(s->robot.model, s->states);
  s->mujoco = std::make_unique<MujocoCode>(s->robot, p.urdf, p.floating_base, s->states);
  s->kdl = std::make_unique<KdlCode>(s->robot, p.urdf, p.floating_base, seed, state_count);
  add(p, Generated, s->generated.get());
  add(p, Snapped, s->snapped.get());
  add(p, Unrolled, s->unrolled.get());
  add(p, Copy, s->copy.get());
  add(p, Runtime, s->runtime.get());
  add(p, Mujoco, s->mujoco.get());
  add(p, Kdl, s->kdl.get());
  return s;
}

/// Operations per call (add, mul, div, neg, sin and cos together) of the generated code and of
/// the runtime, from the banner of NAME_dynamics.hpp.
struct OperationCounts {
  std::map<Algorithm, long> generated_, runtime_;  // none where the banner has none
  long generated(Algorithm a) const { return generated_.contains(a) ? generated_.at(a) : 0; }
  long runtime(Algorithm a) const { return runtime_.contains(a) ? runtime_.at(a) : 0; }
};

OperationCounts operation_counts(const char* header) {
  OperationCounts counts;
  if (!header) return counts;
  std::ifstream in(header);
  // "//   rnea" opens an algorithm's lines, "//     generated: add 235, mul 325, ..." follow
  const std::regex algorithm_line(R"(^//\s+(\w+)$)");
  const std::regex count_line(R"(^//\s+(generated|runtime):\s+(.*)$)");
  const std::regex count(R"([a-z]+ (\d+))");
  std::optional<Algorithm> algorithm;
  for (std::string text; std::getline(in, text) && text.starts_with("//");) {
    std::smatch m;
    if (std::regex_match(text, m, algorithm_line)) {
      algorithm = compared_algorithm(m[1].str());
      continue;
    }
    if (!algorithm || !std::regex_match(text, m, count_line)) continue;
    long total = 0;
    const std::string list = m[2];
    for (std::sregex_iterator it(list.begin(), list.end(), count), end; it != end; ++it)
      total += std::stol((*it)[1]);
    (m[1] == "generated" ? counts.generated_ : counts.runtime_)[*algorithm] = total;
  }
  return counts;
}

std::string format_ns(std::optional<double> ns) {
  if (!ns) return "-";
  char text[32];
  std::snprintf(text, sizeof text, *ns < 100 ? "%.1f" : "%.0f", *ns);
  return text;
}

std::string format_ratio(std::optional<double> x, std::optional<double> y) {
  if (!x || !y) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", *x / *y);
  return text;
}

/// A pair of times of the same or nearly the same operations that differ by this factor or more
/// is placement, not code (issue 16: less than 20%).
constexpr double robust_spread = 1.2;

/// The paired measurement behind the robust-speed table: rounds, and the length of one burst.
constexpr int paired_rounds = 31;
constexpr double burst_seconds = 1e-3;

/// The time of y over the time of x for algorithm a, measured so that load from elsewhere on a
/// shared machine cancels: a burst of about burst_seconds of calls of x, then one of y (the order
/// alternating by round), and the median over paired_rounds of each round's ratio. Separate
/// medians of a few repetitions, as Google Benchmark takes them, differed between two runs of
/// the same binary by more than the placement effect looked for.
double paired_ratio(GeneratedCode& x, GeneratedCode& y, Algorithm a) {
  using Clock = std::chrono::steady_clock;
  const auto burst = [a](GeneratedCode& code, int calls) {
    const auto start = Clock::now();
    for (int k = 0; k < calls; ++k) {
      code.run(a, k % state_count);
      benchmark::ClobberMemory();
    }
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  int calls = 16;
  while (burst(x, calls) + burst(y, calls) < 2 * burst_seconds) calls *= 2;
  std::vector<double> ratios;
  for (int round = 0; round < paired_rounds; ++round) {
    const bool x_first = round % 2 == 0;
    const double first = burst(x_first ? x : y, calls), second = burst(x_first ? y : x, calls);
    ratios.push_back(x_first ? second / first : first / second);
  }
  std::nth_element(ratios.begin(), ratios.begin() + paired_rounds / 2, ratios.end());
  return ratios[paired_rounds / 2];
}

/// The slower of two times over the faster, from their ratio.
std::optional<double> spread(std::optional<double> ratio) {
  if (!ratio) return std::nullopt;
  return std::max(*ratio, 1 / *ratio);
}

/// The robust-speed table: each robot's generated code against the same code linked a second
/// time (copy), and against its snapped code where snapping removes less than 20% of the
/// operations; a spread of robust_spread or more is flagged.
template <class Time>
void write_robust_speed(std::ostream& md, const std::vector<std::unique_ptr<Subject>>& subjects,
                        const Time& time) {
  std::printf("measuring the robust-speed pairs\n");
  std::fflush(stdout);
  std::ostringstream rows;
  int pairs = 0, flagged = 0;
  for (const auto& s : subjects) {
    const Package& p = s->package;
    if (!p.snapped_header) continue;  // the chains have no copy
    const OperationCounts ops = operation_counts(p.header);
    const OperationCounts snapped_ops = operation_counts(p.snapped_header);
    for (const Algorithm a : algorithms) {
      const auto g = time(p, a, Generated), c = time(p, a, Copy), sn = time(p, a, Snapped);
      if (!g || !c) continue;  // filtered out
      const long n = ops.generated(a), n_snapped = snapped_ops.generated(a);
      const double removed = 1.0 - static_cast<double>(n_snapped) / static_cast<double>(n);
      const auto copy_spread = spread(paired_ratio(*s->generated, *s->copy, a));
      const auto snapped_spread =
          removed < 0.2 ? spread(paired_ratio(*s->generated, *s->snapped, a)) : std::nullopt;
      std::string flag;
      const std::pair<const char*, std::optional<double>> checks[] = {{"copy", copy_spread},
                                                                      {"snapped", snapped_spread}};
      for (const auto& [name, x] : checks) {
        if (!x) continue;
        ++pairs;
        if (*x < robust_spread) continue;
        ++flagged;
        flag += std::string(flag.empty() ? "" : ", ") + "**" + name + "**";
      }
      char percent[16];
      std::snprintf(percent, sizeof percent, "%.0f%%", 100 * removed);
      rows << "| " << p.robot << " | " << p.base << " | " << algorithm_name(a) << " | " << n
           << " | " << format_ns(g) << " | " << format_ns(c) << " | "
           << format_ratio(copy_spread, 1.0) << " | " << percent << " | " << format_ns(sn)
           << " | " << format_ratio(snapped_spread, 1.0) << " | " << flag << " |\n";
    }
  }
  if (pairs == 0) return;
  md << "\n## Robust speed\n\n"
     << "The same operations should take the same time wherever the linker puts them (issue 16). "
        "copy: the generated code built a second time, as its own library, so that the same "
        "instructions run from another address. generated, copy and snapped are the medians "
        "above; spread is measured apart, in pairs: " << paired_rounds << " rounds of a burst of "
     << burst_seconds * 1e3 << " ms of calls of each of the two, the slower over the faster, "
        "the median of the rounds. The snapped code is compared only where snapping removes "
        "less than 20% of the operations. A spread of " << robust_spread
     << " or more is flagged: " << flagged << " of " << pairs << " pairs here.\n\n"
     << "| robot | base | algorithm | ops | generated | copy | spread | snapping removes "
        "| snapped | spread | flagged |\n"
     << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|\n"
     << rows.str();
}

void write_results(const std::string& dir, const std::vector<std::unique_ptr<Subject>>& subjects,
                   const std::map<std::string, double>& ns) {
  const auto time = [&](const Package& p, Algorithm a, Implementation i) -> std::optional<double> {
    const auto it = ns.find(benchmark_name(p, a, i));
    if (it == ns.end()) return std::nullopt;
    return it->second;
  };

  std::ofstream md(dir + "/benchmarks.md");
  const benchmark::CPUInfo& cpu = benchmark::CPUInfo::Get();
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  md << "# dyngen benchmarks\n\n"
     << "ns per call (median over repetitions), " << state_count
     << " seeded random states cycled through; " << cpu.num_cpus << " CPUs at "
     << cpu.cycles_per_second / 1e6 << " MHz; MuJoCo " << mj_versionString()
     << ", orocos-KDL 1.5.1; " << date
     << ". Ratios are times over the generated code's (KDL / runtime: KDL's time over the "
        "runtime's). snapped: the code of `dyngen --snap 1e-9`, with its ratios over the same "
        "others. unrolled: the code of `dyngen --structure unrolled` (the same operations, every "
        "link's code in place; generated is the default, --structure auto, shared in functions "
        "of 1800 operations or more). ops: operations per call of the generated code, the snapped code and the "
        "runtime (dyngen's count). KDL: `chain` solvers on serial robots, `tree` (RNEA only) "
        "otherwise. bench/README.md says what each column calls.\n\n"
     << "| robot | base | nv | algorithm | generated | snapped | unrolled | runtime | MuJoCo | KDL "
        "| KDL solver | runtime / generated | MuJoCo / generated | KDL / generated "
        "| runtime / snapped | MuJoCo / snapped | KDL / snapped | runtime / unrolled "
        "| unrolled / generated | KDL / runtime | ops generated | ops snapped | ops runtime |\n"
     << "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|"
        "---:|---:|---:|---:|---:|\n";
  for (const auto& s : subjects) {
    const Package& p = s->package;
    const OperationCounts ops = operation_counts(p.header);
    const OperationCounts snapped_ops = operation_counts(p.snapped_header);
    const std::string robot =
        p.links ? std::string(p.robot) + " " + std::to_string(p.links) : std::string(p.robot);
    for (const Algorithm a : algorithms) {
      const auto g = time(p, a, Generated), sn = time(p, a, Snapped), u = time(p, a, Unrolled),
                 r = time(p, a, Runtime), m = time(p, a, Mujoco), k = time(p, a, Kdl);
      if (!g && !sn && !u && !r && !m && !k) continue;  // filtered out
      md << "| " << robot << " | " << p.base << " | " << s->robot.model.nv << " | "
         << algorithm_name(a) << " | " << format_ns(g) << " | " << format_ns(sn) << " | "
         << format_ns(u) << " | " << format_ns(r) << " | " << format_ns(m) << " | "
         << format_ns(k) << " | " << (s->kdl->is_chain() ? "chain" : "tree") << " | "
         << format_ratio(r, g) << " | " << format_ratio(m, g) << " | " << format_ratio(k, g)
         << " | " << format_ratio(r, sn) << " | " << format_ratio(m, sn) << " | "
         << format_ratio(k, sn) << " | " << format_ratio(r, u) << " | " << format_ratio(u, g)
         << " | " << format_ratio(k, r) << " | " << ops.generated(a) << " | "
         << (p.snapped_header ? std::to_string(snapped_ops.generated(a)) : "-") << " | "
         << ops.runtime(a) << " |\n";
    }
  }
  write_robust_speed(md, subjects, time);

  // gnuplot: time (top row) and operation count (bottom row) against links, one panel per
  // algorithm; solid lines the planar chains, dashed the spatial ones.
  std::ofstream gp(dir + "/benchmarks.gp");
  const Implementation plotted[] = {Generated, Unrolled, Runtime, Mujoco, Kdl};  // chains: no snap
  const int n_plotted = std::size(plotted);
  const char* kinds[] = {"planar_chain", "spatial_chain"};
  for (const char* kind : kinds)
    for (const Algorithm a : algorithms) {
      gp << "$" << kind << "_" << algorithm_name(a)
         << " << EOD\n# links generated unrolled runtime mujoco kdl ops_generated ops_runtime\n";
      for (const auto& s : subjects) {
        const Package& p = s->package;
        if (!p.links || std::string(p.robot) != kind) continue;
        const OperationCounts ops = operation_counts(p.header);
        gp << p.links;
        for (const Implementation i : plotted) {
          const auto t = time(p, a, i);
          gp << " " << (t ? std::to_string(*t) : "NaN");
        }
        gp << " " << ops.generated(a) << " " << ops.runtime(a) << "\n";
      }
      gp << "EOD\n";
    }
  gp << "set terminal svg size 1500,950 dynamic font 'sans,11'\n"
        "set output 'benchmarks.svg'\n"
        "set logscale xy\nset xtics (2, 4, 8, 16, 32, 64, 128)\nset autoscale xfix\n"
        "set offsets graph 0.05, graph 0.05, 0, 0\nset grid\n"
        "set key top left font ',9'\nset xlabel 'links'\n"
        "set multiplot layout 2,3 title 'dyngen benchmarks: chains (solid: planar, dashed: "
        "spatial)'\n";
  const char* colors[] = {"#1b9e77", "#66a61e", "#d95f02", "#7570b3", "#e7298a"};
  for (const Algorithm a : algorithms) {
    gp << "set title '" << algorithm_name(a) << ": time per call'\nset ylabel 'ns'\nplot ";
    for (int i = 0; i < n_plotted; ++i)
      for (int kind = 0; kind < 2; ++kind)
        gp << (i || kind ? ", " : "") << "$" << kinds[kind] << "_" << algorithm_name(a)
           << " using 1:" << i + 2 << " with linespoints lc rgb '" << colors[i] << "' dt "
           << kind + 1 << " pt 7 ps 0.5 title '" << implementation_names[plotted[i]]
           << (kind ? " spatial" : " planar") << "'";
    gp << "\n";
  }
  for (const Algorithm a : algorithms) {
    gp << "set title '" << algorithm_name(a)
       << ": operations per call'\nset ylabel 'add, mul, div, neg, sin, cos'\nplot ";
    for (int i = 0; i < 2; ++i)
      for (int kind = 0; kind < 2; ++kind)
        gp << (i || kind ? ", " : "") << "$" << kinds[kind] << "_" << algorithm_name(a)
           << " using 1:" << i + 2 + n_plotted << " with linespoints lc rgb '"
           << colors[i == 0 ? 0 : 2] << "' dt " << kind + 1 << " pt 7 ps 0.5 title '"
           << (i == 0 ? "generated" : "runtime")
           << (kind ? " spatial" : " planar") << "'";
    gp << "\n";
  }
  gp << "unset multiplot\n";
}

}  // namespace
}  // namespace dyngen::bench

int main(int argc, char** argv) {
  using namespace dyngen::bench;
  benchmark::Initialize(&argc, argv);
  if (argc > 2 || (argc == 2 && argv[1][0] == '-')) {
    std::fprintf(stderr, "usage: %s [Google Benchmark flags] [OUTPUT_DIR]\n", argv[0]);
    return 2;
  }
  std::vector<std::unique_ptr<Subject>> subjects;
  try {
    for (const Package& p : packages()) {
      std::printf("loading and checking %s\n", p.name);
      std::fflush(stdout);
      subjects.push_back(make_subject(p));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dyngen_bench: %s\n", e.what());
    return 1;
  }
  std::printf("all agree with the runtime to %.0e; timing\n", tolerance);
  MedianCollector collector(MedianCollector::Clock::Real);
  benchmark::RunSpecifiedBenchmarks(&collector);
  if (argc == 2) write_results(argv[1], subjects, collector.ns);
  return 0;
}
