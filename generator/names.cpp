#include "names.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <set>
#include <unordered_set>
#include <vector>

#include <fmt/format.h>

#include "template.hpp"
#include "trace.hpp"

namespace dyngen::gen {

namespace {

/// The length of the valid UTF-8 sequence at text[k] (2 to 4) and its code point, or 0.
std::size_t utf8_sequence(std::string_view text, std::size_t k, std::uint32_t& code) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char c = byte(k);
  std::size_t n = 0;
  if (c >= 0xc2 && c <= 0xdf) n = 2, code = c & 0x1f;
  else if (c >= 0xe0 && c <= 0xef) n = 3, code = c & 0x0f;
  else if (c >= 0xf0 && c <= 0xf4) n = 4, code = c & 0x07;
  else return 0;
  if (k + n > text.size()) return 0;
  for (std::size_t i = 1; i < n; ++i) {
    if ((byte(k + i) & 0xc0) != 0x80) return 0;
    code = (code << 6) | (byte(k + i) & 0x3f);
  }
  // overlong forms, surrogates and code points past U+10FFFF are not valid UTF-8
  const std::uint32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < least[n] || (code >= 0xd800 && code <= 0xdfff) || code > 0x10ffff) return 0;
  return n;
}

/// What no header need declare, so that no probe of the headers finds it: C and C++ keywords,
/// alternative tokens and identifiers with a special meaning, what the harnesses of dyngen
/// report and firmware-report declare at global scope beside the package's header (main and
/// startup.c's sh_write; the rest starts with dyngen), and macros that builds define on the
/// command line (NDEBUG: CMake's release builds).
const std::set<std::string, std::less<>>& keywords() {
  static const std::set<std::string, std::less<>> words = {
      // C++20 keywords, alternative tokens, and identifiers with a special meaning
      "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break",
      "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept",
      "const", "consteval", "constexpr", "constinit", "const_cast", "continue", "co_await",
      "co_return", "co_yield", "decltype", "default", "delete", "do", "double", "dynamic_cast",
      "else", "enum", "explicit", "export", "extern", "false", "final", "float", "for", "friend",
      "goto", "if", "import", "inline", "int", "long", "module", "mutable", "namespace", "new",
      "noexcept", "not", "not_eq", "nullptr", "operator", "or", "or_eq", "override", "private",
      "protected", "public", "register", "reinterpret_cast", "requires", "return", "short",
      "signed", "sizeof", "static", "static_assert", "static_cast", "struct", "switch",
      "template", "this", "thread_local", "throw", "true", "try", "typedef", "typeid",
      "typename", "union", "unsigned", "using", "virtual", "void", "volatile", "wchar_t",
      "while", "xor", "xor_eq",
      // C keywords, and <complex.h>'s imaginary (where the compiler has imaginary types)
      "restrict", "typeof", "typeof_unqual", "imaginary",
      // the harnesses', command-line macros
      "main", "sh_write", "NDEBUG", "DEBUG"};
  return words;
}

/// What the headers that generated files include define as macros or declare at global scope,
/// as scripts/reserved_names.py found them (generator/reserved_names.txt, embedded).
const std::unordered_set<std::string_view>& header_names() {
  static const std::unordered_set<std::string_view> names = [] {
    std::unordered_set<std::string_view> set;
    const std::string_view text = template_text("reserved_names.txt");
    for (std::size_t at = 0; at < text.size();) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      if (end > at && text[at] != '#') set.insert(text.substr(at, end - at));
      at = end + 1;
    }
    return set;
  }();
  return names;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& ch : out) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return out;
}

/// Whether a header defines name, or a name that a C package of that name would declare.
bool reserved(const std::string& name) {
  const auto& headers = header_names();
  if (keywords().count(name) || headers.count(name)) return true;
  const std::vector<std::string> derived = c_names(name);
  return std::any_of(derived.begin(), derived.end(),
                     [&](const std::string& n) { return headers.count(n) > 0; });
}

/// Whether name starts with what the project reserves for itself whatever follows: "dyngen"
/// (the library's names, dyngen_sincos, dyngen_kernels.hpp, and the check's namespace
/// dyngen_check), and CMake's "CMAKE_" (a package's options are NAME_ISA and NAME_BUILD_CHECK),
/// in any case. A suffix would not help.
bool reserved_prefix(std::string_view name) {
  const std::string s = upper(name);
  return s.starts_with("DYNGEN") || s == "CMAKE" || s.starts_with("CMAKE_");
}

}  // namespace

std::string safe_text(std::string_view text, bool keep_newlines) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if (c == '\n' && keep_newlines) {
      out += '\n';
      ++k;
    } else if (c == '\\') {
      out += "\\x5c";
      ++k;
    } else if (c == '?' && k + 1 < text.size() && text[k + 1] == '?') {
      out += "?\\x3f";
      k += 2;
    } else if (c == '*' && k + 1 < text.size() && text[k + 1] == '/') {
      out += "*\\x2f";
      k += 2;
    } else if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
      ++k;
    } else if (std::uint32_t code = 0; const std::size_t n = utf8_sequence(text, k, code)) {
      if (code == 0x2028 || code == 0x2029) out += fmt::format("\\u{:04x}", code);
      else if (code < 0xa0) out += fmt::format("\\u{:04x}", code);  // C1 controls, U+0085
      else out.append(text.substr(k, n));
      k += n;
    } else {
      out += fmt::format("\\x{:02x}", c);
      ++k;
    }
  }
  return out;
}

std::string string_literal(std::string_view text) {
  std::string out = "\"";
  for (std::size_t k = 0; k < text.size(); ++k) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if (c == '"' || c == '\\') out += {'\\', static_cast<char>(c)};
    else if (c == '?' && k > 0 && text[k - 1] == '?') out += "\\?";  // no trigraph "??x"
    else if (c >= 0x20 && c < 0x7f) out += static_cast<char>(c);
    else out += fmt::format("\\{:03o}", c);
  }
  return out + "\"";
}

std::string python_text(std::string_view text) {
  std::string decoded;
  for (std::size_t k = 0; k < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    std::uint32_t code = 0;
    const std::size_t n = c < 0x80 ? 1 : utf8_sequence(text, k, code);
    if (n == 0) decoded += fmt::format("\\x{:02x}", c);
    else decoded.append(text.substr(k, n));
    k += std::max<std::size_t>(n, 1);
  }
  return decoded;
}

std::string python_literal(std::string_view text) { return string_literal(python_text(text)); }

std::string identifier(std::string_view name) {
  std::string s;
  for (const char ch : name) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if ((c < 0x80 && std::isalnum(c))) s += ch;
    else if (!s.empty() && s.back() != '_') s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  if (s.empty()) s = "robot";
  if (std::isdigit(static_cast<unsigned char>(s[0])) || reserved_prefix(s)) s = "robot_" + s;
  if (reserved(s)) s += "_robot";
  if (s.size() > max_identifier) {
    // FNV-1a of the whole name, so that names which share their start stay apart
    std::uint32_t hash = 2166136261u;
    for (const char ch : name) hash = (hash ^ static_cast<unsigned char>(ch)) * 16777619u;
    s.resize(max_identifier - 9);
    while (s.back() == '_') s.pop_back();
    s += fmt::format("_{:08x}", hash);
  }
  return s;
}

bool is_identifier(std::string_view name) { return identifier(name) == name; }

std::vector<std::string> c_names(std::string_view name) {
  const std::string prefix = std::string(name) + "_", macro = upper(name) + "_";
  std::vector<std::string> names;
  for (const char* local :
       {"joint_names", "frame_names", "body_names", "constraint_names", "JointTrig", "joint_trig"})
    names.push_back(prefix + local);
  for (const Algorithm& a : algorithm_names())
    names.insert(names.end(), {prefix + a, prefix + a + "_trig"});
  for (const char* local : {"NQ", "NV", "NFRAMES", "NBODIES", "NC", "NCONSTRAINTS", "DYNAMICS_H"})
    names.push_back(macro + local);
  return names;
}

std::string gnuplot_string(std::string_view text) {
  std::string out = "'";
  const std::string safe = safe_text(text);
  for (std::size_t k = 0; k < safe.size(); ++k) {
    if (safe.compare(k, 3, "\xef\xbf\xbe") == 0 || safe.compare(k, 3, "\xef\xbf\xbf") == 0) {
      out += safe[k + 2] == '\xbe' ? "\\ufffe" : "\\uffff";
      k += 2;
    } else {
      if (safe[k] == '\'') out += '\'';
      out += safe[k];
    }
  }
  return out + "'";
}

namespace {

/// The length of the longest run of backticks in text.
std::size_t longest_backtick_run(std::string_view text) {
  std::size_t longest = 0, run = 0;
  for (const char c : text) {
    run = c == '`' ? run + 1 : 0;
    longest = std::max(longest, run);
  }
  return longest;
}

}  // namespace

std::string markdown_code(std::string_view text) {
  const std::string s = safe_text(text);
  const std::string fence(longest_backtick_run(s) + 1, '`');
  // a span of spaces only keeps them all; any other loses one space from each end
  const bool pad = s.find_first_not_of(' ') != std::string::npos &&
                   (s.front() == '`' || s.back() == '`' || s.front() == ' ' || s.back() == ' ');
  const std::string space = pad ? " " : "";
  return fence + space + s + space + fence;
}

std::string markdown_block(std::string_view text) {
  const std::string s = safe_text(text, true);
  const std::string fence(std::max<std::size_t>(3, longest_backtick_run(s) + 1), '`');
  return fence + "\n" + s + (s.empty() || s.back() == '\n' ? "" : "\n") + fence;
}

}  // namespace dyngen::gen
