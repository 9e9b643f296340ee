#include "farfield/techniques/clusters/switch_fades.hpp"

#include <algorithm>

namespace farfield {

SwitchFades::SwitchFades(const ClusterTree& tree, const LodSet& lods, const BoxSet& boxes,
                         size_t objects, int frames)
    : lods_(lods), frames_(std::max(frames, 1)), anchors_(tree, boxes, objects) {
  fade_of_.assign(tree.nodes.size(), -1);
}

int SwitchFades::fade_at(uint32_t node) const {
  if (fades_.empty()) return -1;
  for (uint32_t n = node; n != UINT32_MAX; n = anchors_.parent[n])
    if (fade_of_[n] >= 0) return fade_of_[n];
  return -1;
}

void SwitchFades::update(std::span<const ClusterSelection::NodeSwitch> switched,
                         std::span<const Choice> choices) {
  for (const Fade& f : fades_) fade_of_[f.node] = -1;
  for (Fade& f : fades_) ++f.step;
  std::erase_if(fades_, [&](const Fade& f) { return f.step > frames_; });
  for (const ClusterSelection::NodeSwitch& s : switched) {
    // A switch within a fading node's part of the hierarchy, or above it, ends that fade.
    std::erase_if(fades_, [&](const Fade& f) {
      return anchors_.beneath(s.node, f.node) || anchors_.beneath(f.node, s.node);
    });
    Fade fade{s.node, 1, {}};
    for (const Choice& c : last_)
      if (c.kind != Choice::Kind::box && c.kind != Choice::Kind::average &&
          anchors_.beneath(anchors_.of(c, lods_), s.node))
        fade.old.push_back(c);
    fades_.push_back(std::move(fade));
  }
  out_.clear();
  for (size_t i = 0; i < fades_.size(); ++i) {
    const Fade& f = fades_[i];
    fade_of_[f.node] = int32_t(i);
    const float coverage = float(f.step) / float(frames_ + 1);
    for (const Choice& c : f.old) out_.push_back({c, coverage});
  }
  last_.assign(choices.begin(), choices.end());
}

float SwitchFades::coverage(const Choice& choice) const {
  const int f = fade_at(anchors_.of(choice, lods_));
  return f < 0 ? 1.0f : float(fades_[size_t(f)].step) / float(frames_ + 1);
}

}  // namespace farfield
