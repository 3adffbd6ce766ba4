// A Google Benchmark reporter that keeps each benchmark's median, and a table cell's number,
// shared by the benchmark programs that print their own tables.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dyngen::bench {

/// x printed with printf's spec ("%.1f"), or `missing` for a value not measured.
inline std::string format(std::optional<double> x, const char* spec, const char* missing) {
  if (!x) return missing;
  char text[32];
  std::snprintf(text, sizeof text, spec, *x);
  return text;
}

/// Keeps the median of each benchmark's repetitions (the only run without repetitions), in
/// wall-clock or CPU time, and prints it as progress.
class MedianCollector : public benchmark::BenchmarkReporter {
 public:
  enum class Clock { Real, Cpu };

  explicit MedianCollector(Clock clock) : clock_(clock) {}

  std::map<std::string, double> ns;

  bool ReportContext(const Context&) override { return true; }

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type == Run::RT_Aggregate && r.aggregate_name != "median") continue;
      if (r.run_type == Run::RT_Iteration && r.repetitions > 1) continue;
      const double t = clock_ == Clock::Real ? r.GetAdjustedRealTime() : r.GetAdjustedCPUTime();
      ns[r.run_name.function_name] = t;
      std::printf("  %-45s %12.1f ns\n", r.run_name.function_name.c_str(), t);
      std::fflush(stdout);
    }
  }

 private:
  Clock clock_;
};

}  // namespace dyngen::bench
