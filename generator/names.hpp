// Names from a robot file (robot, links, joints, the file's own name) made safe wherever they
// land in text that dyngen writes: comments, string literals, identifiers, CMake, gnuplot,
// Markdown and the terminal. A URDF is untrusted input; what it names must never become code.
#pragma once

#include <string>
#include <string_view>

namespace dyngen::gen {

/// Text for a C, C++, CMake or gnuplot comment, a console message or a Markdown line: printable
/// ASCII and valid UTF-8 as they are, except that every control character, DEL, C1 control,
/// Unicode line or paragraph separator (U+0085, U+2028, U+2029) and invalid byte becomes
/// \xNN (\u2028 for the separators), a backslash becomes \x5c (so that no line ends in one,
/// which would splice the next line into the comment), "??" becomes "?\x3f" (trigraphs) and
/// "*/" becomes "*\x2f". With keep_newlines, '\n' stays (multi-line messages).
std::string safe_text(std::string_view text, bool keep_newlines = false);

/// A C and C++ string literal, quotes included, whose bytes are exactly text's: printable ASCII
/// as it is, with \" \\ and \? (after a ?), every other byte as a three-digit octal escape.
std::string string_literal(std::string_view text);

/// An identifier made from a name: letters and digits kept, every run of other characters one
/// underscore, none leading or trailing; "robot" when nothing is left, "robot_" before a
/// leading digit; at most max_identifier characters (a longer name keeps its start and gets a
/// hash of the whole, so that different long names stay different); and never a C or C++
/// keyword, alternative token, common predefined or library macro, or a name that the C and C++
/// libraries declare at global scope (a "_robot" is appended to those).
std::string identifier(std::string_view name);

inline constexpr std::size_t max_identifier = 48;

/// Whether name can be used as it is for a namespace and file prefix: identifier(name) == name.
bool is_identifier(std::string_view name);

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
