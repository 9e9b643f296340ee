// The cluster hierarchy (cluster_tree.hpp) as a 3D Tiles 1.1 tileset: it is an HLOD with a
// stated geometric error, which is what a tileset is. One tile a node of the tree: its
// bounding box, its merged mesh as content (a .glb through scene/glb_export) with the mesh's
// error in metres as geometricError, REPLACE refinement; the objects a node holds itself (on
// its children's boundaries, or in a leaf) at full detail in a child tile of error 0, so that
// refining all the way shows the scene as it is. A node without a merged mesh has no content
// and its parent's error (it is refined when its parent is). glTF's +Y up becomes 3D Tiles'
// +Z up in the bounding volumes (the content stays glTF, which viewers turn themselves).
// Where the bake made textured boxes for the clusters (clusters.boxes=all, paper 001's cluster
// representation), a cluster's box is a tile above its mesh's (the box's sides as textured
// quads cut out by alpha, its error in metres), where the box's error lies between the mesh's
// and the error of the tile above.
// Written as a folder (tileset.json, tiles/N.glb) or, for a name ending in .3dtiles, as one
// 3D Tiles package (store/tiles_package.hpp).
#pragma once

#include <cstdint>
#include <string>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/clusters/box_set.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"

namespace farfield {

struct TilesetSummary {
  uint64_t tiles = 0, contents = 0;  // tiles, and those with content
  uint64_t boxes = 0;                // tiles of textured boxes
  uint64_t bytes = 0;                // of tileset.json and the contents
  int depth = 0;                     // of the deepest tile (the root is 0)
  double root_error_m = 0.0;
};

Result<TilesetSummary> write_tileset(const Scene& scene, const ClusterTree& tree,
                                     const BoxSet& boxes, const std::string& out,
                                     Progress& progress);

}  // namespace farfield
