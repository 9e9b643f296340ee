#include "farfield/techniques/clusters/mesh_pages.hpp"

#include <algorithm>
#include <cstring>

#include "farfield/core/assert.hpp"
#include "farfield/store/blob_array.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

namespace {

// A page blob: this header, then its vertices, texture coordinates and indices.
struct PageHeader {
  uint32_t vertex_count, uv_count, index_count, unused;
};
static_assert(sizeof(PageHeader) == 16);

std::string page_name(const std::string& prefix, uint32_t page) {
  return prefix + "_page/" + std::to_string(page);
}

}  // namespace

const char* mesh_arrays_problem(size_t vertices, size_t uvs, std::span<const uint32_t> indices) {
  if (uvs != 0 && uvs != vertices) return "texture coordinates are not one per vertex";
  for (uint32_t i : indices)
    if (i >= vertices) return "an index past the vertices";
  return nullptr;
}

std::vector<MeshPage> pages_of_runs(std::span<const uint32_t> indices, uint32_t vertex_count,
                                    std::span<const uint32_t> index_ends) {
  std::vector<MeshPage> pages;
  uint32_t first_index = 0, first_vertex = 0;
  for (size_t p = 0; p < index_ends.size(); ++p) {
    const uint32_t end = index_ends[p];
    FF_ASSERT(end >= first_index && end <= indices.size(), "page %zu ends at index %u", p, end);
    uint32_t vertex_end = first_vertex;
    for (uint32_t i = first_index; i < end; ++i) {
      FF_ASSERT(indices[i] >= first_vertex, "page %zu uses a vertex of the page before", p);
      vertex_end = std::max(vertex_end, indices[i] + 1);
    }
    if (p + 1 == index_ends.size()) vertex_end = std::max(vertex_end, vertex_count);
    pages.push_back({first_vertex, vertex_end - first_vertex, first_index, end - first_index});
    first_index = end;
    first_vertex = vertex_end;
  }
  FF_ASSERT(first_index == indices.size() && first_vertex == vertex_count,
            "pages end at index %u and vertex %u", first_index, first_vertex);
  return pages;
}

Result<void> save_mesh_pages(Store& store, const std::string& prefix,
                             std::span<const Vertex> vertices, std::span<const glm::vec2> uvs,
                             std::span<const uint32_t> indices, std::span<const MeshPage> pages) {
  if (auto ok = store.put(prefix + "_pages", std::as_bytes(pages)); !ok) return ok;
  std::vector<std::byte> blob;
  std::vector<uint32_t> local;
  for (uint32_t p = 0; p < pages.size(); ++p) {
    const MeshPage& page = pages[p];
    const PageHeader header{page.vertex_count, uvs.empty() ? 0u : page.vertex_count,
                            page.index_count, 0};
    local.assign(indices.begin() + page.first_index,
                 indices.begin() + page.first_index + page.index_count);
    for (uint32_t& i : local) i -= page.first_vertex;
    blob.clear();
    auto append = [&](const void* data, size_t bytes) {
      const auto* begin = static_cast<const std::byte*>(data);
      blob.insert(blob.end(), begin, begin + bytes);
    };
    append(&header, sizeof header);
    append(vertices.data() + page.first_vertex, size_t(header.vertex_count) * sizeof(Vertex));
    if (header.uv_count > 0)
      append(uvs.data() + page.first_vertex, size_t(header.uv_count) * sizeof(glm::vec2));
    append(local.data(), local.size() * sizeof(uint32_t));
    if (auto ok = store.put(page_name(prefix, p), blob); !ok) return ok;
  }
  return {};
}

Result<std::vector<MeshPage>> load_mesh_page_table(const Store& store, const std::string& prefix) {
  const std::string name = prefix + "_pages";
  auto pages = read_array<MeshPage>(store, name.c_str());
  if (!pages) return pages.error();
  uint32_t vertex = 0, index = 0;
  for (const MeshPage& page : *pages) {
    if (page.first_vertex != vertex || page.first_index != index || page.index_count % 3 != 0 ||
        uint64_t(vertex) + page.vertex_count > UINT32_MAX ||
        uint64_t(index) + page.index_count > UINT32_MAX)
      return make_error(store.path(), ": blob '", name, "' holds pages that do not follow "
                        "each other");
    vertex += page.vertex_count;
    index += page.index_count;
  }
  return pages;
}

Result<std::shared_ptr<SceneMeshData>> read_mesh_page(const Store& store,
                                                      const std::string& prefix, uint32_t page,
                                                      const MeshPage& expected) {
  const std::string name = page_name(prefix, page);
  auto bytes = store.get(name);
  if (!bytes) return bytes.error();
  auto refused = [&](const char* why) {
    return make_error(store.path(), ": blob '", name, "' ", why);
  };
  PageHeader h;
  if (bytes->size() < sizeof h) return refused("is too short for a page");
  std::memcpy(&h, bytes->data(), sizeof h);
  if (h.vertex_count != expected.vertex_count || h.index_count != expected.index_count ||
      (h.uv_count != 0 && h.uv_count != h.vertex_count))
    return refused("is not the page its table describes");
  const uint64_t size = sizeof h + uint64_t(h.vertex_count) * sizeof(Vertex) +
                        uint64_t(h.uv_count) * sizeof(glm::vec2) +
                        uint64_t(h.index_count) * sizeof(uint32_t);
  if (bytes->size() != size) return refused("has a size that does not match its counts");
  auto data = std::make_shared<SceneMeshData>();
  const std::byte* at = bytes->data() + sizeof h;
  auto take = [&](auto& array, uint32_t count) {
    array.resize(count);
    const size_t n = size_t(count) * sizeof(array[0]);
    if (n > 0) std::memcpy(array.data(), at, n);
    at += n;
  };
  take(data->vertices, h.vertex_count);
  take(data->uvs, h.uv_count);
  take(data->indices, h.index_count);
  if (const char* problem = mesh_arrays_problem(data->vertices.size(), data->uvs.size(),
                                                data->indices))
    return refused(problem);
  return data;
}

Result<std::shared_ptr<SceneMeshData>> mesh_page(const Store* store, const std::string& prefix,
                                                 std::span<const MeshPage> pages, uint32_t page,
                                                 std::span<const Vertex> vertices,
                                                 std::span<const glm::vec2> uvs,
                                                 std::span<const uint32_t> indices) {
  FF_ASSERT(page < pages.size(), "page %u of %zu", page, pages.size());
  const MeshPage& p = pages[page];
  if (indices.empty()) {
    if (!store) return make_error("page ", std::to_string(page), " of '", prefix,
                                  "' is neither in memory nor in a pack");
    return read_mesh_page(*store, prefix, page, p);
  }
  auto data = std::make_shared<SceneMeshData>();
  data->vertices.assign(vertices.begin() + p.first_vertex,
                        vertices.begin() + p.first_vertex + p.vertex_count);
  if (!uvs.empty())
    data->uvs.assign(uvs.begin() + p.first_vertex, uvs.begin() + p.first_vertex + p.vertex_count);
  data->indices.reserve(p.index_count);
  for (uint32_t i = p.first_index; i < p.first_index + p.index_count; ++i)
    data->indices.push_back(indices[i] - p.first_vertex);
  return data;
}

Result<void> read_mesh_pages(const Store& store, const std::string& prefix,
                             std::span<const MeshPage> pages,
                             std::vector<Vertex>& vertices, std::vector<glm::vec2>& uvs,
                             std::vector<uint32_t>& indices) {
  vertices.clear();
  uvs.clear();
  indices.clear();
  if (!pages.empty()) {
    vertices.reserve(pages.back().first_vertex + pages.back().vertex_count);
    indices.reserve(pages.back().first_index + pages.back().index_count);
  }
  for (uint32_t p = 0; p < pages.size(); ++p) {
    auto page = read_mesh_page(store, prefix, p, pages[p]);
    if (!page) return page.error();
    vertices.insert(vertices.end(), (*page)->vertices.begin(), (*page)->vertices.end());
    uvs.insert(uvs.end(), (*page)->uvs.begin(), (*page)->uvs.end());
    for (uint32_t i : (*page)->indices) indices.push_back(pages[p].first_vertex + i);
  }
  if (!uvs.empty() && uvs.size() != vertices.size())
    return make_error(store.path(), ": blobs '", prefix, "_page/*' are textured in part");
  return {};
}

}  // namespace farfield
