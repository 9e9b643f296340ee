// libFuzzer target for the cluster hierarchy's readers: load_cluster_tree (a pack holding
// fuzzed nodes, objects, parts, vertices, texture coordinates and indices) and decode_parts
// (a resumable bake's batch of simplified meshes). An accepted tree must be safe to walk from
// the root (each node met once, its ranges followed to the vertices); accepted parts must
// have their indices within their vertices.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "farfield/techniques/clusters/bake_work.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "fuzz_pack.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  const bool parts = in.ConsumeBool();
  if (parts) {
    const size_t items = in.ConsumeIntegralInRange<size_t>(0, 8);
    const std::vector<uint8_t> bytes = in.ConsumeRemainingBytes<uint8_t>();
    auto decoded = farfield::decode_parts(std::as_bytes(std::span(bytes)), items, "batch");
    if (decoded) {
      if (decoded->size() != items) std::abort();
      uint64_t sum = 0;
      for (const farfield::PartList& item : *decoded)
        for (const farfield::SimplifiedPart& p : item)
          for (uint32_t i : p.mesh.indices) sum += p.mesh.vertices[i].color;
      volatile uint64_t sink = sum;
      (void)sink;
    }
    return 0;
  }
  const std::string path = fuzz::scratch_pack("cluster-tree");
  fuzz::remove_pack(path);
  {
    auto store = farfield::Store::open(path, farfield::Store::Mode::kReadWrite);
    if (!store) std::abort();
    {
      auto transaction = store->begin();
      if (!transaction) std::abort();
      fuzz::put(*store, "clusters/tree_nodes", fuzz::records(in, sizeof(farfield::ClusterNode)));
      fuzz::put(*store, "clusters/tree_objects", fuzz::records(in, sizeof(uint32_t)));
      fuzz::put(*store, "clusters/tree_parts", fuzz::records(in, sizeof(farfield::ClusterPart)));
      fuzz::put(*store, "clusters/tree_vertices", fuzz::records(in, sizeof(farfield::Vertex)));
      fuzz::put(*store, "clusters/tree_uvs", fuzz::records(in, sizeof(glm::vec2)));
      fuzz::put(*store, "clusters/tree_indices", fuzz::records(in, sizeof(uint32_t)));
      (void)transaction->commit();
    }
    const farfield::Scene& scene = fuzz::small_scene();
    auto tree = farfield::load_cluster_tree(*store, scene);
    if (tree) {
      uint64_t sum = 0, met = 0;
      std::vector<uint32_t> stack;
      if (!tree->nodes.empty()) stack.push_back(0);
      while (!stack.empty()) {
        const farfield::ClusterNode& node = tree->nodes[stack.back()];
        stack.pop_back();
        if (++met > tree->nodes.size()) std::abort();  // a node met twice
        for (uint32_t k = node.objects_begin; k < node.objects_end; ++k)
          sum += scene.objects[tree->objects[k]].index_count;
        for (uint32_t p = node.parts_begin; p < node.parts_end; ++p) {
          const farfield::ClusterPart& part = tree->parts[p];
          sum += scene.materials[part.material].base_color.x > 0.5f;
          for (uint32_t i = part.first_index; i < part.first_index + part.index_count; ++i)
            sum += tree->vertices[tree->indices[i]].color;
        }
        for (uint32_t c = 0; c < node.child_count; ++c) stack.push_back(node.first_child + c);
      }
      volatile uint64_t sink = sum;
      (void)sink;
    }
  }
  fuzz::remove_pack(path);
  return 0;
}
