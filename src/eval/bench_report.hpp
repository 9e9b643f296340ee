// bench.json (DESIGN.md lists the fields; fields may be added, never renamed).
#pragma once

#include <string>

#include "farfield/core/camera_path.hpp"
#include "farfield/eval/bench.hpp"

namespace farfield {

std::string bench_json(const BenchReport& report, const BenchOptions& options, const Scene& scene,
                       const CameraPath& path);

}  // namespace farfield
