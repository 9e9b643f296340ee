// Where what selection chooses lies in the cluster hierarchy (cluster_selection.hpp): each
// node's parent, the node whose own objects hold an object, the node a box stands at, and so
// the node of any choice. What a walk needs to know of a choice's place: which node stands in
// for it (cluster_stream.hpp), which switch it fades with (switch_fades.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "farfield/techniques/clusters/box_set.hpp"
#include "farfield/techniques/clusters/cluster_selection.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"

namespace farfield {

struct ChoiceAnchors {
  ChoiceAnchors() = default;
  // `objects`: the scene's.
  ChoiceAnchors(const ClusterTree& tree, const BoxSet& boxes, size_t objects);
  uint32_t of(const Choice& choice, const LodSet& lods) const;
  // `node` is `above` or lies beneath it.
  bool beneath(uint32_t node, uint32_t above) const;

  std::vector<uint32_t> parent;       // per node; the root's: UINT32_MAX
  std::vector<uint32_t> object_node;  // per object
  std::vector<uint32_t> box_node;     // per box: its node's, or its object's node
};

}  // namespace farfield
