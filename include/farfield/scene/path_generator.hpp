// Camera paths through a scene, deterministic for the same scene and options.
//   street: at eye height (1.7 m above the street surface) along the centre lines of the
//           scene's street objects, turning at crossings, never leaving the streets (so never
//           through a building); needs street objects (a generated city).
//   fly:    a loop above the roofs, looking ahead and down.
//   orbit:  a circle around the scene, looking at its centre.
//   interior: room to room through doors and up stairs, in a scene with cells and portals;
//           made by spatial/interior_path.hpp (it walks on the scene's surfaces).
#pragma once

#include <cstdint>
#include <string>

#include "farfield/core/camera_path.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

struct PathOptions {
  std::string kind = "street";  // street | fly | orbit | interior
  uint32_t frames = 300;
  double speed = 0.0;       // metres per frame; 0 picks the kind's default
  uint64_t seed = 1;        // turn choices of the street walk
  double eye_height = 1.7;  // metres above the street, street paths
};

// street, fly and orbit paths (interior: spatial/interior_path.hpp).
Result<CameraPath> generate_path(const Scene& scene, const PathOptions& options);

// Checks the options of any kind; the message names the option and the problem.
Result<void> validate_path_options(const PathOptions& options);

// The distance from the centre of `bounds` at which their bounding sphere fits the protocol's
// view (90 degrees wide at 4:3) with 5% to spare: where an orbit path flies.
double whole_view_distance(const Bounds3& bounds);

}  // namespace farfield
