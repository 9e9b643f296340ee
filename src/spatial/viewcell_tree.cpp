#include "farfield/spatial/viewcell_tree.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "farfield/core/assert.hpp"

namespace farfield {

namespace {
constexpr uint32_t kMaxCellsPerAxis = 1u << 21;  // CellKey::packed's field width
}

std::string CellKey::name() const {
  char text[40];
  std::snprintf(text, sizeof text, "%07u_%07u_%07u", at[0], at[1], at[2]);
  return text;
}

Result<ViewcellTree> ViewcellTree::create(const Bounds3& region, double viewcell, double box) {
  if (!(viewcell > 0.0) || !std::isfinite(viewcell))
    return make_error(
        "stratified.viewcell: the viewcell length must be a positive number of "
        "metres (got ",
        std::to_string(viewcell), ")");
  if (!(box >= viewcell) || !std::isfinite(box))
    return make_error("stratified.box: the box (", std::to_string(box),
                      " m) must be at least as long as the viewcell (", std::to_string(viewcell),
                      " m)");
  if (region.empty()) return make_error("the navigable region is empty");
  ViewcellTree tree;
  tree.region_ = region;
  tree.viewcell_ = viewcell;
  tree.box_ = box;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::max(1.0, std::ceil(double(region.max[a] - region.min[a]) / viewcell));
    if (cells > kMaxCellsPerAxis)
      return make_error("stratified.viewcell: ", std::to_string(viewcell),
                        " m cuts the region into more than 2^21 cells along an axis");
    tree.cells_[a] = uint32_t(cells);
  }
  return tree;
}

bool ViewcellTree::valid(const CellKey& key) const {
  return key.at[0] < cells_[0] && key.at[1] < cells_[1] && key.at[2] < cells_[2];
}

std::optional<std::pair<int, uint32_t>> ViewcellTree::split(const Range& r) {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (r.hi[a] - r.lo[a] > r.hi[axis] - r.lo[axis]) axis = a;
  if (r.hi[axis] - r.lo[axis] <= 1) return std::nullopt;
  return std::pair{axis, r.lo[axis] + (r.hi[axis] - r.lo[axis]) / 2};
}

std::optional<CellKey> ViewcellTree::locate(const glm::vec3& p) const {
  if (!region_.contains(p)) return std::nullopt;
  Range r{{0, 0, 0}, cells_};
  // paper 000, Sec. 3.2: retrieving the viewcell descends the k-d tree, O(log n).
  while (const auto s = split(r)) {
    const auto [axis, middle] = *s;
    const double plane = double(region_.min[axis]) + middle * viewcell_;
    if (double(p[axis]) < plane)
      r.hi[axis] = middle;
    else
      r.lo[axis] = middle;
  }
  return CellKey{r.lo};
}

Bounds3 ViewcellTree::cell_bounds(const CellKey& key) const {
  Bounds3 b;
  for (int a = 0; a < 3; ++a) {
    b.min[a] = float(double(region_.min[a]) + key.at[a] * viewcell_);
    b.max[a] =
        std::min(region_.max[a], float(double(region_.min[a]) + (key.at[a] + 1) * viewcell_));
  }
  return b;
}

glm::vec3 ViewcellTree::centre(const CellKey& key) const {
  return cell_bounds(key).center();
}

Bounds3 ViewcellTree::box_bounds(const CellKey& key) const {
  const glm::vec3 c = centre(key);
  const float h = float(0.5 * box_);
  return {c - h, c + h};
}

Bounds3 ViewcellTree::boundary(const Range& r) const {
  Bounds3 b = box_bounds(CellKey{r.lo});
  b.expand(box_bounds(CellKey{{r.hi[0] - 1, r.hi[1] - 1, r.hi[2] - 1}}));
  return b;
}

std::vector<CellKey> ViewcellTree::cells_meeting(const Bounds3& bounds) const {
  std::vector<CellKey> out;
  if (!meet(bounds, region_)) return out;
  std::array<uint32_t, 3> lo{}, hi{};
  for (int a = 0; a < 3; ++a) {
    const double from = (double(bounds.min[a]) - region_.min[a]) / viewcell_;
    const double to = (double(bounds.max[a]) - region_.min[a]) / viewcell_;
    lo[a] = uint32_t(std::clamp(std::floor(from), 0.0, double(cells_[a] - 1)));
    hi[a] = uint32_t(std::clamp(std::floor(to), 0.0, double(cells_[a] - 1)));
  }
  for (uint32_t x = lo[0]; x <= hi[0]; ++x)
    for (uint32_t y = lo[1]; y <= hi[1]; ++y)
      for (uint32_t z = lo[2]; z <= hi[2]; ++z) out.push_back(CellKey{{x, y, z}});
  return out;
}

KdStats ViewcellTree::visit(std::span<const Bounds3> objects, const std::vector<CellKey>* wanted,
                            const Visitor& visitor) const {
  KdStats stats;
  const Range root{{0, 0, 0}, cells_};
  const Bounds3 b = boundary(root);
  std::vector<uint32_t> list;
  for (uint32_t i = 0; i < objects.size(); ++i)
    if (meet(objects[i], b)) list.push_back(i);
  stats.object_tests = objects.size();
  if (wanted) {
    FF_ASSERT(std::is_sorted(wanted->begin(), wanted->end()), "wanted cells must be sorted");
    visit(root, objects, list, *wanted, false, visitor, stats);
  } else {
    visit(root, objects, list, {}, true, visitor, stats);
  }
  return stats;
}

bool ViewcellTree::visit(const Range& r, std::span<const Bounds3> objects,
                         const std::vector<uint32_t>& list, std::span<const CellKey> wanted,
                         bool all, const Visitor& visitor, KdStats& stats) const {
  ++stats.nodes;
  const auto s = split(r);
  if (!s) return visitor(CellKey{r.lo}, list);
  const auto [axis, middle] = *s;
  Range halves[2] = {r, r};
  halves[0].hi[axis] = middle;
  halves[1].lo[axis] = middle;
  std::vector<uint32_t> child;
  std::vector<CellKey> inside;
  for (const Range& half : halves) {
    if (!all) {
      // The wanted cells inside this half.
      inside.clear();
      for (const CellKey& k : wanted) {
        bool in = true;
        for (int a = 0; a < 3; ++a) in = in && k.at[a] >= half.lo[a] && k.at[a] < half.hi[a];
        if (in) inside.push_back(k);
      }
      if (inside.empty()) continue;
    }
    // paper 000, FindNearObj: the child keeps the parent's objects that meet its boundary.
    const Bounds3 b = boundary(half);
    child.clear();
    for (uint32_t i : list)
      if (meet(objects[i], b)) child.push_back(i);
    stats.object_tests += list.size();
    // `inside` and `child` are refilled only after the recursion into this half returns.
    if (!visit(half, objects, child, inside, all, visitor, stats)) return false;
  }
  return true;
}

}  // namespace farfield
