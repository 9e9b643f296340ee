// The frame-time plot of paper 000, Fig. 6-1: frame time against frame for every technique
// of a bench.json, drawn by python3-matplotlib into a PNG.
#pragma once

#include <string>

#include "farfield/core/result.hpp"

namespace farfield {

Result<void> plot_frame_times(const std::string& bench_json_path, const std::string& png_path);

}  // namespace farfield
