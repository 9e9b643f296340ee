#include "farfield/scene/scene_summary.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <vector>

#include "farfield/core/text.hpp"

namespace farfield {

std::string summarize_scene(const SceneSummaryInput& in) {
  const Scene& s = in.scene;
  constexpr size_t kinds = static_cast<size_t>(ObjectKind::count_);
  std::array<uint64_t, kinds> objects{}, triangles{};
  uint64_t transparent = 0;
  for (const Object& o : s.objects) {
    objects[static_cast<size_t>(o.kind)]++;
    triangles[static_cast<size_t>(o.kind)] += o.triangle_count();
    transparent += s.materials[o.material].transparent();
  }
  const glm::vec3 size = s.bounds.size();
  const ChunkedScene* disk = in.on_disk;
  const uint64_t triangle_total = disk ? disk->triangle_count() : s.triangle_count();
  const uint64_t vertices = disk ? disk->vertex_count() : s.vertices.size();
  const uint64_t bytes =
      s.byte_size() +
      (disk ? disk->vertex_count() * sizeof(Vertex) + disk->index_count() * sizeof(uint32_t) +
                  disk->uv_count() * sizeof(glm::vec2)
            : 0);
  std::string out;
  out += formatted("file:        %s\n", in.path.c_str());
  out += formatted("version:     %u\n", in.file.version);
  out += formatted("file bytes:  %llu (%.1f MiB)\n", (unsigned long long)in.file.file_bytes,
                   in.file.file_bytes / 1048576.0);
  if (disk)
    out += formatted("open time:   %.3f s (the geometry left in the file)\n", in.load_seconds);
  else
    out += formatted("load time:   %.3f s\n", in.load_seconds);
  out += formatted("triangles:   %llu\n", (unsigned long long)triangle_total);
  out += formatted("vertices:    %llu\n", (unsigned long long)vertices);
  out += formatted("objects:     %zu (%llu semi-transparent)\n", s.objects.size(),
                   (unsigned long long)transparent);
  out += formatted("materials:   %zu\n", s.materials.size());
  if (!s.textures.empty()) {
    uint64_t texels = 0;
    for (const Texture& t : s.textures) texels += uint64_t(t.width) * t.height;
    out += formatted("textures:    %zu (%llu bytes compressed, %.1f Mtexels)\n", s.textures.size(),
                     (unsigned long long)s.texture_bytes(), double(texels) / 1e6);
  }
  if (!s.cells.empty()) {
    uint64_t listed = 0;
    for (const Cell& c : s.cells) listed += c.object_count;
    out +=
        formatted("cells:       %zu (rooms; %.1f objects seen from each on average), %zu portals\n",
                  s.cells.size(), double(listed) / double(s.cells.size()), s.portals.size());
  }
  if (!s.instances.empty()) {
    std::vector<uint32_t> models;
    uint64_t repeated = 0;
    for (const Instance& i : s.instances) {
      models.push_back(i.prototype);
      repeated += s.objects[i.object].triangle_count();
    }
    std::sort(models.begin(), models.end());
    models.erase(std::unique(models.begin(), models.end()), models.end());
    out += formatted("instances:   %zu objects repeat %zu model%s (%llu of the triangles, "
                     "stored once with their model)\n",
                     s.instances.size(), models.size(), models.size() == 1 ? "" : "s",
                     (unsigned long long)repeated);
  }
  out += formatted("memory:      %llu bytes (%.1f bytes per triangle) when read whole\n",
                   (unsigned long long)bytes, triangle_total ? double(bytes) / double(triangle_total) : 0.0);
  if (disk && !disk->chunks().empty()) {
    uint64_t largest = 0;
    for (const SceneChunk& c : disk->chunks()) largest = std::max(largest, c.byte_size());
    out += formatted("chunks:      %zu (read on demand; %.2f MB on average, %.2f MB the largest)\n",
                     disk->chunks().size(),
                     double(bytes - s.byte_size()) / double(disk->chunks().size()) / 1e6,
                     double(largest) / 1e6);
  }
  if (s.bounds.empty()) {
    out += "bounds:      empty\n";
  } else {
    out +=
        formatted("bounds:      min (%.2f, %.2f, %.2f) max (%.2f, %.2f, %.2f) m\n", s.bounds.min.x,
                  s.bounds.min.y, s.bounds.min.z, s.bounds.max.x, s.bounds.max.y, s.bounds.max.z);
    out += formatted("size:        %.2f x %.2f x %.2f m (x, y up, z)\n", size.x, size.y, size.z);
    out += formatted("detail:      %.3g m (median longest triangle edge%s)\n",
                     double(in.detail_m >= 0.0f ? in.detail_m : median_triangle_edge(s)),
                     disk ? ", of chunks sampled" : "");
  }
  out += "by kind:     kind          objects    triangles\n";
  for (size_t k = 0; k < kinds; ++k) {
    if (objects[k] == 0) continue;
    const std::string name(object_kind_name(static_cast<ObjectKind>(k)));
    out += formatted("             %-12s %8llu %12llu\n", name.c_str(),
                     (unsigned long long)objects[k], (unsigned long long)triangles[k]);
  }
  return out;
}

}  // namespace farfield
