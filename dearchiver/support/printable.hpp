// Names and paths from input (notation files, archives, scene files, the command line), made safe for
// a terminal before any program of the project prints them: control characters, C1 controls and bytes
// that are not well-formed UTF-8 become \xNN escapes, so a hostile name cannot move the cursor, change
// colours or ring the bell. Well-formed UTF-8 passes unchanged.
#pragma once

#include <string>
#include <string_view>

namespace statepack::detail {

std::string printable(std::string_view text);

}  // namespace statepack::detail
