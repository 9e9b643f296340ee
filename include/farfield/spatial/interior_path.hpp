// `path --kind interior`: a walk at eye height from room to room through doors and up stairs,
// in a scene with cells and portals (scene/cells.hpp). Doors are the portals one can walk
// through: upright, at least eye height + 0.1 m tall and 0.6 m wide, with ground at their
// foot on both sides. Within a cell the walk goes in a straight line from door to door, on
// whatever surface lies under it (cast down from knee height, 0.5 m steps at most: stairs
// are climbed), and only where nothing stands in the way (knee and head rays); a room, a cell
// with one door, is visited to its middle and left the way it came. The walk starts in a
// room on the lowest floor near a way up, and then alternates: up the nearest stairs, then
// into the nearest room not yet visited, until the frames are used up. The eye turns towards
// where it goes at most 6 degrees a frame, standing still for sharp turns.
#pragma once

#include "farfield/core/camera_path.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

// Default speed 0.15 m a frame (300 frames: 45 m). Fails on a scene without cells, doors or
// rooms, naming what is missing.
Result<CameraPath> interior_path(const Scene& scene, const PathOptions& options);

}  // namespace farfield
