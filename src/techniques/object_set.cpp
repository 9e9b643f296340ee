#include "farfield/techniques/object_set.hpp"

#include <algorithm>
#include <bit>

namespace farfield {

ObjectSet::ObjectSet(const Scene& scene)
    : scene_(scene), words_((scene.objects.size() + 63) / 64, 0) {}

void ObjectSet::clear() {
  std::fill(words_.begin(), words_.end(), 0);
}

void ObjectSet::insert_meeting(const Bounds3& box) {
  for (uint32_t i = 0; i < scene_.objects.size(); ++i)
    if (meet(scene_.objects[i].bounds, box)) insert(i);
}

void ObjectSet::insert_all() {
  std::fill(words_.begin(), words_.end(), ~uint64_t(0));
  if (const size_t tail = scene_.objects.size() % 64; tail != 0)
    words_.back() = (uint64_t(1) << tail) - 1;
}

void ObjectSet::emit(DrawList& out) const {
  for (size_t w = 0; w < words_.size(); ++w) {
    for (uint64_t bits = words_[w]; bits != 0; bits &= bits - 1) {
      const uint32_t index = static_cast<uint32_t>(w * 64 + std::countr_zero(bits));
      const Object& o = scene_.objects[index];
      auto& ranges = scene_.materials[o.material].transparent() ? out.transparent : out.opaque;
      if (!ranges.empty() && !ranges.back().mesh && ranges.back().material == o.material &&
          ranges.back().first_index + ranges.back().index_count == o.first_index) {
        ranges.back().index_count += o.index_count;
      } else {
        ranges.push_back({o.first_index, o.index_count, o.material});
      }
    }
  }
}

}  // namespace farfield
