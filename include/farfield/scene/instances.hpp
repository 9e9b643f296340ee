// Objects that repeat one model (Scene::instances): fields of copies, an imported mesh that
// several nodes place. The scene file stores their model once (docs/ffscene.md, "Instances");
// these are the rules both sides of the file share: how an instance's vertices follow from its
// prototype's, what a valid instance table is, and how the stored form, where an instance's
// ranges are its prototype's, becomes the form held in memory, where every object has its own.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "farfield/scene/scene.hpp"

namespace farfield {

// An instance's transform, prepared once for its vertices: positions by linear then offset,
// normals by the inverse transpose of linear, renormalised. Where linear is the identity a
// vertex's bits stay as they are but for the offset, so a translated copy is exact.
class InstanceTransform {
 public:
  explicit InstanceTransform(const Instance& instance);
  Vertex operator()(const Vertex& v) const;

 private:
  glm::mat3 linear_, normal_;
  glm::vec3 offset_;
  bool identity_;
};

// The most a linear map stretches a distance: its largest singular value (1 for a rotation),
// so that a distance bound on a prototype, times it, bounds the same on an instance.
double largest_stretch(const glm::mat3& linear);

// The instance of `object`, or null where it is not one (a binary search of the table).
const Instance* instance_of(const Scene& scene, uint32_t object);

// The instance of `object` where it is its prototype only moved, neither turned nor scaled
// (what it looks like from any direction is then the prototype's, moved), else null.
const Instance* moved_copy_of(const Scene& scene, uint32_t object);

// What a scene file holds of a scene's geometry: every object's but the instances'.
struct StoredGeometry {
  uint64_t vertices = 0, indices = 0, uvs = 0;
};
StoredGeometry stored_geometry(const Scene& scene);

// Where a scene keeps its objects' ranges: in memory every object has its own, laid out in
// object order; stored (in a file) an instance's ranges are its prototype's.
enum class InstanceForm : uint8_t { held, stored };

// The instance table against the objects: by increasing object, a prototype earlier and not an
// instance, of the same material, vertex and index counts, a finite transform that does not
// mirror, and, with instances, the objects' ranges tiling the arrays in object order (held) or
// an instance's ranges its prototype's (stored). Held scenes also have each instance's geometry
// checked against its prototype's, moved, when `geometry` is set. A message, or empty.
std::string validate_instances(const Scene& scene, InstanceForm form, bool geometry);

// A stored scene (validate_instances(stored) holds) made the held one: every instance gets its
// own ranges, in object order, and its geometry from its prototype's; indices are renumbered.
void expand_instances(Scene& stored);

// A held scene's objects and geometry in the stored form: an instance's ranges made its
// prototype's, the others' counted in arrays where the instances' geometry is left out
// (indices absolute into them).
struct StoredForm {
  std::vector<Object> objects;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<glm::vec2> uvs;
};
StoredForm stored_form(const Scene& held);

}  // namespace farfield
