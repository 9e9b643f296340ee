// Viewcells of Stratified Rendering (paper 000, Sec. 3.1.1): the navigable region cut into
// cells of the viewcell length v by a k-d tree that halves a kd-cell near its middle, at a
// multiple of v, along its longest side, until every leaf is one viewcell. The leaves form a
// grid aligned with the region's minimum corner (the last cell of an axis may be shorter), so a
// viewcell is named by its grid position.
//
// Each kd-cell keeps the objects within its object boundary, the union of the bounding boxes
// (side b, centred on the viewcell) of the viewcells under it; a child filters its parent's
// list, and a leaf's list is its viewcell's near objects. An object touching a box counts as
// near (the paper's rule for objects on the boundary), so every far object lies wholly outside.
//
// The tree is walked, not stored: a bake visits the leaves it needs in kd order with their
// near objects (memory: one list per level), and locating a viewpoint descends the same
// splits. Pure CPU, no GL.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/result.hpp"

namespace farfield {

struct CellKey {
  std::array<uint32_t, 3> at{};  // grid position per axis
  bool operator==(const CellKey&) const = default;
  auto operator<=>(const CellKey&) const = default;
  uint64_t packed() const { return uint64_t(at[0]) << 42 | uint64_t(at[1]) << 21 | at[2]; }
  static CellKey unpacked(uint64_t p) {
    constexpr uint64_t mask = (uint64_t(1) << 21) - 1;
    return {{uint32_t(p >> 42 & mask), uint32_t(p >> 21 & mask), uint32_t(p & mask)}};
  }
  std::string name() const;  // "x_y_z", zero-padded: the cell's part of its blob names
};

struct KdStats {
  uint64_t nodes = 0;         // kd-cells visited
  uint64_t object_tests = 0;  // object-against-boundary tests (paper 000, FindNearObj)
};

class ViewcellTree {
 public:
  // Fails, naming the setting, unless v > 0, b >= v, the region is not empty, and there are at
  // most 2^21 cells per axis.
  static Result<ViewcellTree> create(const Bounds3& region, double viewcell, double box);

  const Bounds3& region() const { return region_; }
  double viewcell() const { return viewcell_; }
  double box() const { return box_; }
  const std::array<uint32_t, 3>& cells() const { return cells_; }
  uint64_t cell_count() const { return uint64_t(cells_[0]) * cells_[1] * cells_[2]; }

  // The viewcell holding `p`, found by descending the k-d tree; none outside the region.
  std::optional<CellKey> locate(const glm::vec3& p) const;
  bool valid(const CellKey& key) const;
  Bounds3 cell_bounds(const CellKey& key) const;
  glm::vec3 centre(const CellKey& key) const;    // the original viewpoint of the cell
  Bounds3 box_bounds(const CellKey& key) const;  // side b around the centre

  // The viewcells whose bounds meet `bounds` (closed), in grid order.
  std::vector<CellKey> cells_meeting(const Bounds3& bounds) const;

  // Visits, in kd order, every viewcell in `wanted` (sorted, all valid; every cell when null)
  // with its near objects (indices into `objects`, ascending). Stops early when the visitor
  // returns false.
  using Visitor = std::function<bool(const CellKey&, std::span<const uint32_t> near)>;
  KdStats visit(std::span<const Bounds3> objects, const std::vector<CellKey>* wanted,
                const Visitor& visitor) const;

 private:
  struct Range {
    std::array<uint32_t, 3> lo, hi;  // cells [lo, hi) per axis
  };
  Bounds3 boundary(const Range& r) const;  // union of the boxes of r's viewcells
  // The kd split of a range: the axis with the most cells, at the middle cell; none for a leaf.
  static std::optional<std::pair<int, uint32_t>> split(const Range& r);
  bool visit(const Range& r, std::span<const Bounds3> objects, const std::vector<uint32_t>& list,
             std::span<const CellKey> wanted, bool all, const Visitor& visitor,
             KdStats& stats) const;

  Bounds3 region_;
  double viewcell_ = 0, box_ = 0;
  std::array<uint32_t, 3> cells_{};
};

}  // namespace farfield
