// Text from files made safe to print on a terminal: control bytes shown, never interpreted.
#pragma once

#include <string>

namespace facetool {

// `text` with every control byte but newline and tab (escape sequences, carriage returns, bells,
// DEL) written as \xNN, so bytes quoted from a hostile file cannot move the cursor, recolour or
// retitle the user's terminal; bytes that are not valid UTF-8 are written as \xNN too, so the
// result is valid UTF-8 (Python's exceptions need it).
std::string printable_text(const std::string& text);

}  // namespace facetool
