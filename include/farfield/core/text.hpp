// Numbers and counts in messages: "200", "0.5", "1 frame", "3 frames".
#pragma once

#include <cstdint>
#include <string>

namespace farfield {

// Shortest usual form (printf's %g): 200 rather than 200.000000.
std::string number_text(double v);

// printf into a string of any length.
[[gnu::format(printf, 1, 2)]] std::string formatted(const char* fmt, ...);

// "1 frame", "3 frames" (an 's' for every count but one, or the plural given).
std::string counted(uint64_t n, const std::string& noun, const std::string& plural = "");

}  // namespace farfield
