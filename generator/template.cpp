#include "template.hpp"

#include <set>
#include <stdexcept>

namespace dyngen::gen {

std::string fill(std::string_view name, const std::map<std::string, std::string>& values) {
  const std::string_view text = template_text(name);
  std::string out;
  std::set<std::string> used;
  std::size_t pos = 0;
  while (true) {
    const std::size_t open = text.find('@', pos);
    if (open == std::string_view::npos) break;
    const std::size_t close = text.find('@', open + 1);
    if (close == std::string_view::npos)
      throw std::logic_error("template " + std::string(name) + ": unmatched @");
    const std::string key(text.substr(open + 1, close - open - 1));
    const auto it = values.find(key);
    if (it == values.end())
      throw std::logic_error("template " + std::string(name) + ": no value for @" + key + "@");
    out.append(text.substr(pos, open - pos));
    out += it->second;
    used.insert(key);
    pos = close + 1;
  }
  out.append(text.substr(pos));
  for (const auto& [key, value] : values)
    if (!used.count(key))
      throw std::logic_error("template " + std::string(name) + ": @" + key + "@ is not used");
  return out;
}

}  // namespace dyngen::gen
