#include "names.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <set>

#include <fmt/format.h>

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

/// C and C++ keywords and alternative tokens, macros that compilers predefine or the standard
/// headers define, and what the C, C++ and POSIX headers that generated code and its check
/// include declare at global scope: a namespace of one of these names does not compile, or
/// means something else.
const std::set<std::string, std::less<>>& reserved_words() {
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
      // C keywords and the macros of its headers that spell keywords
      "restrict", "typeof", "typeof_unqual", "complex", "imaginary", "noreturn", "I",
      // predefined and library macros
      "linux", "unix", "i386", "NULL", "EOF", "BUFSIZ", "FILENAME_MAX", "FOPEN_MAX", "errno",
      "assert", "stdin", "stdout", "stderr", "INFINITY", "NAN", "HUGE_VAL", "HUGE_VALF",
      "offsetof", "setjmp", "longjmp", "va_arg", "va_start", "va_end", "va_copy", "va_list",
      "EXIT_SUCCESS", "EXIT_FAILURE", "RAND_MAX", "CHAR_BIT", "INT_MAX", "INT_MIN", "SIZE_MAX",
      "TRUE", "FALSE", "NDEBUG", "DEBUG", "MB_CUR_MAX", "CLOCKS_PER_SEC", "math_errhandling",
      "fpclassify", "isfinite", "isinf", "isnan", "isnormal", "signbit", "major", "minor",
      // namespaces and entry points that generated code and its check use
      "std", "dyngen", "testing", "main", "posix", "gtest",
      // C library functions and objects at global scope (math.h, stdio.h, stdlib.h, string.h,
      // time.h, signal.h, ctype.h) and POSIX's (unistd.h, strings.h)
      "abs", "acos", "asin", "atan", "atan2", "ceil", "cos", "cosh", "exp", "fabs", "floor",
      "fmod", "frexp", "ldexp", "log", "log10", "modf", "pow", "sin", "sinh", "sqrt", "tan",
      "tanh", "acosh", "asinh", "atanh", "cbrt", "copysign", "erf", "erfc", "exp2", "expm1",
      "fdim", "fma", "fmax", "fmin", "hypot", "ilogb", "lgamma", "llrint", "llround", "log1p",
      "log2", "logb", "lrint", "lround", "nan", "nearbyint", "nextafter", "nexttoward",
      "remainder", "remquo", "rint", "round", "scalbln", "scalbn", "tgamma", "trunc", "gamma",
      "j0", "j1", "jn", "y0", "y1", "yn", "sincos", "drem", "significand", "finite", "div",
      "ldiv", "labs", "atof", "atoi", "atol", "strtod", "strtol", "strtoul", "rand", "srand",
      "random", "srandom", "calloc", "malloc", "realloc", "free", "abort", "atexit", "exit",
      "getenv", "setenv", "system", "bsearch", "qsort", "printf", "scanf", "sprintf", "sscanf",
      "fprintf", "fscanf", "snprintf", "puts", "gets", "fputs", "fgets", "putc", "getc",
      "putchar", "getchar", "fopen", "fclose", "fread", "fwrite", "fflush", "fseek", "ftell",
      "rewind", "remove", "rename", "tmpfile", "tmpnam", "perror", "FILE", "fpos_t",
      "memcpy", "memmove", "memset", "memcmp", "memchr", "strcpy", "strncpy", "strcat",
      "strncat", "strcmp", "strncmp", "strlen", "strchr", "strrchr", "strstr", "strtok",
      "strerror", "strdup", "index", "rindex", "bcopy", "bzero", "bcmp", "ffs", "time",
      "clock", "difftime", "mktime", "ctime", "gmtime", "localtime", "asctime", "strftime",
      "timezone", "daylight", "tzname", "tm", "signal", "raise", "kill", "isalpha", "isdigit",
      "isalnum", "isspace", "isupper", "islower", "toupper", "tolower", "read", "write", "open",
      "close", "pipe", "fork", "dup", "dup2", "link", "unlink", "symlink", "sleep", "usleep",
      "access", "chdir", "rmdir", "mkdir", "sync", "pause", "alarm", "nice", "getpid",
      "getppid", "environ", "optarg", "optind", "opterr", "optopt", "getopt", "select", "poll",
      "wait", "truncate", "lseek", "chown", "chmod", "stat", "isatty", "ttyname", "exec",
      "execv", "execl", "execvp", "brk", "sbrk", "swab", "crypt", "encrypt", "confstr",
      "sysconf", "pathconf", "umask", "mount", "accept", "bind", "connect", "listen", "send",
      "recv", "socket", "shutdown", "int8_t", "int16_t", "int32_t", "int64_t", "uint8_t",
      "uint16_t", "uint32_t", "uint64_t", "size_t", "ptrdiff_t", "intptr_t", "uintptr_t",
      "clock_t", "time_t", "wint_t", "max_align_t", "float_t", "double_t", "jmp_buf",
      "sig_atomic_t", "div_t", "ldiv_t"};
  return words;
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

std::string identifier(std::string_view name) {
  std::string s;
  for (const char ch : name) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if ((c < 0x80 && std::isalnum(c))) s += ch;
    else if (!s.empty() && s.back() != '_') s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  if (s.empty()) s = "robot";
  if (std::isdigit(static_cast<unsigned char>(s[0]))) s = "robot_" + s;
  if (s.size() > max_identifier) {
    // FNV-1a of the whole name, so that names which share their start stay apart
    std::uint32_t hash = 2166136261u;
    for (const char ch : name) hash = (hash ^ static_cast<unsigned char>(ch)) * 16777619u;
    s.resize(max_identifier - 9);
    while (s.back() == '_') s.pop_back();
    s += fmt::format("_{:08x}", hash);
  }
  if (reserved_words().count(s)) s += "_robot";
  return s;
}

bool is_identifier(std::string_view name) { return identifier(name) == name; }

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
