// Which cells a view sees, and through which part of the view (paper 004, "Plan to implement
// portals"; Luebke and Georges, 1995): from the eye's cell, every portal in view narrows the
// view volume to what is seen through it, and the walk goes on in the cell behind it. Two
// ways to narrow (PortalClip):
//   exact       the portal polygon clipped by the volume, the new volume the planes through
//               the eye and the clipped polygon's edges, and the portal's plane (the default);
//   rectangles  the paper's: the screen rectangle of the portal's projection intersected with
//               the current one (Luebke and Georges' cull boxes); cheaper, looser.
// Both are conservative: whatever is seen through a chain of portals lies in the volume of a
// visit. A portal is passed only from the side its current cell sees (a portal facing away
// is skipped), never twice in one chain (loops of rooms end), and an eye standing in a
// portal's opening sees both sides through it. Pure CPU, no allocation once warmed up.
#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <span>
#include <vector>

#include "farfield/core/convex_volume.hpp"
#include "farfield/core/view.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

enum class PortalClip : uint8_t { exact, rectangles };

struct PortalWalkOptions {
  PortalClip clip = PortalClip::exact;
  uint32_t max_depth = 64;     // portals in one chain
  uint32_t max_visits = 4096;  // cell visits in one walk
};

struct CellVisit {
  uint32_t cell = 0;
  uint32_t depth = 0;            // portals passed to get here (0: the eye's cell)
  uint32_t portal = UINT32_MAX;  // the last one passed (none for the eye's cell)
  // A limit was reached here: what the volume holds must be drawn from the whole scene.
  bool beyond_limits = false;
  ConvexVolume volume;
};

class PortalWalk {
 public:
  // Keeps a reference to `scene` (which must hold cells), and must not outlive it.
  PortalWalk(const Scene& scene, const PortalWalkOptions& options);
  // The visits of a view whose eye stands in `start`, into `out` (cleared first).
  void walk(const View& view, uint32_t start, std::vector<CellVisit>& out);
  // The portals of a cell (into Scene::portals).
  std::span<const uint32_t> portals_of(uint32_t cell) const {
    return std::span(cell_portals_)
        .subspan(first_portal_[cell], first_portal_[cell + 1] - first_portal_[cell]);
  }

 private:
  void visit(uint32_t cell, uint32_t depth, uint32_t via, const ConvexVolume& volume,
             const glm::vec4& rect);
  // Whether the eye lies within the portal's opening (projected on its plane).
  bool in_opening(uint32_t portal) const;
  // The volume seen through `portal` (passed towards its cells[1] when `forward`) from
  // `volume`, or false where the portal is out of it.
  bool narrow_exact(uint32_t portal, bool forward, const ConvexVolume& volume,
                    ConvexVolume& out) const;
  bool narrow_rectangle(uint32_t portal, const glm::vec4& rect, glm::vec4& out_rect,
                        ConvexVolume& out) const;

  const Scene& scene_;
  PortalWalkOptions options_;
  std::vector<uint32_t> first_portal_, cell_portals_;  // CSR: a cell's portals
  std::vector<PortalPlane> planes_;                    // per portal
  std::vector<uint8_t> in_chain_;                      // per portal, during a walk
  // The walk's view.
  glm::vec3 eye_{0.0f};
  glm::mat4 view_projection_{1.0f};
  glm::vec4 near_plane_{0.0f};
  std::vector<CellVisit>* out_ = nullptr;
};

}  // namespace farfield
