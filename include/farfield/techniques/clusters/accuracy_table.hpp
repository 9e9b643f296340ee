// View-dependent accuracy tables (paper 001, Sec. 3.2): every representation of an object or
// a cluster (its levels of detail, cluster mesh and textured box) rendered orthographically
// from directions spread over the sphere (many more than the paper's five) and compared with
// the full geometry rendered the same way, by the paper's comparator (edges of the grey image)
// or by SSIM (core/image_similarity.hpp).
// The paper keeps an accuracy in [0, 1] per (representation, direction) and weighs it against
// benefit and cost; here it becomes an error in metres, on the scale of the geometric errors,
// so that both selection modes use it unchanged: the images are compared at `levels`
// resolutions, each half the last's, and the error is the texel size at which the
// representation's image reaches the threshold (similarity >= threshold): between the texels
// of the level that failed and the first that passed, where the similarity, taken as linear
// in log texel size between them, crosses the threshold; passing at the finest level, that
// level's texel times how far the similarity is from 1 relative to the threshold's; where
// no level passes, the subject's size. A representation whose error projects below a pixel
// then looks like the full geometry at the frame's resolution: a level that lost its windows
// has a geometric error of centimetres and an image error of metres.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/clusters/box_set.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"

namespace farfield {

class Store;
namespace gpu {
class Renderer;
}

enum class Comparator : uint8_t { ssim, edges };  // edges: the paper's

struct AccuracyOptions {
  int directions = 16;
  int resolution_px = 64;  // texels across the subject's bounding sphere at the finest level
  int levels = 4;
  Comparator comparator = Comparator::ssim;
  double threshold = 0.97;
};

// `count` unit directions spread evenly over the sphere (a Fibonacci lattice).
std::vector<glm::vec3> sphere_directions(int count);

struct AccuracyTable {
  std::vector<glm::vec3> directions;  // from a subject towards the viewer
  // Per representation, one error (metres) per direction.
  std::vector<float> lod_error;   // LodSet::lods
  std::vector<float> box_error;   // BoxSet::boxes
  std::vector<float> node_error;  // ClusterTree::nodes (their cluster meshes; 0 unclustered)
  bool empty() const { return directions.empty(); }
  // The direction nearest `towards_viewer` (need not be unit).
  uint32_t nearest(const glm::vec3& towards_viewer) const;
  float lod(uint32_t lod, uint32_t direction) const {
    return lod_error[size_t(lod) * directions.size() + direction];
  }
  float box(uint32_t box, uint32_t direction) const {
    return box_error[size_t(box) * directions.size() + direction];
  }
  float node(uint32_t node, uint32_t direction) const {
    return node_error[size_t(node) * directions.size() + direction];
  }
};

// Renders with `renderer` (a renderer of `scene`); the levels' errors are made non-decreasing
// along each chain, direction by direction. The levels' and clusters' meshes are taken a page
// at a time from the sets where they hold them, else from `store`, where they were saved.
Result<AccuracyTable> bake_accuracy_table(const Scene& scene, const LodSet& lods,
                                          const ClusterTree& tree, const BoxSet& boxes,
                                          gpu::Renderer& renderer, const AccuracyOptions& options,
                                          Progress& progress, const Store* store = nullptr);

// Blobs "clusters/accuracy_*" and back; a pack without them holds no table (an empty one).
// Refused: arrays that do not match the levels, boxes and nodes, or errors not finite.
Result<void> save_accuracy_table(const AccuracyTable& table, Store& store);
Result<AccuracyTable> load_accuracy_table(const Store& store, const LodSet& lods,
                                          const ClusterTree& tree, const BoxSet& boxes);

}  // namespace farfield
