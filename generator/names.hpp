// Names from a robot file (robot, links, joints, the file's own name) made safe wherever they
// land in text that dyngen writes: comments, string literals, identifiers, CMake, gnuplot,
// Markdown and the terminal. A URDF is untrusted input; what it names must never become code.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace dyngen::gen {

/// Text for a C, C++, CMake or gnuplot comment, a console message, or inside markdown_code's
/// and markdown_block's fences (not bare Markdown, where it could still be markup): printable
/// ASCII and valid UTF-8 as they are, except that every control character, DEL, C1 control,
/// Unicode line or paragraph separator (U+0085, U+2028, U+2029) and invalid byte becomes
/// \xNN (\u2028 for the separators), a backslash becomes \x5c (so that no line ends in one,
/// which would splice the next line into the comment), "??" becomes "?\x3f" (trigraphs) and
/// "*/" becomes "*\x2f". With keep_newlines, '\n' stays (multi-line messages).
std::string safe_text(std::string_view text, bool keep_newlines = false);

/// A C and C++ string literal, quotes included, whose bytes are exactly text's: printable ASCII
/// as it is, with \" \\ and \? (after a ?), every other byte as a three-digit octal escape.
std::string string_literal(std::string_view text);

/// An identifier made from a name, for the package's C++ namespace, C prefix, file prefix and
/// CMake names: letters and digits kept, every run of other characters one underscore, none
/// leading or trailing; "robot" when nothing is left; "robot_" before a leading digit and
/// before a name that starts with "dyngen" (the project's own names) or "cmake" followed by
/// nothing or "_" (CMake's), in any case; "_robot" after a C or C++ keyword, what harnesses
/// declare beside the package (main, sh_write), a macro that builds define (NDEBUG, DEBUG), and a
/// name that the headers which generated files include define as a macro or declare at global
/// scope, or define as one of the name's c_names (generator/reserved_names.txt, which
/// scripts/reserved_names.py makes by compiling them); and
/// at most max_identifier characters (a longer result keeps its start and gets a hash of the
/// whole name, so that different long names stay different).
std::string identifier(std::string_view name);

inline constexpr std::size_t max_identifier = 48;

/// Whether name can be used as it is for a namespace and file prefix: identifier(name) == name.
bool is_identifier(std::string_view name);

/// Text as Python's bytes.decode("utf-8", "backslashreplace") reads it: valid UTF-8 as it is
/// (NUL, quotes, newlines and all) and every other byte as the four characters \xNN. The Python
/// module's names and dyngen eval's JSON names are this text, so the two agree.
std::string python_text(std::string_view text);

/// A C++ string literal, in string_literal's form, for a Python str (pybind11 docstrings and
/// names): python_text, which is valid UTF-8, so the str is made at import without fail.
std::string python_literal(std::string_view text);

/// The names that a C package of that name declares at global scope: name_rnea and
/// name_rnea_trig for every algorithm, name_joint_trig, name_joint_names, name_frame_names,
/// name_JointTrig, and the macros NAME_NQ, NAME_NV, NAME_NFRAMES and NAME_DYNAMICS_H.
std::vector<std::string> c_names(std::string_view name);

/// A gnuplot single-quoted string, quotes included, for a label drawn with `noenhanced`:
/// safe_text (one line, no control character or invalid byte), with each ' doubled and U+FFFE
/// and U+FFFF (which XML, and so gnuplot's SVG, cannot hold) as \ufffe and \uffff. gnuplot
/// substitutes neither backquoted commands nor @macros in single-quoted strings and reads no
/// backslash escapes there, so the label shows the text and nothing runs.
std::string gnuplot_string(std::string_view text);

/// A Markdown (CommonMark) code span of safe_text(text), backticks included: fenced by one
/// backtick more than the longest run inside it, with a space inside each end when the text
/// starts or ends with a backtick or a space, so that it shows the text exactly and nothing in
/// it reads as Markdown or HTML. Not for table cells, where a | would end the cell.
std::string markdown_code(std::string_view text);

/// A fenced Markdown code block of safe_text(text, true) (lines kept), fenced by more backticks
/// than any run in it, so that no line of the text closes it.
std::string markdown_block(std::string_view text);

}  // namespace dyngen::gen
