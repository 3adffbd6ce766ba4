// dyngen_contacts_bench (bench/README.md, "Contacts"): the generated contact_dynamics and
// impulse_dynamics of the packages of bench/CMakeLists.txt's contact entries, beside the same
// package's generated ABA and the runtime's contact_dynamics, and where the package has them
// contact_dynamics_derivatives beside aba_derivatives. ns per call on seeded random states
// that change every call. Before timing, each generated function is checked against the runtime
// at every state, so that a benchmark of wrong code fails instead of passing. Then it prints and,
// given a path, writes a Markdown table: the medians, contact_dynamics over ABA in time and in
// operations, and the operations of one call; and a second for the derivatives.
//
// usage: dyngen_contacts_bench [Google Benchmark flags] [TABLE.md]
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact_packages.hpp"
#include "dyngen/constrained.hpp"
#include "dyngen/contact_derivatives.hpp"
#include "dyngen/numerics/random.hpp"
#include "emit.hpp"
#include "median_collector.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace dyngen::bench {
namespace {

constexpr int state_count = 64;  // cycled through, so the inputs change every call
constexpr std::uint64_t seed = 20261129;

enum Function { Aba, Contact, Impulse, RuntimeContact, AbaDerivatives, ContactDerivatives };
constexpr const char* function_names[] = {"aba",
                                          "contact_dynamics",
                                          "impulse_dynamics",
                                          "runtime contact_dynamics",
                                          "aba_derivatives",
                                          "contact_dynamics_derivatives"};

/// One package: its model, states and outputs.
struct Subject {
  const ContactPackage& package;
  gen::Robot robot;
  std::vector<numerics::State> states;
  Workspace<double> ws;
  std::vector<double> x, y;  // outputs: nv, nc
  std::vector<double> d[6];  // the derivatives: 3 of nv x nv, 3 of nc x nv

  explicit Subject(const ContactPackage& p)
      : package(p),
        robot(gen::load_robot(p.input, options(p))),
        ws(robot.model),
        x(static_cast<std::size_t>(model().nv)),
        y(static_cast<std::size_t>(model().nc)) {
    const std::size_t nv = x.size(), nc = y.size();
    for (int k = 0; k < 6; ++k) d[k].resize(nv * (k < 3 ? nv : nc));
    numerics::Random rng(seed);
    for (int k = 0; k < state_count; ++k) states.push_back(numerics::random_state(model(), rng));
  }

  const Model<double>& model() const { return robot.model; }

  static gen::LoadOptions options(const ContactPackage& p) {
    gen::LoadOptions o;
    o.floating_base = p.floating_base;
    o.mimic_independent = true;
    std::stringstream in(p.contacts);
    for (std::string c; std::getline(in, c, ',');) o.contacts.push_back(c);
    return o;
  }

  void run(Function f, int k) {
    const numerics::State& s = states[static_cast<std::size_t>(k)];
    switch (f) {
      case Aba: package.aba(s.q.data(), s.qd.data(), s.tau.data(), x.data()); break;
      case Contact:
        package.contact_dynamics(s.q.data(), s.qd.data(), s.tau.data(), x.data(), y.data());
        break;
      case Impulse: package.impulse_dynamics(s.q.data(), s.qd.data(), x.data(), y.data()); break;
      case RuntimeContact: contact_dynamics<double>(model(), ws, s.q, s.qd, s.tau, x, y); break;
      case AbaDerivatives:
        package.aba_derivatives(s.q.data(), s.qd.data(), s.tau.data(), d[0].data(), d[1].data(),
                                d[2].data());
        break;
      case ContactDerivatives:
        package.contact_dynamics_derivatives(s.q.data(), s.qd.data(), s.tau.data(), d[0].data(),
                                             d[1].data(), d[2].data(), d[3].data(), d[4].data(),
                                             d[5].data());
        break;
    }
  }

  /// The functions the package has.
  std::vector<Function> functions() const {
    std::vector<Function> all{Aba, Contact, Impulse, RuntimeContact};
    if (package.contact_dynamics_derivatives)
      all.insert(all.end(), {AbaDerivatives, ContactDerivatives});
    return all;
  }
};

/// Throws unless a and b agree to 1e-8 relative.
void expect_close(const Subject& s, Function f, const std::vector<double>& a,
                  const std::vector<double>& b) {
  for (std::size_t e = 0; e < a.size(); ++e)
    if (!(std::abs(a[e] - b[e]) <= 1e-8 * (1 + std::abs(b[e]))))
      throw std::runtime_error(std::string(s.package.name) + " " + function_names[f] +
                               " differs from the runtime");
}

/// The generated functions against the runtime at every state.
void check(Subject& s) {
  std::vector<double> x(s.x.size()), y(s.y.size()), d[6];
  for (int k = 0; k < 6; ++k) d[k].resize(s.d[k].size());
  for (int k = 0; k < state_count; ++k) {
    const numerics::State& st = s.states[static_cast<std::size_t>(k)];
    s.run(Contact, k);
    contact_dynamics<double>(s.model(), s.ws, st.q, st.qd, st.tau, x, y);
    expect_close(s, Contact, s.x, x);
    expect_close(s, Contact, s.y, y);
    s.run(Impulse, k);
    impulse_dynamics<double>(s.model(), s.ws, st.q, st.qd, x, y);
    expect_close(s, Impulse, s.x, x);
    expect_close(s, Impulse, s.y, y);
    if (!s.package.contact_dynamics_derivatives) continue;
    s.run(ContactDerivatives, k);
    contact_dynamics_derivatives<double>(s.model(), s.ws, st.q, st.qd, st.tau, d[0], d[1], d[2],
                                         d[3], d[4], d[5]);
    for (int e = 0; e < 6; ++e) expect_close(s, ContactDerivatives, s.d[e], d[e]);
  }
}

long operations(const Model<double>& model, const char* function) {
  return gen::count_ops(gen::trace<double>(function, model)).total();
}

std::string benchmark_name(const Subject& s, Function f) {
  return std::string(s.package.name) + " (" + s.package.words + ")/" + function_names[f];
}

/// The table of the run: ns per call and the ratios over ABA, in time and in operations.
std::string table(const std::vector<std::unique_ptr<Subject>>& subjects,
                  const std::map<std::string, double>& ns) {
  std::ostringstream md;
  md << "| robot | contacts | nv | nc | aba | contact_dynamics | impulse_dynamics | runtime "
        "contact_dynamics | contact / aba, time | contact / aba, ops | ops aba | ops contact "
        "| ops impulse |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& s : subjects) {
    double t[4];
    bool measured = true;  // not filtered out (--benchmark_filter)
    for (int f = 0; f < 4; ++f) {
      const auto it = ns.find(benchmark_name(*s, static_cast<Function>(f)));
      measured = measured && it != ns.end();
      t[f] = measured ? it->second : 0;
    }
    if (!measured) continue;
    const long ops[3] = {operations(s->model(), "aba"), operations(s->model(), "contact_dynamics"),
                         operations(s->model(), "impulse_dynamics")};
    md << "| " << s->package.name << " | " << s->package.words << " | " << s->model().nv << " | "
       << s->model().nc << " | " << format(t[Aba], "%.1f", "-") << " | "
       << format(t[Contact], "%.1f", "-") << " | " << format(t[Impulse], "%.1f", "-") << " | "
       << format(t[RuntimeContact], "%.1f", "-") << " | "
       << format(t[Contact] / t[Aba], "%.2f", "-") << " | "
       << format(static_cast<double>(ops[1]) / static_cast<double>(ops[0]), "%.2f", "-") << " | "
       << ops[0] << " | " << ops[1] << " | " << ops[2] << " |\n";
  }
  return md.str();
}

/// The derivatives' table: contact_dynamics_derivatives over aba_derivatives.
std::string derivative_table(const std::vector<std::unique_ptr<Subject>>& subjects,
                             const std::map<std::string, double>& ns) {
  std::ostringstream md;
  md << "| robot | contacts | aba_derivatives | contact_dynamics_derivatives | time ratio | ops "
        "aba_derivatives | ops contact_dynamics_derivatives | ops ratio |\n"
        "|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& s : subjects) {
    const auto a = ns.find(benchmark_name(*s, AbaDerivatives));
    const auto c = ns.find(benchmark_name(*s, ContactDerivatives));
    if (a == ns.end() || c == ns.end()) continue;
    const long ops[2] = {operations(s->model(), "aba_derivatives"),
                         operations(s->model(), "contact_dynamics_derivatives")};
    md << "| " << s->package.name << " | " << s->package.words << " | "
       << format(a->second, "%.1f", "-") << " | " << format(c->second, "%.1f", "-") << " | "
       << format(c->second / a->second, "%.2f", "-") << " | " << ops[0] << " | " << ops[1] << " | "
       << format(static_cast<double>(ops[1]) / static_cast<double>(ops[0]), "%.2f", "-") << " |\n";
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
  for (const ContactPackage& p : contact_packages()) {
    subjects.push_back(std::make_unique<Subject>(p));
    Subject* s = subjects.back().get();
    check(*s);
    for (const Function f : s->functions())
      benchmark::RegisterBenchmark(benchmark_name(*s, f).c_str(), [s, f](benchmark::State& st) {
        int k = 0;
        for (auto _ : st) {
          s->run(f, k);
          benchmark::ClobberMemory();
          k = (k + 1) % state_count;
        }
      });
  }
  MedianCollector collector(MedianCollector::Clock::Cpu);
  benchmark::RunSpecifiedBenchmarks(&collector);
  const std::string md =
      table(subjects, collector.ns) + "\n" + derivative_table(subjects, collector.ns);
  std::printf("\n%s", md.c_str());
  if (table_path) {
    const benchmark::CPUInfo& cpu = benchmark::CPUInfo::Get();
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
    std::ofstream(table_path)
        << "# dyngen contacts benchmark\n\nns of CPU time per call (median over repetitions), "
        << state_count << " seeded random states cycled through (random v: the impulses stop "
        << "it); " << cpu.num_cpus << " CPUs at " << cpu.cycles_per_second / 1e6 << " MHz; " << date
        << ". ops: operations per call (add, mul, div, neg, sin, cos) of the generated "
        << "code. Command: `scripts/contacts_bench.sh`.\n\n"
        << md;
  }
}
