// Regular expressions for the tests, compiled in one place: <regex>'s templates cost each test
// file that instantiates them about 3 s of compile time.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dyngen::test {

/// A match: the whole at 0, then each parenthesised group ("" where it took no part).
using Groups = std::vector<std::string>;

/// An ECMAScript regular expression (std::regex's default grammar).
class Pattern {
 public:
  explicit Pattern(const std::string& expression);
  Pattern(Pattern&&) noexcept;
  ~Pattern();

  /// The groups, if the whole of text matches.
  std::optional<Groups> match(std::string_view text) const;
  /// The groups of the first match in text.
  std::optional<Groups> search(std::string_view text) const;
  /// Every match in text, in order.
  std::vector<Groups> find_all(std::string_view text) const;
  /// text with every match replaced by `format` ($1 for group 1).
  std::string replace(std::string_view text, const std::string& format) const;

 private:
  struct Compiled;
  std::unique_ptr<Compiled> compiled_;
};

}  // namespace dyngen::test
