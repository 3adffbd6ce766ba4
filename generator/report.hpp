// dyngen report ROBOT -o DIR: the accuracy and speed of every way dyngen can compute a
// robot's dynamics (runtime and generated code, double and float, FMA and fast-math, and
// CRBA+LDLT for forward dynamics), as a Markdown table, JSON and a plot of error against run
// time. The measuring is done by a harness that dyngen writes, builds with CMake and runs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dyngen/numerics/conditioning.hpp"
#include "generate.hpp"
#include "robot.hpp"

namespace dyngen::gen {

struct ReportOptions {
  std::vector<Algorithm> algorithms = default_algorithm_names();
  int states = 1000;           // random states for the errors
  std::uint64_t seed = 1;
  int timed_states = 64;       // the benchmarks cycle through the first ones
  double min_time = 0.2;       // seconds per benchmark repetition
  int repetitions = 5;         // the time reported is their median
  std::string model_flags;     // the model options as given, for the report's header
  std::string command;         // the command line, for the report's footer
  std::string package_dir;     // where find_package(dyngen) finds this dyngen
  bool quiet = false;
  bool force = false;          // write into a directory that holds other files too
};

/// The files dyngen report writes into DIR (besides its work directory DIR/harness).
inline constexpr const char* report_files[] = {"report.md", "report.json", "report.gp",
                                               "report.svg"};

/// The algorithms dyngen report generates in float, and the others with why, as report.json's
/// "float_left_out" holds them: {"algorithm", "reason": "pivots", "joints": the joints that move
/// no inertia once the model is rounded to float} or {"algorithm", "reason": "overflow",
/// "detail": where its values overflow float at typical states}.
struct FloatPlan {
  std::vector<Algorithm> kept;
  nlohmann::json left_out = nlohmann::json::array();
};
FloatPlan float_plan(const Robot& robot, const std::vector<Algorithm>& all);

/// Generates the variants, builds and runs the harness in dir/harness, and writes the report
/// files into dir, each whole or not at all. Throws InputError for a robot without ABA when
/// ABA is asked for, and std::runtime_error when a build or run fails (with its log's end).
void make_report(const Robot& robot, const ReportOptions& options, const std::string& dir);

/// The last step of make_report: writes the report files into dir from what the harness
/// measured (its results.json, with float_plan's "float_left_out") and the conditioning
/// estimate, each whole or not at all, prints the tables and the files' paths (unless
/// options.quiet), and returns the paths. The plot is drawn when gnuplot is installed (its log
/// in dir/harness/plot.log).
std::vector<std::string> write_report(const Robot& robot, const ReportOptions& options,
                                      const numerics::Conditioning& c, nlohmann::json measured,
                                      const std::string& dir);

}  // namespace dyngen::gen
