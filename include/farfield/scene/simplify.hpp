// Mesh simplification for levels of detail (paper 001, Sec. 4.1.2: "simplified LODs" of each
// conceptual object), through meshoptimizer (Debian's 0.18): the topology-preserving
// simplifier on a position-welded copy of the mesh, so that seams of flat-shaded faces and
// texture borders do not lock the vertices on them, falling back to the sloppy (vertex
// clustering) simplifier where it stalls, which also removes whole small parts. The error is
// a distance in metres: meshoptimizer's, which is relative to the mesh's extent, scaled by
// meshopt_simplifyScale, raised to a bound of the distance from every point of either surface
// to the other (surface_distance; tests check it against random points of both).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "farfield/scene/scene.hpp"

namespace farfield {

// Triangles of one material in the scene's vertex format, indices local to `vertices`.
struct MeshPart {
  std::vector<Vertex> vertices;
  std::vector<glm::vec2> uvs;  // one per vertex, or empty (untextured)
  std::vector<uint32_t> indices;
  uint32_t material = 0;  // into Scene::materials
  uint64_t triangle_count() const { return indices.size() / 3; }
};

// The triangles of `objects` that have `material`, as one part (a cluster's merged mesh is
// one part per material).
MeshPart gather_part(const Scene& scene, std::span<const uint32_t> objects, uint32_t material);

struct SimplifyOptions {
  double target_ratio = 0.5;  // of the part's triangles
  // The simplifier stops before this error (metres); infinity: the ratio alone decides.
  float max_error_m = INFINITY;
  bool allow_sloppy = true;  // fall back to vertex clustering where the ratio is not met
};

struct SimplifiedPart {
  MeshPart mesh;
  // Distance between this mesh and the original, metres (nothing left: the part's diagonal).
  float error_m = 0;
  bool sloppy = false;  // made by the sloppy simplifier
};

// One simplification of `part` (from the original, so that errors do not add up along a
// chain). The result never has more triangles than the part.
SimplifiedPart simplify_part(const MeshPart& part, const SimplifyOptions& options);

// The largest distance from `points` to the triangles of `mesh` (0 for no points, infinity
// for a mesh without triangles).
float farthest_distance(const std::vector<glm::vec3>& points, const MeshPart& mesh);
// An upper bound of the distance from any point of `from`'s triangles to `to`'s surface
// (one-sided Hausdorff distance), settled to 1/200 of the two meshes' extent where sampling
// 16 steps an edge allows (else a looser bound: 1/28 of the longest edge of a triangle).
float surface_distance(const MeshPart& from, const MeshPart& to);

}  // namespace farfield
