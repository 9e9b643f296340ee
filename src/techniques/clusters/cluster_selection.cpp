#include "farfield/techniques/clusters/cluster_selection.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

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
                                   const BoxSet* boxes)
    : scene_(scene),
      tree_(tree),
      lods_(lods),
      boxes_(boxes && !boxes->boxes.empty() ? boxes : nullptr),
      state_(tree.nodes.size(), unseen),
      last_state_(tree.nodes.size(), unseen),
      wanted_(tree.nodes.size(), 0),
      coarsened_at_(tree.nodes.size(), 0) {
  object_diagonal_.reserve(scene.objects.size());
  for (const Object& o : scene.objects) object_diagonal_.push_back(glm::length(o.bounds.size()));
  node_diagonal_.reserve(tree.nodes.size());
  for (const ClusterNode& n : tree.nodes) node_diagonal_.push_back(glm::length(n.bounds.size()));
  node_semantics_.assign(tree.nodes.size(), 0.0f);
  for (uint32_t n = 0; n < tree.nodes.size(); ++n)
    for (uint32_t k = tree.nodes[n].objects_begin; k < tree.nodes[n].objects_end; ++k)
      node_semantics_[n] =
          std::max(node_semantics_[n], semantic_weight(scene.objects[tree.objects[k]].kind));
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
  for (uint32_t n : touched_) {
    const bool coarsened = cluster(state_[n]) && last_state_[n] == refined;
    if (coarsened) coarsened_at_[n] = frame_;
    switches += coarsened || (state_[n] == refined && cluster(last_state_[n]));
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

ClusterSelection::Seen ClusterSelection::see_node(uint32_t node) {
  if (precomputed_) return node_seen_[node];
  ++visited_;
  const Bounds3& box = tree_.nodes[node].bounds;
  const std::optional<Bounds3>& near = view_->near_box;
  const bool visible = view_->frustum->classify(box) != Visibility::none &&
                       (!near || meet(box, *near)) &&
                       !(view_->occlusion && view_->occlusion->hidden(box));
  return {visible, !near || inside(box, *near), visible ? distance_to(box, view_->eye) : 0.0f,
          visible ? direction_of(box) : 0u};
}

ClusterSelection::Seen ClusterSelection::see_object(uint32_t object) {
  if (precomputed_) return object_seen_[object];
  ++visited_;
  const Bounds3& box = scene_.objects[object].bounds;
  const std::optional<Bounds3>& near = view_->near_box;
  const bool visible = view_->frustum->classify(box) != Visibility::none &&
                       (!near || meet(box, *near)) &&
                       !(view_->occlusion && view_->occlusion->hidden(box));
  return {visible, true, visible ? distance_to(box, view_->eye) : 0.0f,
          visible ? direction_of(box) : 0u};
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
  for (uint32_t o = 0; o < object_seen_.size(); ++o) object_seen_[o] = see_object(o);
  precomputed_ = true;
}

float ClusterSelection::projected(float error_m, float distance) const {
  return error_m / (std::max(distance, 1e-3f) * view_->pixel);
}

uint64_t ClusterSelection::object_triangles(uint32_t object, uint32_t level) const {
  if (level == kBox) return box_triangles(object_box(object));
  return level == kWhole ? scene_.objects[object].index_count / 3
                         : lods_.lods[level].index_count / 3;
}

float ClusterSelection::resolved(float image_m, float geometric_m, float diagonal_m) const {
  const float finest = view_->accuracy_finest_px;
  return finest > 0.0f && image_m * finest < diagonal_m ? geometric_m : image_m;
}

float ClusterSelection::object_error(uint32_t object, uint32_t level, uint32_t direction) const {
  const AccuracyTable* a = view_->accuracy;
  if (level == kWhole) return 0.0f;
  const float geometric =
      level == kBox ? boxes_->boxes[object_box(object)].error_m : lods_.lods[level].error_m;
  if (!a) return geometric;
  return resolved(level == kBox ? a->box(object_box(object), direction) : a->lod(level, direction),
                  geometric, object_diagonal_[object]);
}

float ClusterSelection::node_error(uint32_t node, uint32_t level, uint32_t direction) const {
  const AccuracyTable* a = view_->accuracy;
  const float geometric =
      level == kBox ? boxes_->boxes[node_box(node)].error_m : tree_.nodes[node].error_m;
  if (!a) return geometric;
  return resolved(level == kBox ? a->box(node_box(node), direction) : a->node(node, direction),
                  geometric, node_diagonal_[node]);
}

SelectionStats ClusterSelection::select(const SelectionView& view, ClusterTraversal traversal,
                                        std::vector<Choice>& out) {
  out.clear();
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
  auto take = [&](float error_px) {
    stats.largest_error_px = std::max(stats.largest_error_px, error_px);
  };
  stack_.assign(1, 0);
  while (!stack_.empty()) {
    const uint32_t n = stack_.back();
    stack_.pop_back();
    const ClusterNode& node = tree_.nodes[n];
    const Seen seen = see_node(n);
    if (!seen.visible) continue;
    if (node.clustered() && seen.clusterable) {
      const uint32_t box = node_box(n);
      const float box_px = box != BoxSet::kNone
                               ? projected(node_error(n, kBox, seen.direction), seen.distance)
                               : INFINITY;
      if (box_px <= view_->error_px) {
        set_state(n, as_cluster);
        out.push_back({Choice::Kind::box, box});
        stats.triangles += box_triangles(box);
        take(box_px);
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
      const uint32_t object = tree_.objects[k];
      const Seen o = see_object(object);
      if (!o.visible) continue;
      uint32_t level = kWhole;
      const uint32_t box = object_box(object);
      if (box != BoxSet::kNone && object_error(object, kBox, o.direction) <= allowed * o.distance)
        level = kBox;
      else
        for (uint32_t l = lods_.first_lod[object]; l < lods_.first_lod[object + 1]; ++l) {
          if (object_error(object, l, o.direction) > allowed * o.distance) break;
          level = l;
        }
      out.push_back(level == kBox     ? Choice{Choice::Kind::box, box}
                    : level == kWhole ? Choice{Choice::Kind::whole, object}
                                      : Choice{Choice::Kind::lod, level});
      stats.triangles += object_triangles(object, level);
      take(projected(object_error(object, level, o.direction), o.distance));
    }
    for (uint32_t c = node.child_count; c-- > 0;) stack_.push_back(node.first_child + c);
  }
}

// The coarsest complete representation of what the frustum sees of a node: its cluster (where
// `use_cluster` and it has one), else its visible objects at their coarsest levels and its
// children likewise; returns its cost (triangles, each draw counted as triangles_per_draw).
double ClusterSelection::open(uint32_t first, bool use_cluster, std::vector<Item>& into) {
  const double per_draw = view_->triangles_per_draw;
  double total = 0;
  const size_t base = stack_.size();  // stack_ is this call's alone above `base`
  stack_.push_back(first);
  while (stack_.size() > base) {
    const uint32_t n = stack_.back();
    stack_.pop_back();
    const ClusterNode& node = tree_.nodes[n];
    const Seen seen = see_node(n);
    if (!seen.visible) continue;
    if ((use_cluster || n != first) && node.clustered() && seen.clusterable) {
      const uint32_t box = node_box(n);
      const uint64_t triangles = box != BoxSet::kNone ? box_triangles(box) : node.triangles;
      const double cost = box != BoxSet::kNone
                              ? double(triangles)
                              : triangles + per_draw * double(node.parts_end - node.parts_begin);
      into.push_back({n, kNone, box != BoxSet::kNone ? kBox : 0, seen.direction, seen.distance,
                      benefit_of(node.bounds, seen.distance, node_semantics_[n]), triangles, cost,
                      true});
      total += cost;
      continue;
    }
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k) {
      const uint32_t object = tree_.objects[k];
      const Seen o = see_object(object);
      if (!o.visible) continue;
      const uint32_t begin = lods_.first_lod[object], end = lods_.first_lod[object + 1];
      const uint32_t level = object_box(object) != BoxSet::kNone ? kBox
                             : end > begin                       ? end - 1
                                                                 : kWhole;
      const uint64_t triangles = object_triangles(object, level);
      const Object& obj = scene_.objects[object];
      const double cost = double(triangles) + (level == kBox ? 0.0 : per_draw);
      into.push_back({n, object, level, o.direction, o.distance,
                      benefit_of(obj.bounds, o.distance, semantic_weight(obj.kind)), triangles,
                      cost, true});
      total += cost;
    }
    for (uint32_t c = node.child_count; c-- > 0;) stack_.push_back(node.first_child + c);
  }
  return total;
}

void ClusterSelection::under_budget(std::vector<Choice>& out, SelectionStats& stats) {
  const double budget = view_->max_triangles;
  items_.clear();
  heap_.clear();
  stack_.clear();
  auto error_px = [&](const Item& item) {
    return projected(item.object != kNone ? object_error(item.object, item.level, item.direction)
                                          : node_error(item.node, item.level, item.direction),
                     item.distance);
  };
  // Paper 001, Sec. 4.5.2: the most beneficial refined first (the benefit 1 without weights).
  auto key = [&](const Item& item) { return error_px(item) * item.benefit; };
  auto refinable = [&](const Item& item) { return item.object == kNone || item.level != kWhole; };
  auto push = [&](uint32_t id) {
    if (!refinable(items_[id])) return;
    heap_.push_back({key(items_[id]), id});
    std::push_heap(heap_.begin(), heap_.end());
  };
  double cost = open(0, true, items_);
  for (uint32_t id = 0; id < items_.size(); ++id) push(id);
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end());
    const uint32_t id = heap_.back().second;
    heap_.pop_back();
    Item& item = items_[id];
    if (item.object == kNone) {
      const ClusterNode& node = tree_.nodes[item.node];
      // A box into its cluster mesh where that is finer; no hysteresis: the node stays drawn
      // as a cluster.
      if (item.level == kBox &&
          node_error(item.node, 0, item.direction) < node_error(item.node, kBox, item.direction)) {
        const double mesh_cost =
            node.triangles + view_->triangles_per_draw * double(node.parts_end - node.parts_begin);
        const double more = mesh_cost - item.cost;
        if (more > 0 && cost + more > budget && item.distance > 0.0f) continue;
        cost += more;
        item.level = 0;
        item.triangles = node.triangles;
        item.cost = mesh_cost;
        push(id);
        continue;
      }
      opened_.clear();
      const double more = open(item.node, false, opened_) - item.cost;
      // A refinement that does not fit is skipped (a cheaper one may still fit); one that
      // costs nothing is always taken, and so is a cluster the eye is inside, whose coarse
      // mesh would wrap the view (a frame of 7 dB on the 10M city's street where it was not).
      if (more > 0 && cost + more > budget && item.distance > 0.0f) continue;
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
    const uint32_t begin = lods_.first_lod[item.object];
    uint32_t finer = kWhole;
    if (item.level == kBox) {  // the coarsest level finer than the box, else the whole
      const float box = object_error(item.object, kBox, item.direction);
      for (uint32_t l = lods_.first_lod[item.object + 1]; l-- > begin;)
        if (object_error(item.object, l, item.direction) < box) {
          finer = l;
          break;
        }
    } else if (item.level != begin)
      finer = item.level - 1;
    const uint64_t triangles = object_triangles(item.object, finer);
    // A level is a draw of its own; a box was not (SelectionView::triangles_per_draw).
    const double more = double(triangles) - double(item.triangles) +
                        (item.level == kBox ? view_->triangles_per_draw : 0.0);
    if (more > 0 && cost + more > budget) continue;
    cost += more;
    item.level = finer;
    item.triangles = triangles;
    item.cost += more;
    push(id);
  }
  for (const Item& item : items_) {
    if (!item.live) continue;
    if (item.object == kNone) {
      if (state_[item.node] != held) set_state(item.node, as_cluster);
      out.push_back(item.level == kBox ? Choice{Choice::Kind::box, node_box(item.node)}
                                       : Choice{Choice::Kind::cluster, item.node});
    } else if (item.level == kBox)
      out.push_back({Choice::Kind::box, object_box(item.object)});
    else if (item.level == kWhole)
      out.push_back({Choice::Kind::whole, item.object});
    else
      out.push_back({Choice::Kind::lod, item.level});
    stats.triangles += item.triangles;
    stats.largest_error_px = std::max(stats.largest_error_px, error_px(item));
  }
}

}  // namespace farfield
