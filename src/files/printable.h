// capflow/files/printable: text taken from a file or the command line, made safe to print on a
// terminal. Every byte that a terminal could act on is shown as an escape instead: the C0
// controls (ESC, BEL, CR, ...) and DEL as \xNN, the C1 controls (U+0080..U+009F) as \u00NN, and
// bytes that are not UTF-8 as \xNN; valid UTF-8 (tau, G_s) passes unchanged, and so do newlines
// and tabs when `keep_lines` is set. A text longer than `max_bytes` is cut (at a character
// boundary) and ends in "...".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace capflow::files {

std::string printable(std::string_view text, std::size_t max_bytes = 4096,
                      bool keep_lines = false);

}  // namespace capflow::files
