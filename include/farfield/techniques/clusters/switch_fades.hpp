// Blended switches (paper 001, Sec. 5.4, "smooth LOD switching using transparency blending"):
// where a node of the cluster hierarchy switches between its cluster and its children, what
// the last frame drew beneath it fades out over a few frames while what this frame draws
// there fades in. Both are drawn as dithered parts of the pixels (DrawList::faded), the new
// representation on a growing share and the old one on the rest, so that every pixel shows
// one of them, with no sorting and no blending. A switch beneath or above a node still fading
// ends that fade. Only scene ranges fade (clusters, levels, whole objects); boxes are drawn
// whole or not at all.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "farfield/techniques/clusters/box_set.hpp"
#include "farfield/techniques/clusters/choice_anchors.hpp"
#include "farfield/techniques/clusters/cluster_selection.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"

namespace farfield {

class SwitchFades {
 public:
  // `frames` > 0: a fade lasts that many frames; `objects`: the scene's. All outlive it.
  SwitchFades(const ClusterTree& tree, const LodSet& lods, const BoxSet& boxes, size_t objects,
              int frames);

  // After a frame's selection: the fades of its switches start, those done end.
  void update(std::span<const ClusterSelection::NodeSwitch> switched,
              std::span<const Choice> choices);
  // The share of its pixels one of this frame's choices draws: 1, or below while it fades in.
  float coverage(const Choice& choice) const;
  // What fades out this frame: drawn on the complement of `coverage`.
  struct Out {
    Choice choice;
    float coverage;
  };
  const std::vector<Out>& fading_out() const { return out_; }
  size_t active() const { return fades_.size(); }

 private:
  uint32_t anchor(const Choice& choice) const;        // the node it lies in
  bool beneath(uint32_t node, uint32_t above) const;  // node is `above` or beneath it
  int fade_at(uint32_t node) const;  // the fade of the node or of its lowest fading ancestor

  struct Fade {
    uint32_t node;
    int step;  // 1 .. frames_
    std::vector<Choice> old;
  };
  const LodSet& lods_;
  int frames_;
  ChoiceAnchors anchors_;
  std::vector<int32_t> fade_of_;  // per node: index into fades_, or -1
  std::vector<Fade> fades_;
  std::vector<Choice> last_;  // the last frame's choices
  std::vector<Out> out_;
};

}  // namespace farfield
