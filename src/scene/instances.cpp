#include "farfield/scene/instances.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace farfield {

InstanceTransform::InstanceTransform(const Instance& instance)
    : linear_(instance.linear),
      normal_(glm::transpose(glm::inverse(instance.linear))),
      offset_(instance.offset),
      identity_(instance.linear == glm::mat3(1.0f)) {}

Vertex InstanceTransform::operator()(const Vertex& v) const {
  if (identity_) return {v.position + offset_, v.normal, v.color};
  const glm::vec3 n = normal_ * unpack_normal(v.normal);
  const float length = glm::length(n);
  return {linear_ * v.position + offset_, length > 0.0f ? pack_normal(n / length) : v.normal,
          v.color};
}

double largest_stretch(const glm::mat3& linear) {
  // The largest eigenvalue of the symmetric A = L^T L, in closed form (trigonometric roots of
  // its characteristic cubic), in double precision.
  double a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      a[i][j] = double(glm::dot(linear[i], linear[j]));  // glm: linear[c] is column c
  const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
  double largest = std::max({a[0][0], a[1][1], a[2][2]});
  if (off > 0.0) {
    const double q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    const double p =
        std::sqrt(((a[0][0] - q) * (a[0][0] - q) + (a[1][1] - q) * (a[1][1] - q) +
                   (a[2][2] - q) * (a[2][2] - q) + 2.0 * off) /
                  6.0);
    double b[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) b[i][j] = (a[i][j] - (i == j ? q : 0.0)) / p;
    const double det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                       b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                       b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    const double phi = std::acos(std::clamp(det / 2.0, -1.0, 1.0)) / 3.0;
    largest = std::max(largest, q + 2.0 * p * std::cos(phi));
  }
  return std::sqrt(std::max(largest, 0.0));
}

const Instance* instance_of(const Scene& scene, uint32_t object) {
  const auto it = std::lower_bound(
      scene.instances.begin(), scene.instances.end(), object,
      [](const Instance& i, uint32_t o) { return i.object < o; });
  return it != scene.instances.end() && it->object == object ? &*it : nullptr;
}

const Instance* moved_copy_of(const Scene& scene, uint32_t object) {
  const Instance* instance = instance_of(scene, object);
  return instance && instance->linear == glm::mat3(1.0f) ? instance : nullptr;
}

StoredGeometry stored_geometry(const Scene& scene) {
  StoredGeometry g{scene.vertices.size(), scene.indices.size(), scene.uvs.size()};
  for (const Instance& i : scene.instances) {
    if (i.object >= scene.objects.size()) continue;  // validate_instances says so
    const Object& o = scene.objects[i.object];
    g.vertices -= o.vertex_count;
    g.indices -= o.index_count;
    if (o.material < scene.materials.size() && scene.textured(o)) g.uvs -= o.vertex_count;
  }
  return g;
}

namespace {

// The ranges every object has in the held form: one after the other, in object order.
struct Ranges {
  uint64_t vertex = 0, index = 0, uv = 0;
  void place(Object& o, bool textured) {
    o.first_vertex = uint32_t(vertex);
    o.first_index = uint32_t(index);
    o.first_uv = textured ? uint32_t(uv) : 0;
    vertex += o.vertex_count;
    index += o.index_count;
    if (textured) uv += o.vertex_count;
  }
};

bool finite(const glm::mat3& m) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

}  // namespace

std::string validate_instances(const Scene& s, InstanceForm form, bool geometry) {
  if (s.instances.empty()) return {};
  auto fail = [](uint32_t object, const std::string& what) {
    return "object " + std::to_string(object) + ": " + what;
  };
  uint64_t previous = 0;
  for (size_t k = 0; k < s.instances.size(); ++k) {
    const Instance& i = s.instances[k];
    if (i.object >= s.objects.size())
      return "instance " + std::to_string(k) + ": object " + std::to_string(i.object) +
             " out of range";
    if (k > 0 && i.object <= previous) return "instances not in increasing object order";
    previous = i.object;
    if (i.prototype >= i.object)
      return fail(i.object, "an instance of object " + std::to_string(i.prototype) +
                                ", not an earlier one");
    if (instance_of(s, i.prototype))
      return fail(i.object, "an instance of object " + std::to_string(i.prototype) +
                                ", itself an instance");
    const Object &o = s.objects[i.object], &p = s.objects[i.prototype];
    if (o.material != p.material || o.vertex_count != p.vertex_count ||
        o.index_count != p.index_count)
      return fail(i.object, "an instance of object " + std::to_string(i.prototype) +
                                " with another material, vertex or index count");
    const float det = glm::determinant(i.linear);
    if (!finite(i.linear) || !std::isfinite(i.offset.x) || !std::isfinite(i.offset.y) ||
        !std::isfinite(i.offset.z) || !std::isfinite(det) || !finite(glm::inverse(i.linear)))
      return fail(i.object, "an instance's transform is not finite");
    if (!(det > 0.0f)) return fail(i.object, "an instance's transform mirrors or flattens");
  }
  // Held, the scene must stay within 32-bit ranges (a stored one expands to it).
  uint64_t held_vertices = 0, held_indices = 0;
  for (const Object& o : s.objects) {
    held_vertices += o.vertex_count;
    held_indices += o.index_count;
  }
  if (held_vertices > UINT32_MAX || held_indices > UINT32_MAX)
    return "its instances expand past 2^32 - 1 vertices or indices";
  // The ranges: held, every object's in object order; stored, the same for all but the
  // instances, whose ranges are their prototypes'.
  Ranges next;
  for (uint32_t n = 0; n < s.objects.size(); ++n) {
    const Object& o = s.objects[n];
    const bool textured = o.material < s.materials.size() && s.textured(o);
    const Instance* i = instance_of(s, n);
    if (form == InstanceForm::stored && i) {
      const Object& p = s.objects[i->prototype];
      if (o.first_vertex != p.first_vertex || o.first_index != p.first_index ||
          (textured && o.first_uv != p.first_uv))
        return fail(n, "an instance whose ranges are not its prototype's");
      continue;
    }
    Object expected = o;
    next.place(expected, textured);
    if (expected.first_vertex != o.first_vertex || expected.first_index != o.first_index ||
        expected.first_uv != o.first_uv)
      return fail(n, "in a scene with instances, its ranges do not follow the object before");
  }
  if (form == InstanceForm::stored || !geometry) return {};
  for (const Instance& i : s.instances) {
    const Object &o = s.objects[i.object], &p = s.objects[i.prototype];
    const InstanceTransform move(i);
    for (uint32_t v = 0; v < o.vertex_count; ++v) {
      const Vertex want = move(s.vertices[p.first_vertex + v]);
      if (std::memcmp(&want, &s.vertices[o.first_vertex + v], sizeof(Vertex)) != 0)
        return fail(i.object, "vertex " + std::to_string(v) +
                                  " is not its prototype's moved by the instance's transform");
    }
    for (uint32_t k = 0; k < o.index_count; ++k)
      if (s.indices[o.first_index + k] - o.first_vertex !=
          s.indices[p.first_index + k] - p.first_vertex)
        return fail(i.object, "its triangles are not its prototype's");
    if (s.textured(o) && !std::equal(s.uvs.begin() + o.first_uv,
                                     s.uvs.begin() + o.first_uv + o.vertex_count,
                                     s.uvs.begin() + p.first_uv))
      return fail(i.object, "its texture coordinates are not its prototype's");
  }
  return {};
}

StoredForm stored_form(const Scene& held) {
  StoredForm out;
  out.objects = held.objects;
  const StoredGeometry sizes = stored_geometry(held);
  out.vertices.reserve(sizes.vertices);
  out.indices.reserve(sizes.indices);
  out.uvs.reserve(sizes.uvs);
  Ranges next;
  for (uint32_t n = 0; n < out.objects.size(); ++n) {
    Object& o = out.objects[n];
    if (const Instance* i = instance_of(held, n)) {
      const Object& p = out.objects[i->prototype];  // stored already: it comes earlier
      o.first_vertex = p.first_vertex;
      o.first_index = p.first_index;
      o.first_uv = p.first_uv;
      continue;
    }
    const Object from = o;
    next.place(o, held.textured(o));
    out.vertices.insert(out.vertices.end(), held.vertices.begin() + from.first_vertex,
                        held.vertices.begin() + from.first_vertex + from.vertex_count);
    for (uint32_t k = 0; k < from.index_count; ++k)
      out.indices.push_back(held.indices[from.first_index + k] - from.first_vertex +
                            o.first_vertex);
    if (held.textured(o))
      out.uvs.insert(out.uvs.end(), held.uvs.begin() + from.first_uv,
                     held.uvs.begin() + from.first_uv + from.vertex_count);
  }
  return out;
}

void expand_instances(Scene& s) {
  if (s.instances.empty()) return;
  std::vector<Object> held = s.objects;
  Ranges next;
  for (Object& o : held) next.place(o, s.textured(o));
  std::vector<Vertex> vertices(next.vertex);
  std::vector<uint32_t> indices(next.index);
  std::vector<glm::vec2> uvs(next.uv);
  for (uint32_t n = 0; n < held.size(); ++n) {
    const Object &to = held[n], &from = s.objects[n];  // from: its prototype's, where it is one
    const Instance* i = instance_of(s, n);
    if (i) {
      const InstanceTransform move(*i);
      for (uint32_t v = 0; v < to.vertex_count; ++v)
        vertices[to.first_vertex + v] = move(s.vertices[from.first_vertex + v]);
    } else {
      std::copy_n(s.vertices.begin() + from.first_vertex, to.vertex_count,
                  vertices.begin() + to.first_vertex);
    }
    for (uint32_t k = 0; k < to.index_count; ++k)
      indices[to.first_index + k] = s.indices[from.first_index + k] - from.first_vertex +
                                    to.first_vertex;
    if (s.textured(to))
      std::copy_n(s.uvs.begin() + from.first_uv, to.vertex_count, uvs.begin() + to.first_uv);
  }
  s.objects = std::move(held);
  s.vertices = std::move(vertices);
  s.indices = std::move(indices);
  s.uvs = std::move(uvs);
}

}  // namespace farfield
