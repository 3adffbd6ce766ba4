// dyngen report's harness. For each algorithm and variant it measures the norm-wise relative
// error against the MPFR reference (the dyngen runtime on 256-bit numbers) on seeded random
// states, times the variant with Google Benchmark, and writes the figures as JSON for dyngen
// report to tabulate and plot.
//   harness STATES SEED TIMED_STATES MIN_TIME REPETITIONS REFERENCE_BITS OUTPUT.json
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <type_traits>
#include <utility>

#include <benchmark/benchmark.h>

#include <dyngen/numerics/random.hpp>

#include "dyngen/report/harness.hpp"

namespace dyngen_report {
namespace {

using dyngen::numerics::State;

/// Every state's inputs in one scalar type, packed.
template <class S>
struct Inputs {
  int nq = 0, nv = 0;
  std::vector<S> q, qd, qdd, tau;

  /// The entries of state k of the array that algorithm tables call `name`.
  const S* of(std::string_view name, int k) const {
    const std::size_t n = name == "q" ? nq : nv;
    const std::vector<S>& x = name == "q" ? q : name == "v" ? qd : name == "a" ? qdd : tau;
    return &x[static_cast<std::size_t>(k) * n];
  }
};

template <class S>
Inputs<S> pack(const std::vector<State>& states, int nq, int nv) {
  Inputs<S> in{nq, nv, {}, {}, {}, {}};
  for (const State& s : states) {
    in.q.insert(in.q.end(), s.q.begin(), s.q.end());
    in.qd.insert(in.qd.end(), s.qd.begin(), s.qd.end());
    in.qdd.insert(in.qdd.end(), s.qdd.begin(), s.qdd.end());
    in.tau.insert(in.tau.end(), s.tau.begin(), s.tau.end());
  }
  return in;
}

/// What every variant works on: the model in both scalar types, a runtime workspace for each,
/// and the states' inputs. Set up before the variants are registered.
struct Setting {
  explicit Setting(dyngen::Model<double> model) : model_double(std::move(model)) {}

  dyngen::Model<double> model_double;
  dyngen::Model<float> model_float = model_double.cast<float>();
  dyngen::Workspace<double> ws_double{model_double};
  dyngen::Workspace<float> ws_float{model_float};
  Inputs<double> inputs_double;
  Inputs<float> inputs_float;
  int timed_states = 1;
  int repetitions = 1;
  double min_time = 0.1;

  template <class S>
  const Inputs<S>& inputs() const {
    if constexpr (std::is_same_v<S, float>) return inputs_float;
    else return inputs_double;
  }
  template <class S>
  const dyngen::Model<S>& model() const {
    if constexpr (std::is_same_v<S, float>) return model_float;
    else return model_double;
  }
  template <class S>
  dyngen::Workspace<S>& workspace() {
    if constexpr (std::is_same_v<S, float>) return ws_float;
    else return ws_double;
  }
};

std::unique_ptr<Setting> setting;

template <class S>
const dyngen::AlgorithmSpec<S>& spec(const std::string& algorithm) {
  const dyngen::AlgorithmSpec<S>* s = runtime_algorithm<S>(algorithm);
  if (!s) std::fprintf(stderr, "no algorithm %s\n", algorithm.c_str()), std::exit(2);
  return *s;
}

std::size_t size_of(const dyngen::ArraySpec& a) {
  return dyngen::extent_size(a.extent, setting->model_double);
}

/// A variant's outputs, and the pointers to its inputs at each state and to its outputs, made
/// before it is called so that a call allocates nothing.
template <class S>
struct Arrays {
  std::vector<std::vector<S>> outputs;
  std::vector<std::vector<const S*>> x;  // per state
  std::vector<S*> y;

  Arrays(const dyngen::AlgorithmSpec<S>& s, int states) : x(static_cast<std::size_t>(states)) {
    for (const dyngen::ArraySpec& a : s.outputs) outputs.emplace_back(size_of(a));
    for (std::vector<S>& array : outputs) y.push_back(array.data());
    for (int k = 0; k < states; ++k)
      for (const dyngen::ArraySpec& a : s.inputs)
        x[k].push_back(setting->inputs<S>().of(a.name, k));
  }
};

/// One way of computing one algorithm, and what was measured of it.
struct Variant {
  std::string algorithm;
  std::string name;
  bool single;
  std::function<void(int state, std::vector<std::vector<double>>& out)> evaluate;
  std::vector<double> errors;
};

std::vector<Variant> variants;

}  // namespace

/// Registers a variant for the error measurement and for Google Benchmark; the benchmark
/// cycles through the first timed_states states. Its time is wall-clock time, and so is its
/// minimum time: on a busy machine, CPU time would take longer to reach it.
template <class S>
void add(const std::string& algorithm, const std::string& name, Call<S> f) {
  const dyngen::AlgorithmSpec<S>& s = spec<S>(algorithm);
  const int states = static_cast<int>(setting->inputs<S>().q.size()) / setting->inputs<S>().nq;
  auto errors = std::make_shared<Arrays<S>>(s, states);
  variants.push_back({algorithm, name, std::is_same_v<S, float>,
                      [errors, f](int k, std::vector<std::vector<double>>& out) {
                        f(errors->x[k].data(), errors->y.data());
                        out.clear();
                        for (const std::vector<S>& y : errors->outputs) out.emplace_back(y.begin(), y.end());
                      }, {}});
  const std::string title = algorithm + "/" + name;
  auto timed = std::make_shared<Arrays<S>>(s, setting->timed_states);
  benchmark::RegisterBenchmark(title.c_str(), [timed, f](benchmark::State& st) {
    const int n = static_cast<int>(timed->x.size());
    int k = 0;
    for (auto _ : st) {
      f(timed->x[k].data(), timed->y.data());
      benchmark::DoNotOptimize(timed->y.data());
      benchmark::ClobberMemory();
      k = k + 1 == n ? 0 : k + 1;
    }
  })->Repetitions(setting->repetitions)->MinTime(setting->min_time)->ReportAggregatesOnly(true)
    ->UseRealTime()->Unit(benchmark::kNanosecond);
}

/// The runtime's algorithm through its table entry, on spans made once, so that a call
/// allocates nothing (as a call of the generated code).
template <class S>
void add_runtime(const std::string& algorithm) {
  const dyngen::AlgorithmSpec<S>& s = spec<S>(algorithm);
  std::vector<std::span<const S>> in;
  std::vector<std::span<S>> out;
  for (const dyngen::ArraySpec& a : s.inputs) in.emplace_back(static_cast<const S*>(nullptr), size_of(a));
  for (const dyngen::ArraySpec& a : s.outputs) out.emplace_back(static_cast<S*>(nullptr), size_of(a));
  add<S>(algorithm, std::is_same_v<S, float> ? "runtime float" : "runtime double",
         [&s, in, out](const S* const* x, S* const* y) mutable {
           for (std::size_t k = 0; k < in.size(); ++k) in[k] = {x[k], in[k].size()};
           for (std::size_t k = 0; k < out.size(); ++k) out[k] = {y[k], out[k].size()};
           s.call(setting->model<S>(), setting->workspace<S>(), in, out);
         });
}

template void add<double>(const std::string&, const std::string&, Call<double>);
template void add<float>(const std::string&, const std::string&, Call<float>);
template void add_runtime<double>(const std::string&);
template void add_runtime<float>(const std::string&);

}  // namespace dyngen_report

namespace {

using dyngen::numerics::State;

/// Errors of every variant at every state, against the reference at that variant's inputs
/// (float variants see the state rounded to float; the model is the double one throughout):
/// the largest of the errors of its output arrays.
void measure_errors(dyngen_report::Reference& reference, const std::vector<State>& states,
                    const std::vector<State>& rounded) {
  std::vector<std::string> algorithms;
  for (const dyngen_report::Variant& v : dyngen_report::variants)
    if (std::find(algorithms.begin(), algorithms.end(), v.algorithm) == algorithms.end())
      algorithms.push_back(v.algorithm);
  std::vector<std::vector<double>> out;
  const int n = static_cast<int>(states.size());
  for (int k = 0; k < n; ++k) {
    for (const bool single : {false, true}) {
      const State& s = single ? rounded[k] : states[k];
      for (const std::string& a : algorithms) {
        std::vector<std::span<const double>> x;
        for (const dyngen::ArraySpec& array : dyngen_report::spec<double>(a).inputs)
          x.emplace_back(array.name == "q"   ? s.q
                         : array.name == "v" ? s.qd
                         : array.name == "a" ? s.qdd
                                             : s.tau);
        bool computed = false;
        for (dyngen_report::Variant& v : dyngen_report::variants) {
          if (v.algorithm != a || v.single != single) continue;
          if (!computed) reference.compute(a, x), computed = true;
          v.evaluate(k, out);
          v.errors.push_back(reference.error(out));
        }
      }
    }
    if ((k + 1) % std::max(1, n / 10) == 0 || k + 1 == n)
      std::printf("  errors: %d of %d states\n", k + 1, n), std::fflush(stdout);
  }
}

/// Keeps the median of each benchmark's repetitions (with one repetition, its only run; with
/// more, only the aggregates are reported), and prints it as progress.
class MedianCollector : public benchmark::BenchmarkReporter {
 public:
  std::map<std::string, double> median_ns;

  bool ReportContext(const Context&) override { return true; }

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
      median_ns[r.run_name.function_name] = r.GetAdjustedRealTime();
      std::printf("  %-48s %10.1f ns\n", r.run_name.function_name.c_str(), r.GetAdjustedRealTime());
      std::fflush(stdout);
    }
  }
};

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

/// The FMA variant is compiled for FMA instructions; without them it would not run.
bool cpu_has_fma() {
#if defined(__x86_64__) || defined(__i386__)
  return __builtin_cpu_supports("fma");
#else
  return true;
#endif
}

/// A number as JSON: its shortest round trip, and null when it is not finite (an output that
/// is not finite has an infinite error).
std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char text[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, x);
    if (std::strtod(text, nullptr) == x) break;
  }
  return text;
}

/// A string as JSON. The harness's strings are algorithm and variant names: ASCII, no quote,
/// backslash or control character (checked, so that the JSON is valid whatever they become).
std::string json_string(const std::string& s) {
  for (const char c : s)
    if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
      std::fprintf(stderr, "a name the JSON cannot hold as it is: %s\n", s.c_str()), std::exit(2);
  return '"' + s + '"';
}

/// Writes what was measured as JSON, in the form dyngen report reads.
bool write_results(const char* path, const dyngen_report::Setting& setting, int count,
                   unsigned long long seed, int bits, const MedianCollector& collector) {
  const benchmark::CPUInfo& cpu = benchmark::CPUInfo::Get();
  std::string out = "{\n";
  const auto field = [&](const char* name, const std::string& value) {
    out += std::string("  \"") + name + "\": " + value + ",\n";
  };
  field("nq", std::to_string(setting.model_double.nq));
  field("nv", std::to_string(setting.model_double.nv));
  field("states", std::to_string(count));
  field("seed", std::to_string(seed));
  field("timed_states", std::to_string(setting.timed_states));
  field("min_time_s", json_number(setting.min_time));
  field("repetitions", std::to_string(setting.repetitions));
  field("reference_bits", std::to_string(bits));
  field("error_floor", json_number(dyngen_report::Reference::error_floor()));
  field("cpus", std::to_string(cpu.num_cpus));
  field("cpu_mhz", json_number(cpu.cycles_per_second / 1e6));
  out += "  \"results\": [";
  for (std::size_t k = 0; k < dyngen_report::variants.size(); ++k) {
    const dyngen_report::Variant& v = dyngen_report::variants[k];
    out += std::string(k ? "," : "") + "\n    {\"algorithm\": " + json_string(v.algorithm) +
           ", \"variant\": " + json_string(v.name) + ", \"scalar\": \"" +
           (v.single ? "float" : "double") + "\", \"median_error\": " +
           json_number(median(v.errors)) + ", \"worst_error\": " +
           json_number(*std::max_element(v.errors.begin(), v.errors.end())) +
           ", \"nonfinite\": " +
           std::to_string(std::count_if(v.errors.begin(), v.errors.end(),
                                        [](double e) { return std::isinf(e); })) +
           ", \"median_ns\": " +
           json_number(collector.median_ns.at(v.algorithm + "/" + v.name)) + "}";
  }
  out += "\n  ]\n}\n";
  std::ofstream file(path);
  file << out;
  return static_cast<bool>(file);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr,
                 "usage: %s STATES SEED TIMED_STATES MIN_TIME REPETITIONS REFERENCE_BITS "
                 "OUTPUT.json\n",
                 argv[0]);
    return 2;
  }
  const int count = std::atoi(argv[1]);
  const unsigned long long seed = std::strtoull(argv[2], nullptr, 10);
  dyngen_report::setting.reset(new dyngen_report::Setting(dyngen_report::robot_model()));
  dyngen_report::Setting& setting = *dyngen_report::setting;
  setting.timed_states = std::max(1, std::min(count, std::atoi(argv[3])));
  setting.min_time = std::atof(argv[4]);
  setting.repetitions = std::max(1, std::atoi(argv[5]));
  dyngen_report::Reference reference(setting.model_double, std::atoi(argv[6]));

  dyngen::numerics::Random rng(seed);
  std::vector<State> states, rounded;
  for (int k = 0; k < count; ++k) {
    State s = dyngen::numerics::random_state(setting.model_double, rng);
    reference.set_consistent_torques(s);
    rounded.push_back(dyngen::numerics::round_to_float(s));
    states.push_back(std::move(s));
  }
  const int nq = setting.model_double.nq, nv = setting.model_double.nv;
  setting.inputs_double = dyngen_report::pack<double>(states, nq, nv);
  setting.inputs_float = dyngen_report::pack<float>(rounded, nq, nv);

  dyngen_report::add_variants(cpu_has_fma());
  for (dyngen_report::Variant& v : dyngen_report::variants) v.errors.reserve(count);
  std::printf("measuring errors against the MPFR reference (%d bits) on %d states\n",
              reference.bits(), count);
  std::fflush(stdout);
  measure_errors(reference, states, rounded);

  std::printf("timing %zu variants (Google Benchmark: %d repetitions of at least %g s, median)\n",
              dyngen_report::variants.size(), setting.repetitions, setting.min_time);
  std::fflush(stdout);
  int bench_argc = 1;
  benchmark::Initialize(&bench_argc, argv);
  MedianCollector collector;
  benchmark::RunSpecifiedBenchmarks(&collector);

  return write_results(argv[7], setting, count, seed, reference.bits(), collector) ? 0 : 1;
}
