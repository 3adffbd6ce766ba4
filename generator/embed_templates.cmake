# Writes a C++ source that holds every template's text (run at build time).
# Inputs: TEMPLATES (files separated by |), OUTPUT.
string(REPLACE "|" ";" TEMPLATES "${TEMPLATES}")
set(cases "")
foreach(file IN LISTS TEMPLATES)
  get_filename_component(name "${file}" NAME)
  file(READ "${file}" text)
  string(APPEND cases "  if (name == \"${name}\") return R\"dyngen_template(${text})dyngen_template\";\n")
endforeach()
file(WRITE "${OUTPUT}.tmp" "// Generated from templates/ at build time.
#include <stdexcept>
#include <string>
#include \"template.hpp\"

namespace dyngen::gen {

std::string_view template_text(std::string_view name) {
${cases}  throw std::logic_error(\"no template named \" + std::string(name));
}

}  // namespace dyngen::gen
")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
