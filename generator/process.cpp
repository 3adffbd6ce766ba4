#include "process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "robot.hpp"

extern char** environ;

namespace dyngen::gen {

namespace fs = std::filesystem;

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (const char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

std::string shell_word(const std::string& s) {
  constexpr const char* plain =
      "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./=+:,@%-";
  return !s.empty() && s.find_first_not_of(plain) == std::string::npos ? s : shell_quoted(s);
}

std::vector<std::string> command_words(const std::string& text) {
  std::vector<std::string> words;
  constexpr const char* blanks = " \t\n\r\f\v";
  for (std::size_t at = text.find_first_not_of(blanks); at != std::string::npos;) {
    const std::size_t end = text.find_first_of(blanks, at);
    words.push_back(text.substr(at, end - at));
    at = text.find_first_not_of(blanks, end);
  }
  return words;
}

std::string ending(int status, bool shell) {
  if (WIFSIGNALED(status))
    return fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
  if (!WIFEXITED(status)) return fmt::format("wait status {}", status);
  if (shell && WEXITSTATUS(status) == 127) return "not found";
  return fmt::format("exit status {}", WEXITSTATUS(status));
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
    throw std::runtime_error(fmt::format("{} failed ({}); the end of {}:\n{}", what,
                                         ending(status, true), log.string(), last));
  }
}

namespace {

/// InputError: `what` failed, how, the command and the end of its output.
[[noreturn]] void failed(const std::string& what, const std::string& how,
                         const std::string& command, std::string out) {
  if (out.size() > 3000) out = "..." + out.substr(out.size() - 3000);
  throw InputError(fmt::format("{} failed ({}): {}\n{}", what, how, command, out));
}

}  // namespace

std::string output_of(const std::string& command, const std::string& what) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw InputError(fmt::format("{}: cannot start '{}'", what, command));
  std::string out;
  char buffer[4096];
  while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  if (const int status = pclose(pipe); status != 0)
    failed(what, ending(status, true), command, out);
  return out;
}

std::string output_of(const std::vector<std::string>& argv, const std::string& what) {
  if (argv.empty()) throw InputError(fmt::format("{}: the command is empty", what));
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw InputError(fmt::format("{}: cannot start {}: {}", what, argv[0], std::strerror(errno)));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t child = 0;
  // glibc reports a failed exec (ENOENT: not in PATH) as posix_spawnp's result
  const int error = posix_spawnp(&child, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  std::string command;  // as the user would type it
  for (const std::string& a : argv)
    command.append(command.empty() ? "" : " ").append(shell_word(a));
  if (error != 0) {
    ::close(fds[0]);
    if (error == ENOENT) throw InputError(fmt::format("{}: {}: not found", what, argv[0]));
    throw InputError(fmt::format("{}: cannot run {}: {}", what, argv[0], std::strerror(error)));
  }
  std::string out;
  char buffer[4096];
  for (ssize_t n; (n = ::read(fds[0], buffer, sizeof buffer)) != 0;)
    if (n > 0) out.append(buffer, static_cast<std::size_t>(n));
    else if (errno != EINTR) break;
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (status != 0) failed(what, ending(status, false), command, out);
  return out;
}

}  // namespace dyngen::gen
