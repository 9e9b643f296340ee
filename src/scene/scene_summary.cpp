#include "farfield/scene/scene_summary.hpp"

#include <array>
#include <cstdio>

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
  std::string out;
  out += formatted("file:        %s\n", in.path.c_str());
  out += formatted("version:     %u\n", in.file.version);
  out += formatted("file bytes:  %llu (%.1f MiB)\n", (unsigned long long)in.file.file_bytes,
                   in.file.file_bytes / 1048576.0);
  out += formatted("load time:   %.3f s\n", in.load_seconds);
  out += formatted("triangles:   %llu\n", (unsigned long long)s.triangle_count());
  out += formatted("vertices:    %zu\n", s.vertices.size());
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
  out += formatted("memory:      %llu bytes (%.1f bytes per triangle)\n",
                   (unsigned long long)s.byte_size(),
                   s.triangle_count() ? double(s.byte_size()) / double(s.triangle_count()) : 0.0);
  if (s.bounds.empty()) {
    out += "bounds:      empty\n";
  } else {
    out +=
        formatted("bounds:      min (%.2f, %.2f, %.2f) max (%.2f, %.2f, %.2f) m\n", s.bounds.min.x,
                  s.bounds.min.y, s.bounds.min.z, s.bounds.max.x, s.bounds.max.y, s.bounds.max.z);
    out += formatted("size:        %.2f x %.2f x %.2f m (x, y up, z)\n", size.x, size.y, size.z);
    out += formatted("detail:      %.3g m (median longest triangle edge)\n",
                     double(median_triangle_edge(s)));
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
