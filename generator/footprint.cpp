#include "footprint.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "process.hpp"
#include "robot.hpp"

namespace dyngen::gen {

namespace fs = std::filesystem;

namespace {

/// The function a call graph label or an nm line names: "ur5::rnea" of
/// "void ur5::rnea(const double*, double*)", "dyngen_sc_bits_at" of "dyngen_sc_bits_at.constprop".
std::string function_name(std::string text) {
  text = text.substr(0, text.find('('));
  if (const std::size_t space = text.rfind(' '); space != std::string::npos)
    text = text.substr(space + 1);
  return text.substr(0, text.find('.'));
}

struct CallGraph {
  std::map<std::string, std::string> name;            // by node title
  std::map<std::string, std::optional<long>> frame;   // by node title; empty: not bounded
  std::map<std::string, std::vector<std::string>> callees;
};

/// GCC's -fcallgraph-info=su file: a VCG graph whose nodes are the functions, labelled with
/// their name, place and frame ("N bytes (static)"), and whose edges are the calls. Routines of
/// the compiler's library (software double) are labelled "<built-in>": they get `builtin_frame`
/// (none: unbounded).
CallGraph read_call_graph(const fs::path& path, std::optional<long> builtin_frame) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("the compiler wrote no call graph {}", path.string()));
  static const std::regex node(R"re(^node: \{ title: "([^"]*)" label: "([^"]*)")re");
  static const std::regex edge(R"re(^edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)")re");
  static const std::regex frame(R"re(\\n([0-9]+) bytes \((static|dynamic,bounded)\))re");
  CallGraph graph;
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (std::regex_search(line, m, node)) {
      const std::string title = m[1], label = m[2];
      graph.name[title] = function_name(label.substr(0, label.find("\\n")));
      std::smatch f;
      if (label.ends_with("\\n<built-in>"))
        graph.frame[title] = builtin_frame;
      else if (std::regex_search(label, f, frame))
        graph.frame[title] = std::stol(f[1]);
      else
        graph.frame[title] = std::nullopt;  // dynamic, or a function defined elsewhere
    } else if (std::regex_search(line, m, edge)) {
      graph.callees[m[1]].push_back(m[2]);
    }
  }
  return graph;
}

/// The deepest chain of frames from `title` down its calls; empty if a frame on some chain has
/// no bound, or the chain recurses.
std::optional<long> deepest(const CallGraph& graph, const std::string& title,
                            std::map<std::string, std::optional<long>>& memo,
                            std::set<std::string>& open) {
  if (const auto it = memo.find(title); it != memo.end()) return it->second;
  const auto own = graph.frame.find(title);
  if (own == graph.frame.end() || !own->second || !open.insert(title).second) return std::nullopt;
  long below = 0;
  bool bounded = true;
  if (const auto calls = graph.callees.find(title); calls != graph.callees.end())
    for (const std::string& callee : calls->second) {
      const std::optional<long> d = deepest(graph, callee, memo, open);
      if (!d) bounded = false;
      else below = std::max(below, *d);
    }
  open.erase(title);
  return memo[title] = bounded ? std::optional<long>(*own->second + below) : std::nullopt;
}

/// A command's words followed by more.
std::vector<std::string> followed_by(std::vector<std::string> words,
                                     const std::vector<std::string>& more) {
  words.insert(words.end(), more.begin(), more.end());
  return words;
}

}  // namespace

Toolchain toolchain(const std::string& target) {
  Toolchain t;
  if (target == "host") {
    // as make and CMake take them: words, the first the compiler ("ccache g++", "gcc -m32")
    const char* cc = std::getenv("CC");
    const char* cxx = std::getenv("CXX");
    t.c = command_words(cc ? cc : "");
    t.cxx = command_words(cxx ? cxx : "");
    if (t.c.empty()) t.c = {"cc"};
    if (t.cxx.empty()) t.cxx = {"c++"};
    t.nm = {"nm"};
    // one instruction set, the baseline: each of a function's clones (DYNGEN_DISPATCH) would
    // have its own code and stack
    t.flags = {"-DDYNGEN_NO_DISPATCH"};
    return t;
  }
  t.c = {"arm-none-eabi-gcc"};
  t.cxx = {"arm-none-eabi-g++"};
  t.nm = {"arm-none-eabi-nm"};
  if (target == "cortex-m4f")
    t.flags = {"-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-mthumb"};
  else if (target == "cortex-m7")
    t.flags = {"-mcpu=cortex-m7", "-mfpu=fpv5-d16", "-mfloat-abi=hard", "-mthumb"};
  else if (target == "cortex-m33")
    t.flags = {"-mcpu=cortex-m33", "-mfpu=fpv5-sp-d16", "-mfloat-abi=hard", "-mthumb"};
  else
    throw std::invalid_argument("no toolchain for target " + target);
  t.flags.push_back("-ffreestanding");
  // libgcc's software double for Thumb-2 (ieee754-df.S) pushes at most 16 bytes and calls
  // nothing; the bound allows twice that
  t.libgcc_frame = 32;
  return t;
}

std::vector<std::string> compile_flags(const Toolchain& toolchain, const Dialect& dialect) {
  std::vector<std::string> flags = toolchain.flags;
  flags.insert(flags.end(), {"-O2", "-ffp-contract=off", "-fno-fast-math"});
  const std::vector<std::string> language = dialect.language_flags();
  flags.insert(flags.end(), language.begin(), language.end());
  return flags;
}

Footprint measure_footprint(const std::vector<GeneratedFile>& files, const Dialect& dialect,
                            const std::vector<std::string>& algorithms, const Toolchain& toolchain) {
  const std::vector<std::string>& compiler = dialect.compiler(toolchain);
  const std::string source = dialect.source(), prefix = dialect.prefix();
  const fs::path dir =
      fs::temp_directory_path() / fmt::format("dyngen-footprint-{}", static_cast<long>(getpid()));
  struct Scratch {
    fs::path dir;
    ~Scratch() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  } scratch{dir};
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const GeneratedFile& f : files) write_file(dir / f.name, f.text);

  // run without a shell: $CXX is words, not a command line
  const std::string version =
      output_of(followed_by(compiler, {"-dumpfullversion"}),
                fmt::format("measuring the code needs {} (GCC)", fmt::join(compiler, " ")));
  const std::vector<std::string> flags = compile_flags(toolchain, dialect);
  const fs::path object = dir / "package.o";
  // without identical code folding, each function keeps its own code and call graph node (GCC
  // would otherwise make aba_derivatives_shape_0 an alias of an identical aba_shape_0)
  output_of(followed_by(followed_by(compiler, flags),
                        {dialect.standard_flag(), "-fno-ipa-icf", "-fstack-usage",
                         "-fcallgraph-info=su", "-c", (dir / source).string(), "-o",
                         object.string()}),
            "compiling the package to measure it");

  Footprint footprint;
  footprint.compiler = fmt::format("{} {}", fmt::join(compiler, " "),
                                   version.substr(0, version.find('\n')));
  for (const std::string& f : flags) footprint.compiler += " " + f;

  // code bytes by symbol: what belongs to one algorithm, and what they share
  const std::string symbols =
      output_of(followed_by(toolchain.nm, {"-S", "-C", "--defined-only", object.string()}),
                "reading the measured package's symbols");
  std::map<std::string, long> code;
  std::istringstream lines(symbols);
  std::string line;
  static const std::regex sized(R"(^[0-9a-f]+ ([0-9a-f]+) [A-Za-z] (.*)$)");
  std::smatch m;
  std::vector<std::regex> owns;  // an algorithm's symbols: f, f_trig, f_shape_N and its table
  for (const std::string& a : algorithms)
    owns.emplace_back("^" + a + "(_trig|_shape_[0-9]+(_k)?)?$");
  while (std::getline(lines, line)) {
    if (!std::regex_match(line, m, sized)) continue;  // labels without a size
    std::string name = function_name(m[2]);
    if (name.starts_with(prefix)) name = name.substr(prefix.size());
    long owner = -1;
    for (std::size_t a = 0; a < owns.size() && owner < 0; ++a)
      if (std::regex_match(name, owns[a])) owner = static_cast<long>(a);
    const long bytes = std::stol(m[1], nullptr, 16);
    if (owner < 0) footprint.common_code_bytes += bytes;
    else code[algorithms[owner]] += bytes;
  }

  const CallGraph graph = read_call_graph(dir / "package.ci", toolchain.libgcc_frame);
  std::map<std::string, std::string> title_of;
  for (const auto& [title, name] : graph.name) title_of[name] = title;
  std::map<std::string, std::optional<long>> memo;
  auto bound = [&](const std::string& function) -> std::optional<long> {
    const auto it = title_of.find(prefix + function);
    if (it == title_of.end())
      throw std::logic_error("internal error: no " + prefix + function + " in the call graph");
    std::set<std::string> open;
    return deepest(graph, it->second, memo, open);
  };
  for (const std::string& a : algorithms)
    footprint.functions.push_back({a, code[a], bound(a), bound(a + "_trig")});
  return footprint;
}

std::string footprint_text(const Footprint& footprint) {
  auto stack = [](const std::optional<long>& bytes) {
    return bytes ? fmt::format("{}", *bytes) : std::string("unbounded");
  };
  std::string text =
      "Code and stack in bytes (code: the function, its _trig form, their shared functions and\n"
      "tables; stack: an upper bound from -fstack-usage on the call graph, for f(q, ...) and\n"
      "f_trig(q, trig, ...)), compiled by";
  std::size_t column = 80;
  std::istringstream words(footprint.compiler);
  for (std::string word; words >> word; column += word.size() + 1) {
    if (column + word.size() > 96) text += "\n ", column = 1;
    text += " " + word;
  }
  text += ":";
  for (const FunctionFootprint& f : footprint.functions)
    text += fmt::format("\n  {:<18} code {:>7}   stack {:>6} / {}", f.algorithm, f.code_bytes,
                        stack(f.stack_bound), stack(f.trig_stack_bound));
  return text + fmt::format("\n  {:<18} code {:>7}", "shared (trig, ...)",
                            footprint.common_code_bytes);
}

}  // namespace dyngen::gen
