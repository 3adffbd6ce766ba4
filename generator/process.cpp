#include "process.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "robot.hpp"

namespace dyngen::gen {

namespace fs = std::filesystem;

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (const char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

void run_logged(const std::string& what, const std::string& command, const fs::path& log,
                bool echo) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw std::runtime_error(fmt::format("{}: cannot start '{}'", what, command));
  std::ofstream out(log, std::ios::binary);
  std::vector<std::string> tail;
  char line[4096];
  while (std::fgets(line, sizeof line, pipe)) {
    out << line;
    if (echo) fmt::print("  {}", line), std::fflush(stdout);
    tail.emplace_back(line);
    if (tail.size() > 30) tail.erase(tail.begin());
  }
  const int status = pclose(pipe);
  if (status != 0) {
    std::string last;
    for (const std::string& l : tail) last += "  " + l;
    throw std::runtime_error(fmt::format("{} failed (exit status {}); the end of {}:\n{}", what,
                                         status, log.string(), last));
  }
}

std::string output_of(const std::string& command, const std::string& what) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw InputError(fmt::format("{}: cannot start '{}'", what, command));
  std::string out;
  char buffer[4096];
  while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  if (const int status = pclose(pipe); status != 0) {
    if (out.size() > 3000) out = "..." + out.substr(out.size() - 3000);
    throw InputError(fmt::format("{} failed (exit status {}): {}\n{}", what, status, command, out));
  }
  return out;
}

}  // namespace dyngen::gen
