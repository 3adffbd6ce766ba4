#include "report.hpp"

#include <algorithm>
#include <cmath>
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

/// Whether the table's entry that computes c is among the algorithms.
bool has(const std::vector<Algorithm>& algorithms, Computes c) {
  const AlgorithmSpec<double>* spec = find_algorithm<double>(c);
  return spec && has(algorithms, Algorithm(spec->name));
}

/// Whether the CRBA+LDLT variant can be built from these generated algorithms: with the mass
/// matrix and inverse dynamics, whose solve gives forward dynamics.
bool with_ldlt_in(const std::vector<Algorithm>& generated) {
  return has(generated, Computes::MassMatrix) && has(generated, Computes::InverseDynamics);
}

/// Whether forward dynamics is measured through CRBA+LDLT too: when the algorithms have it
/// and what the variant is built from.
bool with_ldlt(const std::vector<Algorithm>& algorithms) {
  return has(algorithms, Computes::ForwardDynamics) && with_ldlt_in(algorithms);
}

}  // namespace

FloatPlan float_plan(const Robot& robot, const std::vector<Algorithm>& all) {
  const std::vector<int> blocking = joints_blocking_aba_in_float(robot.model);
  FloatPlan plan;
  for (const Algorithm& a : all) {
    if (!blocking.empty() && algorithm_spec(a).divides_by_pivots) {
      std::vector<std::string> joints;
      for (const int i : blocking) joints.push_back(robot.model.joint_name[i]);
      plan.left_out.push_back({{"algorithm", a}, {"reason", "pivots"}, {"joints", joints}});
    } else if (const std::string why = typical_overflow(robot, a, true); !why.empty()) {
      plan.left_out.push_back({{"algorithm", a}, {"reason", "overflow"}, {"detail", why}});
    } else {
      plan.kept.push_back(a);
    }
  }
  return plan;
}

namespace {

/// The generated code of one variant into dir/harness/<variant>; returns generation's
/// conditioning estimate.
numerics::Conditioning write_variant(const Robot& robot, const ReportOptions& options,
                                     const std::vector<Algorithm>& algorithms,
                                     const std::string& name, bool single, const fs::path& dir,
                                     bool with_model) {
  GenerateOptions g;
  g.name = name;
  g.algorithms = algorithms;
  g.single_precision = single;
  g.options_text = options.model_flags;
  const Generated generated = generate(robot, g);
  std::vector<GeneratedFile> files;
  for (const GeneratedFile& f : generated.files)
    if (f.name == name + "_dynamics.hpp" || f.name == name + "_dynamics.cpp" ||
        f.name == "dyngen_sincos.h" || f.name == "dyngen_kernels.hpp" || f.name == "dyngen_lie.h" ||
        (with_model && f.name == name + "_model.hpp"))
      files.push_back(f);
  write_package(dir.string(), files);
  return generated.conditioning;
}

std::string algorithm_title(const std::string& a) {
  const AlgorithmSpec<double>& spec = algorithm_spec(a);
  if (!spec.title.empty()) return std::string(spec.title);
  std::string outputs;
  for (const ArraySpec& y : spec.outputs)
    outputs += (outputs.empty() ? "" : ", ") + std::string(y.name);
  return fmt::format("{} ({})", a, outputs);
}

/// The harness's registrations of every variant of each algorithm: the runtime and the
/// generated code in double (exact, FMA, fast-math) and float, and for forward dynamics, when
/// the mass matrix and inverse dynamics are generated too, CRBA+LDLT.
std::string harness_variants(const std::vector<Algorithm>& algorithms,
                             const std::vector<Algorithm>& in_float, const std::string& name) {
  std::string text;
  for (const Algorithm& a : algorithms) {
    const AlgorithmSpec<double>& spec = algorithm_spec(a);
    std::string arguments;
    for (std::size_t k = 0; k < spec.inputs.size(); ++k)
      arguments += fmt::format("{}x[{}]", k ? ", " : "", k);
    for (std::size_t k = 0; k < spec.outputs.size(); ++k) arguments += fmt::format(", y[{}]", k);
    const auto generated = [&](const char* scalar, const std::string& ns,
                               const std::string& label) {
      return fmt::format("add<{0}>(\"{1}\", \"{2}\", [](const {0}* const* x, {0}* const* y) {{ "
                         "::{3}::{1}({4}); }});\n",
                         scalar, a, label, ns, arguments);
    };
    text += fmt::format("  add_runtime<double>(\"{}\");\n", a);
    text += "  " + generated("double", name, "generated double");
    text += "  if (fma) " + generated("double", name + "_fma", "generated double, FMA");
    text += "  " + generated("double", name + "_fastmath", "generated double, fast-math");
    text += fmt::format("  add_runtime<float>(\"{}\");\n", a);
    if (has(in_float, a))
      text += "  " + generated("float", name + "_float", "generated float");
    if (spec.computes != Computes::ForwardDynamics || !with_ldlt(algorithms)) continue;
    const auto ldlt = [&](const char* scalar, const std::string& ns) {
      return fmt::format(
          "  add<{0}>(\"{2}\", \"generated CRBA+LDLT {0}\",\n"
          "           [](const {0}* const* x, {0}* const* y) {{\n"
          "             ldlt_forward_dynamics<{0}>(::{1}::nv, ::{1}::{3}, ::{1}::{4}, x[0],\n"
          "                                        x[1], x[2], y[0]);\n"
          "           }});\n",
          scalar, ns, a, find_algorithm<double>(Computes::MassMatrix)->name,
          find_algorithm<double>(Computes::InverseDynamics)->name);
    };
    text += ldlt("double", name);
    // in float only where float's CRBA and RNEA are generated
    if (with_ldlt_in(in_float)) text += ldlt("float", name + "_float");
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

/// How the plot draws a variant: a colour per way of computing (Okabe and Ito's palette, which
/// colour-blind readers tell apart too) and a shape, filled for double and open for float.
struct VariantStyle {
  std::string_view variant;
  const char* colour;
  int point;  // gnuplot's point type: 7 circle, 5 square, 13 diamond, 9 and 11 triangles
};

/// Every variant the harness measures, in the legend's order: two rows, double above float.
constexpr VariantStyle variant_styles[] = {
    {"runtime double", "#000000", 7},
    {"runtime float", "#000000", 6},
    {"generated double", "#0072B2", 5},
    {"generated float", "#0072B2", 4},
    {"generated CRBA+LDLT double", "#CC79A7", 13},
    {"generated CRBA+LDLT float", "#CC79A7", 12},
    {"generated double, FMA", "#009E73", 9},
    {"generated double, fast-math", "#D55E00", 11},
};

const VariantStyle& style_of(const std::string& variant) {
  for (const VariantStyle& s : variant_styles)
    if (s.variant == variant) return s;
  throw std::logic_error("internal error: the plot has no style for variant " + variant);
}

std::string point_style(const VariantStyle& s) {
  return fmt::format("lc rgb '{}' pt {} ps 1.8 lw 1.5", s.colour, s.point);
}

/// Labelled ticks of a logarithmic time axis over [lo, hi]: 1, 2 and 5 in every decade, or
/// decades only over more than two and a half of them, so that a short range has several.
std::string time_tics(double lo, double hi) {
  const bool fine = hi / lo < std::pow(10.0, 2.5);
  std::string tics;
  for (int e = static_cast<int>(std::floor(std::log10(lo))); std::pow(10.0, e) <= hi; ++e)
    for (const double m : fine ? std::vector<double>{1, 2, 5} : std::vector<double>{1})
      if (const double t = m * std::pow(10.0, e); t >= lo && t <= hi)
        tics += fmt::format("{}'{}' {:g}", tics.empty() ? "" : ", ", fmt::format("{:g}", t), t);
  return "(" + tics + ")";
}

/// The plot's data blocks and panels: one per algorithm, each point a variant's median error
/// against its median time, its bar reaching the worst error; a legend below them all.
std::string plot_script(const nlohmann::json& results, const std::string& robot, int states,
                        const std::string& banner) {
  const std::vector<std::string> algorithms = result_algorithms(results);
  const int panels = static_cast<int>(algorithms.size());
  const int columns = std::min(panels, 3), rows = (panels + columns - 1) / columns;
  const int panel_width = 520, panel_height = 420, title_height = 70, key_height = 90;
  const int width = columns * panel_width, height = title_height + rows * panel_height + key_height;
  std::string data, plots;
  for (int p = 0; p < panels; ++p) {
    const std::string& a = algorithms[p];
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
      series += fmt::format("{}${} every ::{}::{} using 1:2:3:4 with yerrorbars {} notitle",
                            k == 0 ? "plot " : ", \\\n     ", a, k, k,
                            point_style(style_of(r["variant"])));
      ++k;
    }
    data += fmt::format("${} << EOD\n{}EOD\n", a, block);
    // whole decades of error with a margin, so that no point sits on the frame
    const int y_from = static_cast<int>(std::floor(std::log10(y_lo) - 0.5));
    const int y_to = static_cast<int>(std::ceil(std::log10(y_hi) + 0.5));
    plots += fmt::format(
        "set origin {:.4f},{:.4f}\nset size {:.4f},{:.4f}\nset title '{}' noenhanced font ',14'\n"
        "set xrange [{:.3g}:{:.3g}]\nset xtics {}\nset yrange [1e{}:1e{}]\nset ytics {:g}\n{}\n",
        static_cast<double>(p % columns * panel_width) / width,
        static_cast<double>(key_height + (rows - 1 - p / columns) * panel_height) / height,
        static_cast<double>(panel_width) / width, static_cast<double>(panel_height) / height,
        algorithm_title(a), x_lo / 1.5, x_hi * 1.5, time_tics(x_lo / 1.5, x_hi * 1.5), y_from,
        y_to, std::pow(10.0, (y_to - y_from + 7) / 8), series);
  }
  // the legend: a panel of its own below the others, with every variant measured
  std::string key;
  for (const VariantStyle& s : variant_styles)
    for (const nlohmann::json& r : results)
      if (r["variant"] == s.variant) {
        key += fmt::format("{}NaN with points {} title '{}'", key.empty() ? "plot " : ", \\\n     ",
                           point_style(s), s.variant);
        break;
      }
  plots += fmt::format(
      "set origin 0,0\nset size 1,{:.4f}\nunset title\nunset border\nunset tics\nunset grid\n"
      "unset xlabel\nunset ylabel\nunset logscale\nset xrange [0:1]\nset yrange [0:1]\n"
      "set margins 0,0,0,0\n"
      "set key center center vertical maxrows 2 reverse Left width 3 samplen 1 spacing 1.5 "
      "font ',13'\n{}\n",
      static_cast<double>(key_height) / height, key);
  return fill("report_plot.gp.in",
              {{"banner", "# " + banner},
               {"script", "report.gp"},
               {"svg", "report.svg"},
               {"width", std::to_string(width)},
               {"height", std::to_string(height)},
               {"data", data},
               {"title", fmt::format("{} . ': relative error against time per call' . \"\\n\" . "
                                     "'{} random states: the point is the median error, the bar "
                                     "reaches the worst. Lower left is better: fewer errors, less "
                                     "time.'",
                                     gnuplot_string(robot), states)},
               {"plots", plots}});
}

/// report.md: the summary, the tables and the plot, every name and the command line in code
/// spans or blocks that show them as written.
std::string report_markdown(const Robot& robot, const ReportOptions& options,
                            const numerics::Conditioning& c, const nlohmann::json& report) {
  bool with_pivots = false;
  for (const Algorithm& a : options.algorithms)
    with_pivots = with_pivots || algorithm_spec(a).divides_by_pivots;
  std::string summary = fmt::format(
      "Robot {} from {} (sha256 {}): {} joints, nq = {}{}. dyngen {}.\n\n{}",
      markdown_code(robot.name), markdown_code(report["robot_file"].get<std::string>()),
      robot.sha256, robot.model.nv, robot.model.nq,
      options.model_flags.empty() ? "" : ", options " + markdown_code(options.model_flags),
      version, markdown_block(conditioning_text(c, with_pivots)));
  std::string pivots, joints;
  for (const nlohmann::json& left : report.value("float_left_out", nlohmann::json::array())) {
    const std::string a = left["algorithm"].get<std::string>();
    if (left["reason"] == "overflow") {
      summary += fmt::format("\n\nNo generated float {}: its values overflow float, so it cannot "
                             "be generated:\n\n{}",
                             a, markdown_block(left["detail"].get<std::string>()));
      continue;
    }
    pivots += (pivots.empty() ? "" : ", ") + a;
    joints.clear();
    for (const nlohmann::json& j : left["joints"])
      joints += (joints.empty() ? "" : ", ") + markdown_code(j.get<std::string>());
  }
  if (!pivots.empty())
    summary += fmt::format(
        "\n\nNo generated float ABA ({}): once the model's constants are rounded to float, these "
        "joints move no inertia, so it cannot be generated (the runtime's float ABA divides by "
        "zero there): {}.",
        pivots, joints);
  return fill("report.md.in",
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
               {"command", markdown_code(options.command)}});
}

/// The first line of every file the report writes, for a comment.
std::string banner_text(const Robot& robot) {
  return fmt::format("Written by dyngen {} report for robot '{}' ({}); rewritten on every run.",
                     version, safe_text(robot.name),
                     safe_text(fs::path(robot.path).filename().string()));
}

bool have_gnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

}  // namespace

void make_report(const Robot& robot, const ReportOptions& options, const std::string& dir) {
  const std::string name = identifier(robot.name);
  const fs::path out_dir(dir);
  const fs::path work = out_dir / "harness";
  if (const std::vector<std::string> foreign =
          foreign_entries(out_dir, {std::begin(report_files), std::end(report_files)}, {"harness"});
      !options.force && !foreign.empty())
    throw FileError(fmt::format(
        "{}: exists and holds files that dyngen report did not write ({}); it writes only into a "
        "new or empty directory or over an earlier report. Choose another directory, or give "
        "--force to write into it (its report files and harness/ are replaced, the rest kept).",
        dir, listed(foreign)));
  fs::create_directories(work);
  const auto step = [&](int k, const std::string& text) {
    if (!options.quiet) fmt::print("[{}/5] {}\n", k, text), std::fflush(stdout);
  };

  step(1, "generating the code: double, float, double for FMA, double for fast-math");
  const std::vector<Algorithm>& all = options.algorithms;
  const FloatPlan in_float = float_plan(robot, all);
  const numerics::Conditioning c = write_variant(robot, options, all, name, false, work / "double",
                                                 true);
  write_variant(robot, options, in_float.kept, name + "_float", true, work / "float", false);
  write_variant(robot, options, all, name + "_fma", false, work / "fma", false);
  write_variant(robot, options, all, name + "_fastmath", false, work / "fastmath", false);
  const std::string banner = banner_text(robot);
  write_file(work / "CMakeLists.txt",
             fill("report_CMakeLists.txt.in", {{"banner", "# " + banner},
                                                {"name", name},
                                                {"robot", safe_text(robot.name)}}));
  write_file(work / "variants.cpp",
             fill("report_variants.cpp.in",
                  {{"banner", "// " + banner},
                   {"name", name},
                   {"robot", safe_text(robot.name)},
                   {"variants", harness_variants(options.algorithms, in_float.kept, name)}}));

  step(2, fmt::format("configuring the harness in {}", work.string()));
  const fs::path build = work / "build";
  run_logged("configuring the harness",
      fmt::format("cmake -S {} -B {} -Ddyngen_DIR={}", shell_quoted(work.string()),
                  shell_quoted(build.string()), shell_quoted(options.package_dir)),
      work / "configure.log", false);
  step(3, "building the harness (the generated code four ways, in parallel)");
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
  nlohmann::json measured;
  std::ifstream(results_path) >> measured;
  measured["float_left_out"] = in_float.left_out;
  write_report(robot, options, c, measured, dir);
}

std::vector<std::string> write_report(const Robot& robot, const ReportOptions& options,
                                      const numerics::Conditioning& c, nlohmann::json report,
                                      const std::string& dir) {
  const fs::path out_dir(dir);
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
  const std::string banner = banner_text(robot);
  const std::string script =
      plot_script(report["results"], robot.name, report["states"].get<int>(), banner);

  // every file under a temporary name first, then renamed into place
  const std::string tmp = ".tmp";
  std::vector<std::string> written = {"report.md", "report.json", "report.gp"};
  try {
    write_file(out_dir / ("report.md" + tmp), report_markdown(robot, options, c, report));
    // names that are not UTF-8 reach JSON with U+FFFD in place of their invalid bytes
    write_file(out_dir / ("report.json" + tmp),
               report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    write_file(out_dir / ("report.gp" + tmp), script);
    if (have_gnuplot()) {
      written.push_back("report.svg");
      fs::create_directories(out_dir / "harness");
      run_logged("drawing the plot with gnuplot",
          fmt::format("cd {} && gnuplot -e \"output_file='report.svg{}'\" report.gp{} && "
                      "test -s report.svg{}",
                      shell_quoted(out_dir.string()), tmp, tmp, tmp),
          out_dir / "harness" / "plot.log", false);
    } else {
      fmt::print(stderr, "dyngen report: warning: gnuplot not found; no plot drawn (install "
                         "gnuplot-nox, then run gnuplot report.gp in {})\n", safe_text(dir));
    }
  } catch (...) {
    std::error_code ignored;
    for (const std::string& f : written) fs::remove(out_dir / (f + tmp), ignored);
    throw;
  }
  std::vector<std::string> paths;
  for (const std::string& f : written) {
    fs::rename(out_dir / (f + tmp), out_dir / f);
    paths.push_back((out_dir / f).string());
  }
  if (!options.quiet)
    fmt::print("{}wrote {}\n", markdown_tables(report["results"]), fmt::join(paths, " "));
  return paths;
}

}  // namespace dyngen::gen
