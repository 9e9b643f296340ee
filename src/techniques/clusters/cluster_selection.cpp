#include "farfield/techniques/clusters/cluster_selection.hpp"

#include <algorithm>
#include <bit>

#include <glm/geometric.hpp>

#include "farfield/core/four_ary_heap.hpp"

namespace farfield {

namespace {

bool inside(const Bounds3& box, const Bounds3& region) {
  return box.min.x >= region.min.x && box.min.y >= region.min.y && box.min.z >= region.min.z &&
         box.max.x <= region.max.x && box.max.y <= region.max.y && box.max.z <= region.max.z;
}

}  // namespace

float semantic_weight(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::tree:
    case ObjectKind::fountain:
      return 0.8f;
    case ObjectKind::terrain:
      return 0.7f;
    case ObjectKind::park:
    case ObjectKind::street:
    case ObjectKind::curb:
    case ObjectKind::ground:
      return 0.5f;
    default:
      return 1.0f;
  }
}

ClusterSelection::ClusterSelection(const Scene& scene, const ClusterTree& tree, const LodSet& lods,
                                   const BoxSet* boxes, bool averages)
    : scene_(scene),
      tree_(tree),
      lods_(lods),
      boxes_(boxes && !boxes->boxes.empty() ? boxes : nullptr),
      averages_(boxes_ && averages),
      state_(tree.nodes.size(), unseen),
      last_state_(tree.nodes.size(), unseen),
      wanted_(tree.nodes.size(), 0),
      coarsened_at_(tree.nodes.size(), 0) {
  slots_.reserve(tree.objects.size());
  for (const uint32_t object : tree.objects) {
    const Object& o = scene.objects[object];
    const bool has_lods = object + 1 < lods.first_lod.size();
    ObjectSlot slot{o.bounds,
                    object,
                    has_lods ? lods.first_lod[object] : 0,
                    has_lods ? lods.first_lod[object + 1] : 0,
                    boxes_ ? boxes_->object_box[object] : BoxSet::kNone, o.index_count / 3,
                    glm::length(o.bounds.size()), semantic_weight(o.kind), 0.0f, 0};
    if (slot.box != BoxSet::kNone) {
      slot.box_error_m = boxes_->boxes[slot.box].error_m;
      slot.box_triangles = 2 * boxes_->boxes[slot.box].side_count();
    }
    slots_.push_back(slot);
  }
  node_slots_.reserve(tree.nodes.size());
  for (uint32_t n = 0; n < tree.nodes.size(); ++n) {
    const ClusterNode& node = tree.nodes[n];
    NodeSlot slot{boxes_ ? boxes_->node_box[n] : BoxSet::kNone, glm::length(node.bounds.size()),
                  0.0f, 0.0f, 0};
    if (slot.box != BoxSet::kNone) {
      slot.box_error_m = boxes_->boxes[slot.box].error_m;
      slot.box_triangles = 2 * boxes_->boxes[slot.box].side_count();
    }
    for (uint32_t k = node.objects_begin; k < node.objects_end; ++k)
      slot.semantics = std::max(slot.semantics, slots_[k].semantics);
    node_slots_.push_back(slot);
  }
}

// Paper 001, Sec. 3.1: a weighted average of the factors intrinsic to what is seen.
float ClusterSelection::benefit_of(const Bounds3& box, float distance, float semantics) const {
  const BenefitWeights& w = view_->benefit;
  if (!w.any()) return 1.0f;
  const float d = std::max(distance, 1e-3f);
  const glm::vec3 size = box.size();
  const float across_px =
      std::sqrt(size.x * size.x + size.y * size.y + size.z * size.z) / (d * view_->pixel);
  const float size_factor = std::min(1.0f, across_px / std::max(view_->width_px, 1.0f));
  const glm::vec3 to = box.center() - view_->eye;
  const float to_length = std::sqrt(glm::dot(to, to));
  const float angle =
      to_length > 1e-6f
          ? std::acos(std::clamp(glm::dot(to / to_length, view_->forward), -1.0f, 1.0f))
          : 0.0f;
  const float focus = std::max(0.0f, 1.0f - angle / std::max(view_->half_fov_rad, 1e-3f));
  // The eye's motion across the line to the box, in pixels at its distance.
  const glm::vec3 v = view_->velocity;
  const glm::vec3 along = to_length > 1e-6f ? to / to_length : glm::vec3(0.0f);
  const glm::vec3 across = v - along * glm::dot(v, along);
  const float speed_px = std::sqrt(glm::dot(across, across)) / (d * view_->pixel);
  const float slowness = 1.0f / (1.0f + speed_px / 8.0f);
  return (w.size * size_factor + w.focus * focus + w.speed * slowness + w.semantics * semantics) /
         (w.size + w.focus + w.speed + w.semantics);
}

void ClusterSelection::set_state(uint32_t node, State state) {
  if (state_[node] == unseen) touched_.push_back(node);
  state_[node] = state;
}

// Nodes drawn as their cluster in one of the last two frames and refined in the other; the
// frames' states then move on (this frame's become the last).
uint64_t ClusterSelection::count_switches() {
  uint64_t switches = 0;
  auto cluster = [](uint8_t s) { return s == as_cluster || s == held; };
  ++frame_;
  switched_.clear();
  for (uint32_t n : touched_) {
    const bool coarsened = cluster(state_[n]) && last_state_[n] == refined;
    const bool refined_now = state_[n] == refined && cluster(last_state_[n]);
    if (coarsened) coarsened_at_[n] = frame_;
    switches += coarsened || refined_now;
    if (coarsened || refined_now) switched_.push_back({n, refined_now});
  }
  for (uint32_t n : last_touched_)
    if (last_state_[n] == refined && state_[n] == unseen) coarsened_at_[n] = 0;  // left view
  for (uint32_t n : last_touched_) last_state_[n] = unseen;
  for (uint32_t n : touched_) {
    last_state_[n] = state_[n];
    if (state_[n] != held) wanted_[n] = 0;  // the wish to refine must last frames in a row
    state_[n] = unseen;
  }
  last_touched_.swap(touched_);
  touched_.clear();
  return switches;
}

ClusterSelection::Seen ClusterSelection::see(const Bounds3& box, bool in_frustum) {
  ++visited_;
  const std::optional<Bounds3>& near = view_->near_box;
  const Visibility v = in_frustum ? Visibility::full : view_->frustum->classify(box);
  const bool visible = v != Visibility::none && (!near || meet(box, *near)) &&
                       !(view_->occlusion && view_->occlusion->hidden(box));
  return {visible, !near || inside(box, *near), v == Visibility::full,
          visible ? distance_to(box, view_->eye) : 0.0f, visible ? direction_of(box) : 0u};
}

ClusterSelection::Seen ClusterSelection::see_node(uint32_t node, bool in_frustum) {
  return precomputed_ ? node_seen_[node] : see(tree_.nodes[node].bounds, in_frustum);
}

ClusterSelection::Seen ClusterSelection::see_object(uint32_t slot, bool in_frustum) {
  if (precomputed_) return object_seen_[slots_[slot].object];
  Seen seen = see(slots_[slot].bounds, in_frustum);
  seen.clusterable = true;
  return seen;
}

uint32_t ClusterSelection::direction_of(const Bounds3& box) const {
  return view_->accuracy ? view_->accuracy->nearest(view_->eye - box.center()) : 0u;
}

// Paper 001, Sec. 4.5.1: the first pass looks at every object (and here every node) of the
// scene, whatever the second pass will use.
void ClusterSelection::classify_all() {
  precomputed_ = false;
  node_seen_.resize(tree_.nodes.size());
  object_seen_.resize(scene_.objects.size());
  for (uint32_t n = 0; n < node_seen_.size(); ++n) node_seen_[n] = see_node(n);
  for (uint32_t o = 0; o < object_seen_.size(); ++o) {
    object_seen_[o] = see(scene_.objects[o].bounds, false);
    object_seen_[o].clusterable = true;
  }
  precomputed_ = true;
}

float ClusterSelection::projected(float error_m, float distance) const {
  return error_m / (std::max(distance, 1e-3f) * view_->pixel);
}

uint64_t ClusterSelection::object_triangles(uint32_t slot, uint32_t level) const {
  if (level == kBox) return slots_[slot].box_triangles;
  return level == kWhole ? slots_[slot].whole_triangles : lods_.lods[level].index_count / 3;
}

float ClusterSelection::resolved(float image_m, float geometric_m, float diagonal_m) const {
  const float finest = view_->accuracy_finest_px;
  return finest > 0.0f && image_m * finest < diagonal_m ? geometric_m : image_m;
}

float ClusterSelection::object_error(uint32_t slot, uint32_t level, uint32_t direction) const {
  const AccuracyTable* a = view_->accuracy;
  if (level == kWhole) return 0.0f;
  const ObjectSlot& s = slots_[slot];
  const float geometric = level == kBox ? s.box_error_m : lods_.lods[level].error_m;
  if (!a) return geometric;
  return resolved(level == kBox ? a->box(s.box, direction) : a->lod(level, direction), geometric,
                  s.diagonal);
}

float ClusterSelection::node_error(uint32_t node, uint32_t level, uint32_t direction) const {
  const AccuracyTable* a = view_->accuracy;
  const NodeSlot& s = node_slots_[node];
  const float geometric = level == kBox ? s.box_error_m : tree_.nodes[node].error_m;
  if (!a) return geometric;
  return resolved(level == kBox ? a->box(s.box, direction) : a->node(node, direction), geometric,
                  s.diagonal);
}

Choice ClusterSelection::box_choice(uint32_t box, float diagonal_m, float distance, float limit_px,
                                    float& error_px) const {
  if (averages_ && limit_px > 0.0f) {
    const float across_px = projected(diagonal_m, distance);
    if (across_px <= limit_px) {
      error_px = across_px;
      return {Choice::Kind::average, box};
    }
  }
  return {Choice::Kind::box, box};
}

SelectionStats ClusterSelection::select(const SelectionView& view, ClusterTraversal traversal,
                                        std::vector<Choice>& out) {
  out.clear();
  switched_.clear();
  SelectionStats stats;
  if (tree_.nodes.empty() || !view.frustum) return stats;
  view_ = &view;
  visited_ = 0;
  precomputed_ = false;
  if (traversal == ClusterTraversal::paper) classify_all();
  if (view.max_triangles >= 0.0)
    under_budget(out, stats);
  else
    by_error(out, stats);
  stats.nodes_visited = visited_;
  stats.switches = count_switches();
  precomputed_ = false;
  view_ = nullptr;
  return stats;
}

void ClusterSelection::by_error(std::vector<Choice>& out, SelectionStats& stats) {
  const float allowed = view_->error_px * view_->pixel;  // metres of error per metre of distance
  const float average_px = std::min(view_->average_px, view_->error_px);
  auto take = [&](float error_px) {
    stats.largest_error_px = std::max(stats.largest_error_px, error_px);
  };
  stack_.assign(1, {0, false});
  while (!stack_.empty()) {
    const auto [n, parent_in_frustum] = stack_.back();
    stack_.pop_back();
    const ClusterNode& node = tree_.nodes[n];
    const Seen seen = see_node(n, parent_in_frustum);
    if (!seen.visible) continue;
    if (node.clustered() && seen.clusterable) {
      const uint32_t box = node_box(n);
      const float box_px = box != BoxSet::kNone
                               ? projected(node_error(n, kBox, seen.direction), seen.distance)
                               : INFINITY;
      if (box_px <= view_->error_px) {
        set_state(n, as_cluster);
        float error_px = box_px;
        out.push_back(
            box_choice(box, node_slots_[n].diagonal, seen.distance, average_px, error_px));
        stats.triangles += node_slots_[n].box_triangles;
        take(error_px);
        continue;
      }
      const float mesh_px = projected(node_error(n, 0, seen.direction), seen.distance);
      if (mesh_px <= view_->error_px) {
        set_state(n, as_cluster);
        out.push_back({Choice::Kind::cluster, n});
        stats.triangles += node.triangles;
        take(mesh_px);
        continue;
      }
    }
    if (node.clustered()) set_state(n, refined);
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k) {
      const Seen o = see_object(k, seen.in_frustum);
      if (!o.visible) continue;
      const ObjectSlot& slot = slots_[k];
      uint32_t level = kWhole;
      if (slot.box != BoxSet::kNone && object_error(k, kBox, o.direction) <= allowed * o.distance)
        level = kBox;
      else
        for (uint32_t l = slot.first_lod; l < slot.lod_end; ++l) {
          if (object_error(k, l, o.direction) > allowed * o.distance) break;
          level = l;
        }
      float error_px = projected(object_error(k, level, o.direction), o.distance);
      out.push_back(level == kBox
                        ? box_choice(slot.box, slot.diagonal, o.distance, average_px, error_px)
                    : level == kWhole ? Choice{Choice::Kind::whole, slot.object}
                                      : Choice{Choice::Kind::lod, level});
      stats.triangles += object_triangles(k, level);
      take(error_px);
    }
    for (uint32_t c = node.child_count; c-- > 0;)
      stack_.push_back({node.first_child + c, seen.in_frustum});
  }
}

// The coarsest complete representation of what the frustum sees of a node: its cluster (where
// `use_cluster` and it has one), else its visible objects at their coarsest levels and its
// children likewise; returns its cost (triangles, each draw counted as triangles_per_draw).
double ClusterSelection::open(uint32_t first, const Seen* first_seen, bool use_cluster,
                              std::vector<Item>& into, double limit) {
  const double per_draw = view_->triangles_per_draw;
  double total = 0;
  const size_t base = stack_.size();  // stack_ is this call's alone above `base`
  stack_.push_back({first, false});
  while (stack_.size() > base) {
    const auto [n, parent_in_frustum] = stack_.back();
    stack_.pop_back();
    const ClusterNode& node = tree_.nodes[n];
    __builtin_prefetch(&slots_[node.objects_begin]);  // seen next, if the node is
    const Seen seen = n == first && first_seen ? *first_seen : see_node(n, parent_in_frustum);
    if (!seen.visible) continue;
    if ((use_cluster || n != first) && node.clustered() && seen.clusterable) {
      const uint32_t box = node_box(n);
      if (const AccuracyTable* a = view_->accuracy) {  // read by the budget pass, as above
        const size_t dirs = a->directions.size();
        __builtin_prefetch(&a->node_error[size_t(n) * dirs + seen.direction]);
        if (box != BoxSet::kNone)
          __builtin_prefetch(&a->box_error[size_t(box) * dirs + seen.direction]);
      }
      const uint64_t triangles = box != BoxSet::kNone ? node_slots_[n].box_triangles : node.triangles;
      const double cost = box != BoxSet::kNone
                              ? double(triangles)
                              : triangles + per_draw * double(node.parts_end - node.parts_begin);
      into.push_back({n, kNone, box != BoxSet::kNone ? kBox : 0, seen.direction, seen.distance,
                      benefit_of(node.bounds, seen.distance, node_slots_[n].semantics), triangles,
                      cost, true, seen.in_frustum});
      total += cost;
      if (total > limit) break;
      continue;
    }
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k) {
      const Seen o = see_object(k, seen.in_frustum);
      if (!o.visible) continue;
      const ObjectSlot& slot = slots_[k];
      const uint32_t level = slot.box != BoxSet::kNone   ? kBox
                             : slot.lod_end > slot.first_lod ? slot.lod_end - 1
                                                             : kWhole;
      if (const AccuracyTable* a = view_->accuracy) {
        // Fetched while the rest of the node is seen: the budget pass reads an object's
        // errors at its direction level by level, a line apart, and after a frame's drawing
        // none are cached.
        const size_t dirs = a->directions.size();
        for (uint32_t l = slot.first_lod; l < slot.lod_end; ++l)
          __builtin_prefetch(&a->lod_error[size_t(l) * dirs + o.direction]);
        if (slot.box != BoxSet::kNone)
          __builtin_prefetch(&a->box_error[size_t(slot.box) * dirs + o.direction]);
      }
      if (slot.lod_end > slot.first_lod) __builtin_prefetch(&lods_.lods[slot.first_lod]);
      const uint64_t triangles = object_triangles(k, level);
      const double cost = double(triangles) + (level == kBox ? 0.0 : per_draw);
      into.push_back({n, k, level, o.direction, o.distance,
                      benefit_of(slot.bounds, o.distance, slot.semantics), triangles, cost, true,
                      o.in_frustum});
      total += cost;
      if (total > limit) break;
    }
    if (total > limit) break;
    for (uint32_t c = node.child_count; c-- > 0;) {
      // Fetched while the siblings are seen: after a frame's drawing they are not cached.
      __builtin_prefetch(&tree_.nodes[node.first_child + c]);
      __builtin_prefetch(&node_slots_[node.first_child + c]);
      stack_.push_back({node.first_child + c, seen.in_frustum});
    }
  }
  stack_.resize(base);
  return total;
}

void ClusterSelection::under_budget(std::vector<Choice>& out, SelectionStats& stats) {
  const double budget = view_->max_triangles;
  items_.clear();
  heap_.clear();
  stack_.clear();
  auto error_px = [&](const Item& item) {
    return projected(item.slot != kNone ? object_error(item.slot, item.level, item.direction)
                                          : node_error(item.node, item.level, item.direction),
                     item.distance);
  };
  // Paper 001, Sec. 4.5.2: the most beneficial refined first (the benefit 1 without weights).
  auto key = [&](const Item& item) { return error_px(item) * item.benefit; };
  auto refinable = [&](const Item& item) { return item.slot == kNone || item.level != kWhole; };
  // Non-negative floats order as their bits do; adding 0 turns a -0 into +0.
  auto entry = [&](uint32_t id) {
    return uint64_t(std::bit_cast<uint32_t>(key(items_[id]) + 0.0f)) << 32 | id;
  };
  auto push = [&](uint32_t id) {
    if (!refinable(items_[id])) return;
    four_ary_heap_push(heap_, entry(id));
  };
  // An item refined that still comes first (its key and number above the heap's top, as the
  // heap orders them) is taken again at once instead of pushed and popped: the same order
  // without the heap's work for each level of an object refined several levels in a row.
  uint32_t again = kNone;
  auto push_refined = [&](uint32_t id) {
    if (!refinable(items_[id])) return;
    const uint64_t e = entry(id);
    if (heap_.empty() || heap_.front() < e) {
      again = id;
      return;
    }
    four_ary_heap_push(heap_, e);
  };
  double cost = open(0, nullptr, true, items_);
  for (uint32_t id = 0; id < items_.size(); ++id) push(id);
  while (again != kNone || !heap_.empty()) {
    uint32_t id = again;
    again = kNone;
    if (id == kNone) {
      id = uint32_t(four_ary_heap_pop(heap_));
    }
    Item& item = items_[id];
    if (item.slot == kNone) {
      const ClusterNode& node = tree_.nodes[item.node];
      // A box into its cluster mesh where that is finer; no hysteresis: the node stays drawn
      // as a cluster.
      if (item.level == kBox &&
          node_error(item.node, 0, item.direction) < node_error(item.node, kBox, item.direction)) {
        const double mesh_cost =
            node.triangles + view_->triangles_per_draw * double(node.parts_end - node.parts_begin);
        const double more = mesh_cost - item.cost;
        if (more > 0 && cost + more > budget && item.distance > 0.0f) {
          stats.needed = std::min(stats.needed, cost + more);
          continue;
        }
        cost += more;
        item.level = 0;
        item.triangles = node.triangles;
        item.cost = mesh_cost;
        push_refined(id);
        continue;
      }
      opened_.clear();
      // An item's node was seen visible and clusterable this frame: not seen again. Opening
      // stops once what it found cannot fit (costs are never negative).
      const Seen seen{true, true, item.in_frustum, item.distance, item.direction};
      const double limit =
          item.distance > 0.0f ? std::max(budget - cost, 0.0) + item.cost : INFINITY;
      const double more = open(item.node, &seen, false, opened_, limit) - item.cost;
      // A refinement that does not fit is skipped (a cheaper one may still fit); one that
      // costs nothing is always taken, and so is a cluster the eye is inside, whose coarse
      // mesh would wrap the view (a frame of 7 dB on the 10M city's street where it was not).
      if (more > 0 && cost + more > budget && item.distance > 0.0f) {
        stats.needed = std::min(stats.needed, cost + more);
        continue;
      }
      // Temporal coherence (paper 001, Sec. 4.6), by one of two rules:
      //  - paper (default): a cluster drawn last frame is refined only once wanted for more than
      //    `hysteresis` frames in a row (one not drawn last frame, just come into view or
      //    opened, at once: it cannot flicker, and a jump refines in one go);
      //  - flips: only a cluster that went back from its children within the last
      //    `hysteresis` frames waits: a first refinement is at once, a flip-flop is not.
      const bool waits =
          view_->hysteresis > 0 &&
          (view_->hysteresis_rule == HysteresisRule::paper
               ? (last_state_[item.node] == as_cluster || last_state_[item.node] == held) &&
                     ++wanted_[item.node] <= view_->hysteresis
               : coarsened_at_[item.node] != 0 &&
                     frame_ - coarsened_at_[item.node] < uint64_t(view_->hysteresis));
      if (waits) {
        set_state(item.node, held);
        continue;
      }
      cost += more;
      set_state(item.node, refined);
      items_[id].live = false;
      for (const Item& child : opened_) {
        items_.push_back(child);
        push(uint32_t(items_.size() - 1));
      }
      continue;
    }
    const ObjectSlot& slot = slots_[item.slot];
    const uint32_t begin = slot.first_lod;
    uint32_t finer = kWhole;
    if (item.level == kBox) {  // the coarsest level finer than the box, else the whole
      const float box = object_error(item.slot, kBox, item.direction);
      for (uint32_t l = slot.lod_end; l-- > begin;)
        if (object_error(item.slot, l, item.direction) < box) {
          finer = l;
          break;
        }
    } else if (item.level != begin)
      finer = item.level - 1;
    const uint64_t triangles = object_triangles(item.slot, finer);
    // A level is a draw of its own; a box was not (SelectionView::triangles_per_draw).
    const double more = double(triangles) - double(item.triangles) +
                        (item.level == kBox ? view_->triangles_per_draw : 0.0);
    if (more > 0 && cost + more > budget) {
      stats.needed = std::min(stats.needed, cost + more);
      continue;
    }
    cost += more;
    item.level = finer;
    item.triangles = triangles;
    item.cost += more;
    push_refined(id);
  }
  for (const Item& item : items_) {
    if (!item.live) continue;
    float item_px = error_px(item);
    if (item.slot == kNone) {
      if (state_[item.node] != held) set_state(item.node, as_cluster);
      out.push_back(item.level == kBox
                        ? box_choice(node_box(item.node), node_slots_[item.node].diagonal,
                                     item.distance, view_->average_px, item_px)
                        : Choice{Choice::Kind::cluster, item.node});
    } else if (item.level == kBox)
      out.push_back(box_choice(slots_[item.slot].box, slots_[item.slot].diagonal, item.distance,
                               view_->average_px, item_px));
    else if (item.level == kWhole)
      out.push_back({Choice::Kind::whole, slots_[item.slot].object});
    else
      out.push_back({Choice::Kind::lod, item.level});
    stats.triangles += item.triangles;
    stats.largest_error_px = std::max(stats.largest_error_px, item_px);
  }
}

}  // namespace farfield
