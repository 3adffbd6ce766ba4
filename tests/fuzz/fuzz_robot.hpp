// What every fuzz target of a robot file checks (tests/fuzz/README.md): the text loads as a
// robot or is refused as bad input (InputError), and a robot that loads generates code that is
// refused as bad input or whose every file is safe text: no control character but the newline,
// no Unicode line separator, no backslash at a line's end, and a namespace that is a plain
// identifier. Anything else (another exception, a crash, a sanitizer report) is a finding.
#pragma once

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "generate.hpp"
#include "robot.hpp"

namespace dyngen::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

inline void check_safe_text(const gen::GeneratedFile& file) {
  const std::string_view text = file.text;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if ((c < 0x20 && c != '\n') || c == 0x7f)
      finding(file.name + ": control character " + std::to_string(c) + " at byte " +
              std::to_string(k));
    if (c == '\\' && k + 1 < text.size() && text[k + 1] == '\n')
      finding(file.name + ": backslash at the end of a line, at byte " + std::to_string(k));
    // U+0085, U+2028 and U+2029 end lines for some compilers and editors
    if ((c == 0xc2 && k + 1 < text.size() && static_cast<unsigned char>(text[k + 1]) == 0x85) ||
        (c == 0xe2 && text.substr(k + 1, 2) == "\x80\xa8") ||
        (c == 0xe2 && text.substr(k + 1, 2) == "\x80\xa9"))
      finding(file.name + ": Unicode line separator at byte " + std::to_string(k));
  }
}

inline void check_identifier(const std::string& name) {
  if (name.empty() || name.size() > 128 || !(std::isalpha(static_cast<unsigned char>(name[0]))))
    finding("namespace '" + name + "' is not a plain identifier");
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
      finding("namespace '" + name + "' is not a plain identifier");
  if (name.find("__") != std::string::npos) finding("namespace '" + name + "' is reserved");
}

/// Loads `text` as the robot file `path`, and generates code for it when it is small enough to
/// keep the fuzzer fast. Options come from `flags`' bits.
inline void load_and_generate(const std::string& path, const std::string& text, unsigned flags) {
  gen::LoadOptions load;
  load.floating_base = flags & 1;
  load.mimic_independent = flags & 2;
  load.lock_massless = flags & 4;
  gen::Robot robot;
  try {
    robot = gen::parse_robot(path, text, load);
  } catch (const gen::InputError&) {
    return;
  } catch (const std::exception& e) {
    finding(std::string("loading threw ") + e.what());
  }
  if (robot.model.nbodies > 12) return;
  gen::GenerateOptions options;
  options.name = gen::identifier(robot.name);
  options.single_precision = flags & 8;
  options.conditioning_samples = 2;
  check_identifier(options.name);
  try {
    for (const gen::GeneratedFile& file : gen::generate(robot, options).files)
      check_safe_text(file);
  } catch (const gen::InputError&) {
  } catch (const std::exception& e) {
    finding(std::string("generating threw ") + e.what());
  }
}

}  // namespace dyngen::fuzz
