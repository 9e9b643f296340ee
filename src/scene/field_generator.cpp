#include "farfield/scene/field_generator.hpp"

#include <cmath>
#include <string>

#include "farfield/core/text.hpp"

namespace farfield {

Result<void> validate_field_options(const FieldOptions& o) {
  if (o.count == 0) return make_error("--count must be at least 1");
  if (!(std::isfinite(o.spacing) && o.spacing > 0.0))
    return make_error("--spacing must be a positive number of metres (got ", number_text(o.spacing),
                      ")");
  if (o.spacing > 1e7) return make_error("--spacing of ", number_text(o.spacing), " m is absurd");
  return {};
}

Result<Scene> generate_field(const Scene& model, const FieldOptions& o, Progress& progress) {
  if (auto ok = validate_field_options(o); !ok) return ok.error();
  if (model.triangle_count() == 0) return make_error("the model has no triangles");
  if (o.count >= UINT32_MAX || o.count * model.vertices.size() >= UINT32_MAX ||
      o.count * model.indices.size() >= UINT32_MAX)
    return make_error("--count ", std::to_string(o.count), " copies of a model of ",
                      std::to_string(model.triangle_count()),
                      " triangles exceed 2^32 vertices or indices");

  // The model with its material colours folded into vertex colours, flattened in object order.
  bool any_transparent = false;
  // A copy is of the model's kind where all its objects share one (a field of trees stays
  // trees: clusters draws their boxes as billboards), else an unclassified mesh.
  ObjectKind kind = model.objects.front().kind;
  for (const Object& object : model.objects)
    if (object.kind != kind) kind = ObjectKind::mesh;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;  // relative to `vertices`
  vertices.reserve(model.vertices.size());
  for (const Object& object : model.objects) {
    const glm::vec4 tint = model.materials[object.material].base_color;
    any_transparent |= tint.a < 1.0f;
    const uint32_t base = static_cast<uint32_t>(vertices.size());
    for (uint32_t v = 0; v < object.vertex_count; ++v) {
      Vertex vertex = model.vertices[object.first_vertex + v];
      vertex.color = pack_color(unpack_color(vertex.color) * tint);
      vertices.push_back(vertex);
    }
    for (uint32_t i = 0; i < object.index_count; ++i)
      indices.push_back(model.indices[object.first_index + i] - object.first_vertex + base);
  }

  const glm::vec3 anchor(model.bounds.center().x, model.bounds.min.y, model.bounds.center().z);
  const uint64_t per_row = static_cast<uint64_t>(std::ceil(std::sqrt(double(o.count))));
  const uint64_t rows = (o.count + per_row - 1) / per_row;
  const float spacing = static_cast<float>(o.spacing);
  const glm::vec3 origin(-0.5f * spacing * float(per_row - 1), 0.0f,
                         -0.5f * spacing * float(rows - 1));

  Scene field;
  field.vertices.reserve(o.count * vertices.size());
  field.indices.reserve(o.count * indices.size());
  SceneBuilder builder(field);
  const uint32_t material =
      builder.add_material(Material{glm::vec4(1.0f, 1.0f, 1.0f, any_transparent ? 0.5f : 1.0f)});
  progress.start("generate field", o.count);
  // The first copy holds the model; the others are its instances, moved along the grid, so
  // that the file stores the model once (instances.hpp).
  glm::vec3 first_offset(0.0f);
  for (uint64_t c = 0; c < o.count; ++c) {
    const glm::vec3 offset =
        origin + glm::vec3(spacing * float(c % per_row), 0.0f, spacing * float(c / per_row)) -
        anchor;
    const std::string name = "copy_" + std::to_string(c);
    if (c == 0) {
      first_offset = offset;
      builder.begin_object(name, kind, material);
      for (const Vertex& v : vertices)
        builder.add_vertex(v.position + offset, unpack_normal(v.normal), v.color);
      for (size_t i = 0; i < indices.size(); i += 3)
        builder.add_triangle(indices[i], indices[i + 1], indices[i + 2]);
      builder.end_object();
    } else {
      builder.add_instance(name, kind, 0, glm::mat3(1.0f), offset - first_offset);
    }
    progress.advance();
  }
  progress.finish();
  return field;
}

}  // namespace farfield
