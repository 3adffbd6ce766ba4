// Text templates: files in templates/, embedded into the binary at build time, with @key@
// placeholders. Substitution is strict: an unknown or unused key is an error.
#pragma once

#include <map>
#include <string>
#include <string_view>

namespace dyngen::gen {

/// The text of templates/<name>, e.g. "dynamics.hpp.in".
std::string_view template_text(std::string_view name);

/// Replaces every @key@ with its value.
std::string fill(std::string_view name, const std::map<std::string, std::string>& values);

}  // namespace dyngen::gen
