#include "farfield/gpu/instance_layout.hpp"

#include <algorithm>

#include <glm/matrix.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/scene/instances.hpp"

namespace farfield::gpu {

Placement identity_placement() {
  Placement p{};
  for (int i = 0; i < 3; ++i) p.rows[i][i] = p.normal_rows[i][i] = 1.0f;
  return p;
}

Placement placement_of(const Instance& instance) {
  const glm::mat3 normal = glm::transpose(glm::inverse(instance.linear));
  Placement p{};
  for (int i = 0; i < 3; ++i) {  // glm is column-major: row i is [c][i] over the columns c
    p.rows[i] = {instance.linear[0][i], instance.linear[1][i], instance.linear[2][i],
                 instance.offset[i]};
    p.normal_rows[i] = {normal[0][i], normal[1][i], normal[2][i], 0.0f};
  }
  return p;
}

Scene uploaded_form(const Scene& held) {
  StoredForm stored = stored_form(held);
  Scene uploaded;
  uploaded.objects = std::move(stored.objects);
  for (const Instance& i : held.instances) uploaded.objects[i.object].index_count = 0;
  uploaded.vertices = std::move(stored.vertices);
  uploaded.indices = std::move(stored.indices);
  uploaded.uvs = std::move(stored.uvs);
  uploaded.materials = held.materials;
  uploaded.names = held.names;
  return uploaded;
}

InstanceLayout::InstanceLayout(const Scene& held, const Scene& uploaded) {
  FF_ASSERT(uploaded.objects.size() == held.objects.size(), "%zu uploaded objects for %zu held",
            uploaded.objects.size(), held.objects.size());
  size_t next = 0;  // into held.instances
  for (uint32_t i = 0; i < held.objects.size(); ++i) {
    const Object& h = held.objects[i];
    const Object& up = uploaded.objects[i];  // an instance's firsts are its prototype's
    const bool instance = next < held.instances.size() && held.instances[next].object == i;
    const uint32_t k = instance ? uint32_t(next++) : kOwn;
    if (instance) instance_materials_.push_back(h.material);
    const auto add = [&](std::vector<Segment>& segments, uint32_t held_first, uint32_t count,
                         uint32_t uploaded_first) {
      if (count == 0) return;
      Segment* last = segments.empty() ? nullptr : &segments.back();
      if (k == kOwn && last && last->instance == kOwn &&
          last->held_first + last->count == held_first &&
          last->uploaded_first + last->count == uploaded_first) {
        last->count += count;
        return;
      }
      segments.push_back({held_first, count, uploaded_first, k});
    };
    add(index_segments_, h.first_index, h.index_count, up.first_index);
    add(vertex_segments_, h.first_vertex, h.vertex_count, up.first_vertex);
  }
  for (auto* segments : {&index_segments_, &vertex_segments_})
    std::sort(segments->begin(), segments->end(),
              [](const Segment& a, const Segment& b) { return a.held_first < b.held_first; });
}

const InstanceLayout::Segment& InstanceLayout::segment_of(const std::vector<Segment>& segments,
                                                          uint32_t held) {
  const auto after =
      std::upper_bound(segments.begin(), segments.end(), held,
                       [](uint32_t v, const Segment& g) { return v < g.held_first; });
  FF_ASSERT(after != segments.begin(), "number %u before every segment", held);
  const Segment& g = *(after - 1);
  FF_ASSERT(held < g.held_first + g.count, "number %u past every segment", held);
  return g;
}

InstanceLayout::Run InstanceLayout::index_run(uint32_t at, uint32_t end) const {
  FF_ASSERT(at < end, "an empty run [%u, %u)", at, end);
  if (!placed()) return {at, end - at, kOwn};
  const Segment& g = segment_of(index_segments_, at);
  return {g.uploaded_first + (at - g.held_first), std::min(end, g.held_first + g.count) - at,
          g.instance};
}

void InstanceLayout::place_vertices(const std::vector<uint32_t>& held,
                                    std::vector<uint32_t>& uploaded,
                                    std::vector<uint32_t>& instances) const {
  FF_ASSERT(held.size() % 3 == 0, "%zu vertex numbers, not whole triangles", held.size());
  uploaded.resize(held.size());
  instances.resize(held.size() / 3);
  for (size_t t = 0; t < held.size(); t += 3) {
    if (!placed()) {
      std::copy_n(&held[t], 3, &uploaded[t]);
      instances[t / 3] = kOwn;
      continue;
    }
    const Segment& g = segment_of(vertex_segments_, held[t]);
    for (size_t k = t; k < t + 3; ++k) {
      FF_ASSERT(held[k] >= g.held_first && held[k] < g.held_first + g.count,
                "triangle %zu's corners span objects", t / 3);
      uploaded[k] = g.uploaded_first + (held[k] - g.held_first);
    }
    instances[t / 3] = g.instance;
  }
}

}  // namespace farfield::gpu
