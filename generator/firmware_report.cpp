#include "firmware_report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "backend.hpp"
#include "footprint.hpp"
#include "names.hpp"
#include "output.hpp"
#include "process.hpp"
#include "template.hpp"

namespace dyngen::gen {

namespace fs = std::filesystem;

namespace {

/// Symbols that must not be in an image: the C library's allocation and copying, libm.
constexpr const char* forbidden_symbols[] = {"malloc", "free",  "calloc", "realloc",
                                             "memset", "memcpy", "sin",   "cos",
                                             "sinf",   "cosf",  "sqrt",   "sqrtf"};

const char* qemu_machine(Target target) {
  switch (target) {
    case Target::CortexM4F: return "mps2-an386";
    case Target::CortexM7: return "mps2-an500";
    case Target::CortexM33: return "mps2-an505";
    default: return nullptr;
  }
}

const char* processor_name(Target target) {
  return target == Target::CortexM4F ? "Cortex-M4F" : target == Target::CortexM7 ? "Cortex-M7"
                                                                                 : "Cortex-M33";
}

std::string words(const std::vector<std::string>& list) {
  std::string text;
  for (const std::string& w : list) text.append(text.empty() ? "" : " ").append(shell_quoted(w));
  return text;
}

std::string extent_expression(const Extent& e) {
  return extent_text(e, "nq", "nv", "nframes", "nbodies", "nc");
}

/// main's loop body: each function on state s, between the markers, its outputs printed.
std::string harness_calls(const std::vector<Algorithm>& algorithms, const Dialect& dialect) {
  std::string text;
  for (std::size_t k = 0; k < algorithms.size(); ++k) {
    const AlgorithmSpec<double>& spec = algorithm_spec(algorithms[k]);
    std::string arrays, fills, arguments, prints;
    for (const auto* list : {&spec.inputs, &spec.outputs})
      for (const ArraySpec& a : *list) {
        arrays += fmt::format("{}{}[{}]", arrays.empty() ? "" : ", ", a.name,
                              extent_expression(a.extent));
        arguments += fmt::format("{}{}", arguments.empty() ? "" : ", ", a.name);
      }
    for (const ArraySpec& a : spec.inputs)
      fills += a.name == "q" ? "      fill_q(q, s);\n"
                             : fmt::format("      fill({}, {}, {});\n", a.name,
                                           extent_expression(a.extent),
                                           a.name == "v" ? 1 : a.name == "tau" ? 4 : 2);
    for (const ArraySpec& a : spec.outputs)
      prints += fmt::format("      print(\"{}\", s, {}, {});\n", spec.name, a.name,
                            extent_expression(a.extent));
    const std::string& name = algorithms[k];
    const std::string call = dialect.qualified(name);
    text += fmt::format(
        "    {{  // {0}\n"
        "      static Scalar {1};\n"
        "{2}"
        "      MEASURED(dyngen_call_begin(); {3}({4}); dyngen_call_end(), stack_use[{5}]);\n"
        "{6}"
        "    }}\n",
        algorithms[k], arrays, fills, call, arguments, k, prints);
  }
  return text;
}

/// Lines of text that do not start with `prefix`, and those that do.
std::pair<std::string, std::vector<std::string>> split_lines(const std::string& text,
                                                             const std::string& prefix) {
  std::string rest;
  std::vector<std::string> matching;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.starts_with(prefix)) matching.push_back(line.substr(prefix.size()));
    else rest += line + "\n";
  return {rest, matching};
}

/// Instructions qemu executed between each dyngen_call_begin() and the following
/// dyngen_call_end(), in order: its exec log, one line per instruction ("Trace 0: host
/// [.../pc/...] symbol"), read as it runs. The log goes to the pipe through /proc rather than
/// /dev/stdout, which a machine can lack (qemu would then write a regular file there).
std::vector<long> instructions_per_call(const std::string& qemu, const fs::path& elf) {
  const std::string command =
      fmt::format("{} -singlestep -d exec,nochain -D /proc/self/fd/1 -kernel {} 2>&1", qemu,
                  shell_quoted(elf.string()));
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw InputError("cannot start " + command);
  std::vector<long> counts;
  bool counting = false;
  long n = 0;
  long traced = 0;
  char line[1024];
  while (std::fgets(line, sizeof line, pipe)) {
    const std::string_view text(line);
    if (!text.starts_with("Trace ")) continue;
    ++traced;
    const bool in_begin = text.find(" dyngen_call_begin") != std::string_view::npos;
    const bool in_end = text.find(" dyngen_call_end") != std::string_view::npos;
    if (in_begin) {
      counting = true;
      n = 0;
    } else if (in_end && counting) {
      counts.push_back(n);
      counting = false;
    } else if (counting) {
      ++n;
    }
  }
  if (const int status = pclose(pipe); status != 0)
    throw InputError(fmt::format("counting instructions under qemu failed (exit status {}): {}",
                                 status, command));
  if (traced == 0)
    throw InputError("counting instructions under qemu: its execution log (-d exec) held no "
                     "trace lines: " + command);
  return counts;
}

/// Where firmware-report works, and what the package was generated as.
struct FirmwareBuild {
  const Robot& robot;
  const FirmwareReportOptions& options;
  const Generated& generated;
  fs::path package_dir, build;
  std::string target;  // its name: "cortex-m4f"
  bool single;
  std::string ns;
  const Dialect& dialect;  // the package's language
};

/// The harness (templates/firmware_harness.cpp.in), the startup code and the linker script of
/// the target, in b.build.
void write_harness(const FirmwareBuild& b) {
  const GenerateOptions& generate_options = b.options.generate;
  const Dialect& dialect = b.dialect;
  const std::string& ns = b.ns;
  std::string quaternions;
  for (int i = 0; i < b.robot.model.nbodies; ++i)
    if (const int o = quaternion_offset(b.robot.model.joint_type[i]); o >= 0)
      quaternions += fmt::format(
          "  for (int k = 0; k < 4; ++k) q[{} + k] = next(0) < 0 ? -Scalar(0.5) : Scalar(0.5);\n",
          b.robot.model.q_index[i] + o);
  std::string stack_prints;
  for (std::size_t k = 0; k < generate_options.algorithms.size(); ++k)
    stack_prints += fmt::format("  print_stack(\"{}\", stack_use[{}]);\n",
                                generate_options.algorithms[k], k);
  write_file(
      b.build / "harness.cpp",
      fill(
          "firmware_harness.cpp.in",
          {{"name", ns},
           {"header", dialect.header()},
           {"scalar", b.single ? "float" : "double"},
           {"states", std::to_string(b.options.states)},
           {"nq", dialect.size_outside("nq")},
           {"nv", dialect.size_outside("nv")},
           {"frames_constant",
            (b.generated.nframes == 0
                 ? ""
                 : fmt::format("constexpr int nframes = {};", dialect.size_outside("nframes"))) +
                (uses_bodies(generate_options.algorithms)
                     ? fmt::format("\nconstexpr int nbodies = {};", dialect.size_outside("nbodies"))
                     : "") +
                (b.robot.model.nc > 0
                     ? fmt::format("\nconstexpr int nc = {};", dialect.size_outside("nc"))
                     : "")},
           {"quaternions", quaternions},
           {"functions", std::to_string(generate_options.algorithms.size())},
           {"calls", harness_calls(generate_options.algorithms, dialect)},
           {"stack_prints", stack_prints}}));
  write_file(b.build / "startup.c", std::string(template_text("startup.c")));
  std::string linker_script(template_text("cortex_m.ld"));
  if (generate_options.target == Target::CortexM33) {
    // mps2-an505 starts a Cortex-M33 in the secure state at 0x10000000, SRAM secure at 0x38000000
    for (const auto& [from, to] : {std::pair{"ORIGIN = 0x00000000", "ORIGIN = 0x10000000"},
                                   std::pair{"ORIGIN = 0x20000000", "ORIGIN = 0x38000000"}}) {
      const std::size_t at = linker_script.find(from);
      if (at == std::string::npos)
        throw std::logic_error(std::string("internal error: cortex_m.ld has no ") + from);
      linker_script.replace(at, std::string_view(from).size(), to);
    }
  }
  write_file(b.build / "cortex_m.ld", linker_script);
}

/// The images for the target (firmware.elf over every state, count.elf over one) and the
/// harness for the host, from the files write_harness wrote.
void compile_images(const FirmwareBuild& b) {
  const Dialect& dialect = b.dialect;
  const std::unique_ptr<Backend> c = language_backend("c", b.ns), cxx = language_backend("c++", b.ns);
  const fs::path& build = b.build;
  const Toolchain cross = toolchain(b.target), host = toolchain("host");
  std::vector<std::string> warnings{"-Wall", "-Wextra", "-Werror"};
  if (b.single) warnings.push_back("-Wdouble-promotion");
  const auto path = [](const fs::path& p) { return shell_quoted(p.string()); };
  const std::string package_flags = words(compile_flags(cross, dialect)) + " " + words(warnings);
  const std::string cxx_flags = words(compile_flags(cross, *cxx->dialect())) + " " + words(warnings);
  const std::string include = "-I" + path(b.package_dir);
  auto compile = [&](const std::string& what, const std::string& command) {
    output_of(command, what);
  };
  compile("cross-compiling the package",
          fmt::format("{} {} {} -c {} -o {}", words(dialect.compiler(cross)), package_flags,
                      dialect.standard_flag(), path(b.package_dir / dialect.source()),
                      path(build / "dynamics.o")));
  compile("cross-compiling startup.c",
          fmt::format("{} {} -std=c99 -c {} -o {}", words(cross.c),
                      words(compile_flags(cross, *c->dialect())), path(build / "startup.c"),
                      path(build / "startup.o")));
  for (const auto& [image, states] :
       {std::pair{"firmware", b.options.states}, std::pair{"count", 1}}) {
    compile("cross-compiling the harness",
            fmt::format("{} {} -std=c++17 -DSTATES={} {} -c {} -o {}", words(cross.cxx),
                        cxx_flags, states, include, path(build / "harness.cpp"),
                        path(build / (std::string(image) + "_harness.o"))));
    compile("linking the image",
            fmt::format("{} {} -nostdlib -T {} {} {} {} -lgcc -o {}", words(cross.cxx),
                        words(cross.flags), path(build / "cortex_m.ld"), path(build / "startup.o"),
                        path(build / (std::string(image) + "_harness.o")),
                        path(build / "dynamics.o"), path(build / (std::string(image) + ".elf"))));
  }
  compile("compiling the package for the host",
          fmt::format("{} {} {} -c {} -o {}", words(dialect.compiler(host)),
                      words(compile_flags(host, dialect)), dialect.standard_flag(),
                      path(b.package_dir / dialect.source()), path(build / "host_dynamics.o")));
  compile("compiling the harness for the host",
          fmt::format("{} {} -std=c++17 {} {} {} -o {}", words(host.cxx),
                      words(compile_flags(host, *cxx->dialect())), include, path(build / "harness.cpp"),
                      path(build / "host_dynamics.o"), path(build / "host")));

}

/// What running the images showed.
struct FirmwareRun {
  bool equal = false;                         // the target's outputs are the host's, bit for bit
  std::vector<std::string> linked_forbidden;  // C library or libm symbols in the image
  bool soft_double = false;                   // software double in the image
  std::map<std::string, long> stack_used;     // by function: bytes, painted stack
};

/// Runs firmware.elf under qemu and the harness on the host, and reads the image's symbols.
FirmwareRun run_images(const FirmwareBuild& b, const std::string& qemu) {
  const auto path = [](const fs::path& p) { return shell_quoted(p.string()); };
  FirmwareRun run;
  const std::string symbols =
      output_of(fmt::format("{} {}", words(toolchain(b.target).nm), path(b.build / "firmware.elf")),
                "reading the image's symbols");
  for (const char* name : forbidden_symbols)
    if (symbols.find(fmt::format(" {}\n", name)) != std::string::npos)
      run.linked_forbidden.push_back(name);
  run.soft_double = symbols.find(" __aeabi_d") != std::string::npos;
  const auto [target_lines, stack_lines] =
      split_lines(output_of(fmt::format("{} -kernel {}", qemu, path(b.build / "firmware.elf")),
                            "running the harness under qemu"),
                  "stack ");
  const std::string host_lines =
      output_of(path(b.build / "host"), "running the harness on the host");
  run.equal = target_lines == host_lines && !host_lines.empty();
  for (const std::string& line : stack_lines) {
    const std::size_t space = line.find(' ');
    run.stack_used[line.substr(0, space)] = std::stol(line.substr(space + 1));
  }
  return run;
}

/// firmware-report.md and .json in out_dir; returns what failed, and prints the Markdown
/// unless quiet.
std::vector<std::string> write_firmware_report(const FirmwareBuild& b, FirmwareRun run,
                                               const std::vector<long>& instructions,
                                               const char* machine, const fs::path& out_dir) {
  const FirmwareReportOptions& options = b.options;
  const GenerateOptions& generate_options = options.generate;
  const Generated& generated = b.generated;
  const Robot& robot = b.robot;
  const bool single = b.single, equal = run.equal, soft_double = run.soft_double;
  const std::string& target = b.target;
  const std::vector<std::string>& linked_forbidden = run.linked_forbidden;
  std::map<std::string, long>& stack_used = run.stack_used;
  std::vector<std::string> failed;
  if (!equal) failed.push_back("the Cortex-M's outputs differ from the host's");
  if (!linked_forbidden.empty())
    failed.push_back("the image links " + fmt::format("{}", fmt::join(linked_forbidden, ", ")));
  if (single && soft_double) failed.push_back("the float image links software double");
  nlohmann::json report;
  report["robot"] = robot.name;
  report["target"] = target;
  report["machine"] = machine;
  report["compiler"] = generated.footprint->compiler;
  report["scalar"] = single ? "float" : "double";
  report["lang"] = b.dialect.language();
  report["states"] = options.states;
  report["bits_equal"] = equal;
  report["forbidden_symbols"] = linked_forbidden;
  report["software_double"] = soft_double;
  report["shared_code_bytes"] = generated.footprint->common_code_bytes;
  std::string rows;
  for (std::size_t k = 0; k < generate_options.algorithms.size(); ++k) {
    const FunctionFootprint& f = generated.footprint->functions[k];
    const long used = stack_used.count(f.algorithm) ? stack_used[f.algorithm] : 0;
    const std::optional<long> bound = f.stack_bound;
    const bool within = bound && used > 0 && used <= *bound && 2 * *bound <= 3 * used;
    if (!within)
      failed.push_back(fmt::format("{}: stack measured {} bytes against the bound {}", f.algorithm,
                                   used, bound ? std::to_string(*bound) : "none"));
    report["functions"].push_back({{"name", f.algorithm},
                                   {"code_bytes", f.code_bytes},
                                   {"stack_bound", bound ? nlohmann::json(*bound) : nullptr},
                                   {"stack_measured", used},
                                   {"instructions", instructions[k]}});
    rows += fmt::format("| {} | {} | {} | {} | {} |\n", f.algorithm, f.code_bytes,
                        bound ? std::to_string(*bound) : "unbounded", used, instructions[k]);
  }
  report["failed"] = failed;
  const std::string yes_no_equal = equal ? "yes" : "**no**";
  std::string markdown = fmt::format(
      "# dyngen firmware report: {} on a {} (qemu {})\n\n"
      "The {} {} package in package/, compiled by {}.\n\n"
      "| function | code bytes | stack bound | stack measured | instructions per call |\n"
      "|---|---:|---:|---:|---:|\n{}\n"
      "Code: the function, its _trig form, their shared functions and tables; sin, cos and what "
      "else the functions share take {} bytes more. Stack bound: the banner's, from "
      "-fstack-usage on the call graph; measured: the most the call overwrote below its caller "
      "(painted stack) over {} states. Instructions: one call at the first state, its set-up "
      "included.\n\n"
      "- Outputs equal to the host's, bit for bit, at every state: {}\n"
      "- C library or libm in the image ({}): {}\n"
      "- Software double in the image: {}\n"
      "- Every stack bound at least the measured use and at most 1.5 times it: {}\n",
      markdown_code(robot.name), processor_name(generate_options.target), machine,
      single ? "float" : "double", b.dialect.title(),
      markdown_code(generated.footprint->compiler), rows,
      generated.footprint->common_code_bytes, options.states, yes_no_equal,
      fmt::join(forbidden_symbols, ", "),
      linked_forbidden.empty() ? "none" : fmt::format("**{}**", fmt::join(linked_forbidden, ", ")),
      soft_double ? (single ? "**yes**" : "yes (double on this FPU)") : "none",
      std::none_of(failed.begin(), failed.end(),
                   [](const std::string& f) { return f.find(": stack") != std::string::npos; })
          ? "yes"
          : "**no**");
  markdown +=
      fmt::format("\nGenerated by {} (dyngen {}).\n", markdown_code(options.command), version);
  // names that are not UTF-8 reach JSON with U+FFFD in place of their invalid bytes
  const std::string json = report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  write_file(out_dir / "firmware-report.md", markdown);
  write_file(out_dir / "firmware-report.json", json + "\n");
  if (!options.quiet) fmt::print("{}", markdown);
  return failed;
}

}  // namespace

std::vector<std::string> make_firmware_report(const Robot& robot,
                                              const FirmwareReportOptions& options,
                                              const std::string& dir) {
  const GenerateOptions& generate_options = options.generate;
  const char* machine = qemu_machine(generate_options.target);
  const std::string target = target_names[static_cast<int>(generate_options.target)];
  if (!machine)
    throw InputError(fmt::format("--target {}: dyngen firmware-report runs {}", target,
                                 fmt::join(firmware_report_targets, ", ")));
  const fs::path out_dir(dir), package_dir = out_dir / "package", build = out_dir / "build";
  if (const std::vector<std::string> foreign = foreign_entries(
          out_dir, {std::begin(firmware_report_files), std::end(firmware_report_files)},
          {"package", "build"});
      !options.force && !foreign.empty())
    throw FileError(fmt::format(
        "{}: exists and holds files that dyngen firmware-report did not write ({}); it writes "
        "only into a new or empty directory or over an earlier report. Choose another directory, "
        "or give --force to write into it (its report files, package/ and build/ are replaced, "
        "the rest kept).",
        dir, listed(foreign)));
  const auto step = [&](int k, const std::string& text) {
    if (!options.quiet) fmt::print("[{}/5] {}\n", k, text), std::fflush(stdout);
  };
  const std::string qemu =
      fmt::format("timeout 1800 qemu-system-arm -machine {} -nographic -monitor none -serial none "
                  "-semihosting-config enable=on,target=native",
                  machine);
  output_of("qemu-system-arm --version", "running the firmware needs qemu-system-arm");

  step(1, fmt::format("generating the package into {}, measuring it for {}",
                      package_dir.string(), target));
  GenerateOptions package_options = generate_options;
  package_options.measure = true;
  const Generated generated = generate(robot, package_options);
  write_package(package_dir.string(), generated.files, options.force);
  const std::string& ns = generate_options.name;
  const std::unique_ptr<Backend> language = language_backend(generate_options.language, ns);
  const FirmwareBuild b{robot,
                        options,
                        generated,
                        package_dir,
                        build,
                        target,
                        generate_options.single_precision,
                        ns,
                        *language->dialect()};

  step(2, fmt::format("writing and cross-compiling the harness in {}", build.string()));
  fs::remove_all(build);
  fs::create_directories(build);
  write_harness(b);
  compile_images(b);

  step(3, fmt::format("running {} states on qemu's {} and on the host", options.states, machine));
  FirmwareRun run = run_images(b, qemu);

  step(4, "counting the instructions of each call (qemu's execution log)");
  const std::vector<long> instructions = instructions_per_call(qemu, build / "count.elf");
  if (instructions.size() != generate_options.algorithms.size())
    throw std::runtime_error(fmt::format("internal error: {} calls counted, {} made",
                                         instructions.size(),
                                         generate_options.algorithms.size()));

  step(5, "writing the report");
  return write_firmware_report(b, std::move(run), instructions, machine, out_dir);
}

}  // namespace dyngen::gen
