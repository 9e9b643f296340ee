// How a scene drawn instanced names its triangles (gpu/instance_layout.hpp), without GL: every
// held index and vertex number maps onto an uploaded one that, moved by its instance's
// transform, is the held vertex.
#include "farfield/gpu/instance_layout.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "farfield/scene/instances.hpp"
#include "test_util.hpp"

namespace farfield {
namespace {

using gpu::InstanceLayout;

// A row of four boxes, then copies of boxes 0, 2 and 1 moved up and one of box 0 turned and
// shrunk, with a plain box between the copies (so that objects drawn as they are come after
// instances too).
Scene row_with_copies() {
  Scene s = test::make_box_row(4);
  SceneBuilder b(s);
  b.add_instance("lifted 0", ObjectKind::mesh, 0, glm::mat3(1.0f), {0, 1.5f, 0});
  b.add_instance("lifted 2", ObjectKind::mesh, 2, glm::mat3(1.0f), {0, 1.5f, 0.5f});
  b.begin_object("plain", ObjectKind::mesh, s.objects[0].material);
  test::add_cuboid(b, {0, 4, 0}, {1, 5, 1});
  b.end_object();
  b.add_instance("lifted glass", ObjectKind::mesh, 1, glm::mat3(1.0f), {0, 1.5f, 0});
  const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(0, 1, 0))) * 0.6f;
  b.add_instance("turned", ObjectKind::mesh, 0, turn, {6.3f, 1.6f, 0.2f});
  return s;
}

// The held vertex that uploaded vertex `v` stands for, drawn with `instance`'s placement.
glm::vec3 placed(const Scene& held, const Scene& uploaded, uint32_t v, uint32_t instance) {
  const Vertex& u = uploaded.vertices[v];
  return instance == InstanceLayout::kOwn
             ? u.position
             : InstanceTransform(held.instances[instance])(u).position;
}

TEST(InstanceLayout, EveryHeldNumberMapsOntoTheVertexItStandsFor) {
  const Scene held = row_with_copies();
  ASSERT_EQ(held.instances.size(), 4u);
  const Scene uploaded = gpu::uploaded_form(held);
  const InstanceLayout layout(held, uploaded);
  ASSERT_TRUE(layout.placed());
  ASSERT_EQ(layout.instance_count(), 4u);
  EXPECT_LT(uploaded.vertices.size(), held.vertices.size());
  // Index runs: a whole scene range crossing every object, split where instances begin and end.
  size_t runs = 0;
  for (uint32_t at = 0, end = uint32_t(held.indices.size()); at < end; ++runs) {
    const InstanceLayout::Run run = layout.index_run(at, end);
    ASSERT_GT(run.count, 0u);
    for (uint32_t j = 0; j < run.count; ++j)
      ASSERT_EQ(placed(held, uploaded, uploaded.indices[run.uploaded_at + j], run.instance),
                held.vertices[held.indices[at + j]].position)
          << "held index " << at + j;
    at += run.count;
  }
  // The first four boxes and the plain one in two runs, each instance one.
  EXPECT_EQ(runs, 2u + 4u);
  // Vertex numbers (as DrawList::scene_indices hold them), a triangle at a time.
  std::vector<uint32_t> numbers, instances;
  layout.place_vertices(held.indices, numbers, instances);
  ASSERT_EQ(numbers.size(), held.indices.size());
  ASSERT_EQ(instances.size(), held.indices.size() / 3);
  for (uint32_t o = 0; o < held.objects.size(); ++o) {
    const Instance* instance = instance_of(held, o);
    const uint32_t k = instance ? uint32_t(instance - held.instances.data()) : InstanceLayout::kOwn;
    const Object& object = held.objects[o];
    for (uint32_t i = object.first_index; i < object.first_index + object.index_count; ++i) {
      EXPECT_EQ(instances[i / 3], k) << "object " << o;
      EXPECT_EQ(placed(held, uploaded, numbers[i], k), held.vertices[held.indices[i]].position);
    }
  }
}

TEST(InstanceLayout, WithoutInstancesNumbersStayAsHeld) {
  const Scene held = test::make_box_row(3);
  const InstanceLayout layout;
  EXPECT_FALSE(layout.placed());
  const InstanceLayout::Run run = layout.index_run(6, 30);
  EXPECT_EQ(run.uploaded_at, 6u);
  EXPECT_EQ(run.count, 24u);
  EXPECT_EQ(run.instance, InstanceLayout::kOwn);
  std::vector<uint32_t> numbers, instances;
  layout.place_vertices(held.indices, numbers, instances);
  EXPECT_EQ(numbers, held.indices);
}

}  // namespace
}  // namespace farfield
