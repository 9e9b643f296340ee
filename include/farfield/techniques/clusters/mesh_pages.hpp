// Baked geometry of the clusters pack (levels of detail, cluster meshes) kept as pages: runs
// of its vertices and indices that a walk loads one at a time (issue 16: the hierarchy of a
// scene larger than memory streams), and that a whole load puts back end to end.
//
// In memory a set's arrays are whole, its pages consecutive runs of them (page p + 1 starts
// where p ends), its indices absolute. In a pack: the table `PREFIX_pages` and one blob
// `PREFIX_page/N` per page (its vertex and index counts, vertices, texture coordinates where
// the set has any, indices counted from the page's first vertex), so that a page read alone
// is a scene mesh as it stands.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "farfield/core/result.hpp"
#include "farfield/gpu/draw_list.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

class Store;

struct MeshPage {
  uint32_t first_vertex = 0, vertex_count = 0;
  uint32_t first_index = 0, index_count = 0;
  bool holds(uint32_t first, uint32_t count) const {
    return first >= first_index && uint64_t(first) + count <= uint64_t(first_index) + index_count;
  }
};
static_assert(sizeof(MeshPage) == 16);

// Triangles of pages laid end to end.
inline uint64_t triangles_of_pages(std::span<const MeshPage> pages) {
  return pages.empty() ? 0 : (uint64_t(pages.back().first_index) + pages.back().index_count) / 3;
}

// What a load reads: everything, or the tables without the geometry (a walk that streams).
enum class GeometryLoad : uint8_t { whole, index_only };

// What is wrong with the arrays (texture coordinates one per vertex or none, indices within
// the vertices), or null where nothing is.
const char* mesh_arrays_problem(size_t vertices, size_t uvs, std::span<const uint32_t> indices);

// Pages over consecutive runs of `indices` (index_ends: where each ends, increasing, the last
// at indices.size()), each page's vertices those from the end of the last page's to one past
// its largest index (the last page's: to `vertex_count`): a set built by appending each
// page's vertices and its indices in the same order.
std::vector<MeshPage> pages_of_runs(std::span<const uint32_t> indices, uint32_t vertex_count,
                                    std::span<const uint32_t> index_ends);

// Writes the table and the pages (in the caller's transaction, if any).
Result<void> save_mesh_pages(Store& store, const std::string& prefix,
                             std::span<const Vertex> vertices, std::span<const glm::vec2> uvs,
                             std::span<const uint32_t> indices, std::span<const MeshPage> pages);
// The table, refused where the pages are not consecutive from zero.
Result<std::vector<MeshPage>> load_mesh_page_table(const Store& store, const std::string& prefix);
// Page `page` as it stands (indices from its first vertex), refused, naming the pack and the
// blob, where it is not what the table says or its indices leave it.
Result<std::shared_ptr<SceneMeshData>> read_mesh_page(const Store& store,
                                                      const std::string& prefix, uint32_t page,
                                                      const MeshPage& expected);
// Page `page` of a set as above: sliced from the set's arrays where it holds them (non-empty
// indices), else read from `store` (null: an error), where the set was saved under `prefix`.
Result<std::shared_ptr<SceneMeshData>> mesh_page(const Store* store, const std::string& prefix,
                                                 std::span<const MeshPage> pages, uint32_t page,
                                                 std::span<const Vertex> vertices,
                                                 std::span<const glm::vec2> uvs,
                                                 std::span<const uint32_t> indices);
// Every page end to end, indices absolute (texture coordinates where every page has them).
Result<void> read_mesh_pages(const Store& store, const std::string& prefix,
                             std::span<const MeshPage> pages,
                             std::vector<Vertex>& vertices, std::vector<glm::vec2>& uvs,
                             std::vector<uint32_t>& indices);

}  // namespace farfield
