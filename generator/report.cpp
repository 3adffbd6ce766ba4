#include "report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dyngen/numerics/reference.hpp"
#include "names.hpp"
#include "output.hpp"
#include "process.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace fs = std::filesystem;

namespace {

/// A number of the harness's JSON, where an infinite error (a non-finite output) is null.
double number(const nlohmann::json& j) {
  return j.is_null() ? std::numeric_limits<double>::infinity() : j.get<double>();
}

bool has(const std::vector<Algorithm>& algorithms, Algorithm a) {
  return std::find(algorithms.begin(), algorithms.end(), a) != algorithms.end();
}

/// The algorithms generated in float: all but those that divide by ABA's pivots where the float
/// model moves no inertia at some joint.
std::vector<Algorithm> float_algorithms(const Robot& robot, const std::vector<Algorithm>& all) {
  if (joints_blocking_aba_in_float(robot.model).empty()) return all;
  std::vector<Algorithm> kept;
  for (const Algorithm& a : all)
    if (!algorithm_spec(a).divides_by_pivots) kept.push_back(a);
  return kept;
}

/// The generated code of one variant into dir/harness/<variant>; returns generation's
/// conditioning estimate.
numerics::Conditioning write_variant(const Robot& robot, const ReportOptions& options,
                                     const std::string& name, bool single, const fs::path& dir,
                                     bool with_model) {
  GenerateOptions g;
  g.name = name;
  g.algorithms = single ? float_algorithms(robot, options.algorithms) : options.algorithms;
  g.single_precision = single;
  g.options_text = options.model_flags;
  const Generated generated = generate(robot, g);
  std::vector<GeneratedFile> files;
  for (const GeneratedFile& f : generated.files)
    if (f.name == name + "_dynamics.hpp" || f.name == name + "_dynamics.cpp" ||
        f.name == "dyngen_sincos.h" || f.name == "dyngen_kernels.hpp" ||
        (with_model && f.name == name + "_model.hpp"))
      files.push_back(f);
  write_package(dir.string(), files);
  return generated.conditioning;
}

std::string algorithm_title(const std::string& a) {
  if (a == "rnea") return "RNEA (inverse dynamics, tau)";
  if (a == "crba") return "CRBA (mass matrix, M)";
  if (a == "aba") return "ABA (forward dynamics, qdd)";
  std::string outputs;
  for (const ArraySpec& y : algorithm_spec(a).outputs)
    outputs += (outputs.empty() ? "" : ", ") + std::string(y.name);
  return fmt::format("{} ({})", a, outputs);
}

/// The harness's registrations of every variant of each algorithm: the runtime and the
/// generated code in double (exact, FMA, fast-math) and float, and for ABA, when CRBA and RNEA
/// are generated too, CRBA+LDLT.
std::string harness_variants(const std::vector<Algorithm>& algorithms,
                             const std::vector<Algorithm>& in_float, const std::string& name) {
  std::string text;
  for (const Algorithm& a : algorithms) {
    const AlgorithmSpec<double>& spec = algorithm_spec(a);
    std::string arguments;
    for (std::size_t k = 0; k < spec.inputs.size(); ++k)
      arguments += fmt::format("{}x[{}]", k ? ", " : "", k);
    for (std::size_t k = 0; k < spec.outputs.size(); ++k) arguments += fmt::format(", y[{}]", k);
    const auto generated = [&](const char* scalar, const std::string& ns, const std::string& label) {
      return fmt::format(
          "add<{0}>(\"{1}\", \"{2}\", [](const {0}* const* x, {0}* const* y) {{ {3}::{1}({4}); }});\n",
          scalar, a, label, ns, arguments);
    };
    text += fmt::format("  add_runtime<double>(\"{}\");\n", a);
    text += "  " + generated("double", name, "generated double");
    text += "  if (fma) " + generated("double", name + "_fma", "generated double, FMA");
    text += "  " + generated("double", name + "_fastmath", "generated double, fast-math");
    text += fmt::format("  add_runtime<float>(\"{}\");\n", a);
    if (std::find(in_float.begin(), in_float.end(), a) != in_float.end())
      text += "  " + generated("float", name + "_float", "generated float");
    if (a == "aba" && has(algorithms, "crba") && has(algorithms, "rnea"))
      for (const auto& [scalar, ns] : {std::pair{"double", name}, std::pair{"float", name + "_float"}})
        text += fmt::format(
            "  add<{0}>(\"aba\", \"generated CRBA+LDLT {0}\", [](const {0}* const* x, {0}* const* y) {{\n"
            "    ldlt_{0}({1}::crba, {1}::rnea, x[0], x[1], x[2], y[0]);\n  }});\n",
            scalar, ns);
  }
  return text;
}

/// The speed-up of each result over the runtime of its algorithm and scalar type (CRBA+LDLT:
/// over the runtime's ABA).
void add_speed_ups(nlohmann::json& results) {
  for (nlohmann::json& r : results) {
    const std::string baseline = "runtime " + r["scalar"].get<std::string>();
    for (const nlohmann::json& b : results)
      if (b["algorithm"] == r["algorithm"] && b["variant"] == baseline)
        r["speed_up"] = b["median_ns"].get<double>() / r["median_ns"].get<double>();
  }
}

/// The algorithms of the results, in their order.
std::vector<std::string> result_algorithms(const nlohmann::json& results) {
  std::vector<std::string> names;
  for (const nlohmann::json& r : results)
    if (std::find(names.begin(), names.end(), r["algorithm"]) == names.end())
      names.push_back(r["algorithm"]);
  return names;
}

std::string markdown_tables(const nlohmann::json& results) {
  std::string out;
  for (const std::string& a : result_algorithms(results)) {
    std::string rows;
    for (const nlohmann::json& r : results) {
      if (r["algorithm"] != a) continue;
      std::string worst = fmt::format("{:.2g}", number(r["worst_error"]));
      if (r["nonfinite"].get<int>() > 0)
        worst = fmt::format("{} non-finite", r["nonfinite"].get<int>());
      rows += fmt::format("| {} | {:.2g} | {} | {:.0f} | {:.2f} |\n", r["variant"].get<std::string>(),
                          number(r["median_error"]), worst, r["median_ns"].get<double>(),
                          r["speed_up"].get<double>());
    }
    if (rows.empty()) continue;
    out += fmt::format("## {}\n\n| variant | median error | worst error | median ns | speed-up |\n"
                       "|---|---:|---:|---:|---:|\n{}\n",
                       algorithm_title(a), rows);
  }
  return out;
}

/// gnuplot data blocks, one panel per algorithm and a last one with the key. A variant has the
/// same point style in every panel.
std::pair<std::string, std::string> plot_parts(const nlohmann::json& results, int& panels) {
  std::vector<std::string> variants;
  for (const nlohmann::json& r : results)
    if (std::find(variants.begin(), variants.end(), r["variant"]) == variants.end())
      variants.push_back(r["variant"]);
  std::vector<std::string> panel_data, panel_plots;
  for (const std::string& a : result_algorithms(results)) {
    std::string block, series;
    double x_lo = 1e300, x_hi = 0, y_lo = 1e300, y_hi = 0;
    int k = 0;
    for (const nlohmann::json& r : results) {
      if (r["algorithm"] != a) continue;
      const double ns = r["median_ns"].get<double>();
      // no correct digit (an error of 1 or more, or a non-finite output) is drawn at 1
      const double median = std::clamp(number(r["median_error"]), 1e-20, 1.0);
      const double worst = std::clamp(number(r["worst_error"]), 1e-20, 1.0);
      block += fmt::format("{:.6g} {:.6g} {:.6g} {:.6g}\n", ns, median, median, worst);
      x_lo = std::min(x_lo, ns), x_hi = std::max(x_hi, ns);
      y_lo = std::min(y_lo, median), y_hi = std::max(y_hi, worst);
      const auto style = std::find(variants.begin(), variants.end(), r["variant"]) - variants.begin();
      series += fmt::format(
          "{}${} every ::{}::{} using 1:2:3:4 with yerrorbars lc {} pt {} ps 1.3 title \"{}\"",
          k == 0 ? "plot " : ", \\\n     ", a, k, k, style + 1, style + 4,
          r["variant"].get<std::string>());
      ++k;
    }
    if (k == 0) continue;
    panel_data.push_back(fmt::format("${} << EOD\n{}EOD\n", a, block));
    // a margin around the points, so that none sits on the frame
    panel_plots.push_back(fmt::format("set title \"{}\"\nset xrange [{:.3g}:{:.3g}]\n"
                                      "set yrange [{:.3g}:{:.3g}]\n{}\n",
                                      algorithm_title(a), x_lo / 1.5, x_hi * 1.5, y_lo / 10,
                                      y_hi * 10, series));
  }
  std::string data, plots = "unset key\n", key;
  for (std::size_t p = 0; p < panel_plots.size(); ++p) data += panel_data[p], plots += panel_plots[p];
  for (std::size_t v = 0; v < variants.size(); ++v)
    key += fmt::format("{}NaN with points lc {} pt {} ps 1.3 title \"{}\"",
                       v == 0 ? "plot " : ", \\\n     ", v + 1, v + 4, variants[v]);
  plots += "unset title\nunset border\nunset tics\nunset grid\nunset xlabel\nunset ylabel\n"
           "unset logscale\nset xrange [0:1]\nset yrange [0:1]\nset key center center\n" +
           key + "\n";
  panels = static_cast<int>(panel_plots.size()) + 1;
  return {data, plots};
}

bool have_gnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

}  // namespace

void make_report(const Robot& robot, const ReportOptions& options, const std::string& dir) {
  const std::string name = identifier(robot.name);
  const fs::path out_dir(dir);
  const fs::path work = out_dir / "harness";
  if (!options.force &&
      !holds_only(out_dir, {std::begin(report_files), std::end(report_files)}, {"harness"}))
    throw FileError(fmt::format(
        "{}: exists and holds files that dyngen report did not write; it writes only into a new "
        "or empty directory or over an earlier report. Choose another directory, or give --force "
        "to write into it (its report files and harness/ are replaced, the rest kept).",
        dir));
  fs::create_directories(work);
  const auto step = [&](int k, const std::string& text) {
    if (!options.quiet) fmt::print("[{}/5] {}\n", k, text), std::fflush(stdout);
  };

  const std::vector<int> blocking_in_float = joints_blocking_aba_in_float(robot.model);
  const std::vector<Algorithm> in_float = float_algorithms(robot, options.algorithms);
  bool with_pivots = false;
  for (const Algorithm& a : options.algorithms)
    with_pivots = with_pivots || algorithm_spec(a).divides_by_pivots;
  step(1, "generating the code: double, float, double for FMA, double for fast-math");
  const numerics::Conditioning c =
      write_variant(robot, options, name, false, work / "double", true);
  write_variant(robot, options, name + "_float", true, work / "float", false);
  write_variant(robot, options, name + "_fma", false, work / "fma", false);
  write_variant(robot, options, name + "_fastmath", false, work / "fastmath", false);
  const std::string banner = fmt::format(
      "Written by dyngen {} report for robot '{}' ({}); rewritten on every run.", version,
      safe_text(robot.name), safe_text(fs::path(robot.path).filename().string()));
  write_file(work / "CMakeLists.txt",
             fill("report_CMakeLists.txt.in", {{"banner", "# " + banner}, {"name", name},
                                                {"robot", safe_text(robot.name)}}));
  write_file(work / "harness.cpp",
             fill("report_harness.cpp.in",
                  {{"banner", "// " + banner},
                   {"name", name},
                   {"robot", safe_text(robot.name)},
                   {"variants", harness_variants(options.algorithms, in_float, name)}}));

  step(2, fmt::format("configuring the harness in {}", work.string()));
  const fs::path build = work / "build";
  run_logged("configuring the harness",
      fmt::format("cmake -S {} -B {} -Ddyngen_DIR={}", shell_quoted(work.string()),
                  shell_quoted(build.string()), shell_quoted(options.package_dir)),
      work / "configure.log", false);
  step(3, "building the harness (the generated code four times; big robots take minutes)");
  run_logged("building the harness",
      fmt::format("cmake --build {} -j {}", shell_quoted(build.string()),
                  std::max(1u, std::thread::hardware_concurrency())),
      work / "build.log", false);

  step(4, fmt::format("measuring errors on {} states, then timing", options.states));
  const fs::path results_path = work / "results.json";
  run_logged("running the harness",
      fmt::format("{} {} {} {} {} {} {} {}", shell_quoted((build / (name + "_report")).string()),
                  options.states, options.seed, options.timed_states, options.min_time,
                  options.repetitions, numerics::reference_bits(c.aba_digits_lost()),
                  shell_quoted(results_path.string())),
      work / "run.log", !options.quiet);

  step(5, "writing the report");
  nlohmann::json report;
  std::ifstream(results_path) >> report;
  add_speed_ups(report["results"]);
  report["robot"] = robot.name;
  report["dyngen"] = version;
  report["command"] = options.command;
  report["robot_file"] = fs::path(robot.path).filename().string();
  report["sha256"] = robot.sha256;
  report["conditioning"] = {{"samples", c.samples},
                            {"cond_M_median", c.cond_M_median},
                            {"cond_M_max", c.cond_M_max},
                            {"pivot_min", c.pivot_min},
                            {"pivot_joint", c.pivot_joint},
                            {"inertia_range", c.inertia_range},
                            {"aba_digits_lost", c.aba_digits_lost()},
                            {"float_unrepresentable", c.float_unrepresentable}};

  std::string summary = fmt::format(
      "Robot {} from {} (sha256 {}): {} joints, nq = {}{}. dyngen {}.\n\n```\n{}\n```",
      markdown_code(robot.name), markdown_code(report["robot_file"].get<std::string>()),
      robot.sha256, robot.model.nv, robot.model.nq,
      options.model_flags.empty() ? "" : ", options " + markdown_code(options.model_flags),
      version, safe_text(conditioning_text(c, with_pivots), true));
  std::string left_out;
  for (const Algorithm& a : options.algorithms)
    if (!has(in_float, a)) left_out += (left_out.empty() ? "" : ", ") + a;
  if (!left_out.empty())
    summary += fmt::format(
        "\n\nNo generated float ABA ({}): once the model's constants are rounded to float, these "
        "joints move no inertia, so it cannot be generated (the runtime's float ABA divides by "
        "zero there): {}.",
        left_out, safe_text(joint_list(robot.model, blocking_in_float)));
  const std::string markdown = fill(
      "report.md.in",
      {{"robot", markdown_code(robot.name)},
       {"summary", summary},
       {"states", std::to_string(report["states"].get<int>())},
       {"seed", std::to_string(options.seed)},
       {"floor", fmt::format("{:g}", report["error_floor"].get<double>())},
       {"bits", std::to_string(report["reference_bits"].get<int>())},
       {"repetitions", std::to_string(options.repetitions)},
       {"min_time", fmt::format("{:g}", options.min_time)},
       {"timed_states", std::to_string(report["timed_states"].get<int>())},
       {"cpus", std::to_string(report["cpus"].get<int>())},
       {"mhz", fmt::format("{:.0f}", report["cpu_mhz"].get<double>())},
       {"tables", markdown_tables(report["results"])},
       {"svg", "report.svg"},
       {"command", options.command}});
  int panels = 0;
  const auto [data, plots] = plot_parts(report["results"], panels);
  const std::string script = fill(
      "report_plot.gp.in",
      {{"banner", "# " + banner},
       {"script", "report.gp"},
       {"width", std::to_string(400 * panels)},
       {"svg", "report.svg"},
       {"data", data},
       {"panels", std::to_string(panels)},
       {"title", fmt::format("{}: error against time, {} states", gnuplot_string(robot.name),
                             report["states"].get<int>())},
       {"plots", plots}});

  // every file under a temporary name first, then renamed into place
  const std::string tmp = ".tmp";
  std::vector<std::string> written = {"report.md", "report.json", "report.gp"};
  try {
    write_file(out_dir / ("report.md" + tmp), markdown);
    write_file(out_dir / ("report.json" + tmp), report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    write_file(out_dir / ("report.gp" + tmp), script);
    if (have_gnuplot()) {
      written.push_back("report.svg");
      run_logged("drawing the plot with gnuplot",
          fmt::format("cd {} && gnuplot -e \"output_file='report.svg{}'\" report.gp{} && "
                      "test -s report.svg{}",
                      shell_quoted(out_dir.string()), tmp, tmp, tmp),
          work / "plot.log", false);
    } else {
      fmt::print(stderr, "dyngen report: warning: gnuplot not found; no plot drawn (install "
                         "gnuplot-nox, then run gnuplot report.gp in {})\n", dir);
    }
  } catch (...) {
    std::error_code ignored;
    for (const std::string& f : written) fs::remove(out_dir / (f + tmp), ignored);
    throw;
  }
  for (const std::string& f : written) fs::rename(out_dir / (f + tmp), out_dir / f);
  if (!options.quiet) {
    fmt::print("{}wrote", markdown_tables(report["results"]));
    for (const std::string& f : written) fmt::print(" {}", (out_dir / f).string());
    fmt::print("\n");
  }
}

}  // namespace dyngen::gen
