#pragma once
//! Text from a file shown on a terminal: names and fields read from a mesh or model file may
//! carry control characters (terminal escape sequences, NUL, carriage returns) or Unicode
//! direction overrides that would make what is printed differ from what is in the file.
#include <cstddef>
#include <string>
#include <string_view>

namespace thermodec {

//! True if `text` holds a C0 control character (U+0000-U+001F), DEL, a C1 control character
//! (U+0080-U+009F) or a Unicode bidirectional formatting character (U+061C, U+200E, U+200F,
//! U+202A-U+202E, U+2066-U+2069).
bool has_control_characters(std::string_view text);

//! `text` safe to print: every character `has_control_characters` names and every byte that
//! is not part of valid UTF-8 written as an escape (`\x1b`, `\u202e`); cut after `max_bytes`
//! bytes of the input with "... (N bytes)" appended.
std::string printable(std::string_view text, std::size_t max_bytes = 200);

}  // namespace thermodec
