#include "farfield/techniques/clusters/choice_anchors.hpp"

namespace farfield {

ChoiceAnchors::ChoiceAnchors(const ClusterTree& tree, const BoxSet& boxes, size_t objects) {
  parent.assign(tree.nodes.size(), UINT32_MAX);
  object_node.assign(objects, 0);
  for (uint32_t n = 0; n < tree.nodes.size(); ++n) {
    const ClusterNode& node = tree.nodes[n];
    for (uint32_t c = 0; c < node.child_count; ++c) parent[node.first_child + c] = n;
    for (uint32_t k = node.objects_begin; k < node.own_end; ++k) object_node[tree.objects[k]] = n;
  }
  box_node.assign(boxes.boxes.size(), 0);
  for (uint32_t o = 0; o < boxes.object_box.size(); ++o)
    if (boxes.object_box[o] != BoxSet::kNone) box_node[boxes.object_box[o]] = object_node[o];
  for (uint32_t n = 0; n < boxes.node_box.size(); ++n)
    if (boxes.node_box[n] != BoxSet::kNone) box_node[boxes.node_box[n]] = n;
}

uint32_t ChoiceAnchors::of(const Choice& c, const LodSet& lods) const {
  switch (c.kind) {
    case Choice::Kind::cluster:
      return c.index;
    case Choice::Kind::lod:
      return object_node[lods.lods[c.index].object];
    case Choice::Kind::whole:
      return object_node[c.index];
    case Choice::Kind::box:
    case Choice::Kind::average:
      return box_node[c.index];
  }
  return 0;
}

bool ChoiceAnchors::beneath(uint32_t node, uint32_t above) const {
  for (uint32_t n = node; n != UINT32_MAX; n = parent[n])
    if (n == above) return true;
  return false;
}

}  // namespace farfield
