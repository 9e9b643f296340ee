// A large office building of rooms joined by doors (issue 14): the scene of portal rendering
// (paper 004's plan; Luebke and Georges' architectural models). Floors of two rows of rooms
// on either side of a corridor, the corridor in segments of a few rooms joined by open
// portals, a door from every room onto the corridor, two windows from every room to the
// outside, and a stairwell at the corridor's east end: one straight flight per floor, from its
// west landing up to the next floor's east landing, with a door onto the corridor at each
// landing. Every room is furnished (desk, chair, bookshelves full of books, a plant, lamps).
//
// Cells and portals (scene/cells.hpp): every room, corridor segment and the stairwell is a
// cell; the outside (ground, facades, roof) is one more, whose box holds the whole building,
// so that an eye in a room is in the room's (smaller) box. A cell's objects are the ones seen
// from inside it: its walls, floor, ceiling and furniture, and the jambs of its doors and
// windows (shared with the cell on the other side). The walls are closed: everything one
// cell sees of another it sees through a portal.
//
// Layout: +Y up, metres; the corridor runs along X at z in [-corridor/2, corridor/2], rooms
// north (+Z) and south (-Z) of it, room slot i at x in [i * room_width, (i + 1) * room_width];
// the stairwell takes the last two south slots on every floor. Floor k stands at
// y = k * storey. Deterministic: the same options give the same scene.
#pragma once

#include <cstdint>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

struct BuildingOptions {
  uint32_t floors = 12;
  uint32_t rooms_per_side = 48;  // room slots on each side of the corridor, per floor
  uint32_t segment_rooms = 4;    // room slots per corridor segment (cell)
  double room_width = 5.0;       // along the corridor, metres
  double room_depth = 6.0;       // metres
  double corridor_width = 3.0;   // metres
  double storey = 3.5;           // floor to floor, metres
  uint32_t books = 150;          // books per bookshelf (two shelves a room)
  uint64_t seed = 1;
};

// Checks the options; the message names the option and the problem.
Result<void> validate_building_options(const BuildingOptions& options);

Result<Scene> generate_building(const BuildingOptions& options, Progress& progress);

}  // namespace farfield
