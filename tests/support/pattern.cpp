#include "pattern.hpp"

#include <regex>

namespace dyngen::test {

struct Pattern::Compiled {
  std::regex regex;
};

namespace {

Groups groups(const std::match_results<std::string_view::const_iterator>& m) {
  Groups g;
  for (const auto& sub : m) g.push_back(sub.str());
  return g;
}

}  // namespace

Pattern::Pattern(const std::string& expression)
    : compiled_(std::make_unique<Compiled>(Compiled{std::regex(expression)})) {}
Pattern::Pattern(Pattern&&) noexcept = default;
Pattern::~Pattern() = default;

std::optional<Groups> Pattern::match(std::string_view text) const {
  std::match_results<std::string_view::const_iterator> m;
  if (!std::regex_match(text.begin(), text.end(), m, compiled_->regex)) return std::nullopt;
  return groups(m);
}

std::optional<Groups> Pattern::search(std::string_view text) const {
  std::match_results<std::string_view::const_iterator> m;
  if (!std::regex_search(text.begin(), text.end(), m, compiled_->regex)) return std::nullopt;
  return groups(m);
}

std::vector<Groups> Pattern::find_all(std::string_view text) const {
  std::vector<Groups> all;
  using Iterator = std::regex_iterator<std::string_view::const_iterator>;
  for (Iterator it(text.begin(), text.end(), compiled_->regex), end; it != end; ++it)
    all.push_back(groups(*it));
  return all;
}

std::string Pattern::replace(std::string_view text, const std::string& format) const {
  return std::regex_replace(std::string(text), compiled_->regex, format);
}

}  // namespace dyngen::test
