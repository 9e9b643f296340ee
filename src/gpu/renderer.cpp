#include "farfield/gpu/renderer.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <compare>
#include <cstddef>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "farfield/core/assert.hpp"
#include "farfield/gpu/instance_layout.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/gpu/scene_chunks.hpp"
#include "gpu_resources.hpp"
#include "scene_textures.hpp"
#include "shaders.hpp"

namespace farfield::gpu {

namespace {

// DrawElementsIndirectCommand as the GL reads it from the indirect buffer.
struct DrawCommand {
  GLuint count;
  GLuint instance_count;
  GLuint first_index;
  GLint base_vertex;
  GLuint base_instance;  // the material: selects the instanced material colour
};
static_assert(sizeof(DrawCommand) == 20);

struct QuadVertex {
  glm::vec3 position;
  glm::vec2 texcoord;
};

// A chunk's texture coordinates, one per vertex (those of untextured objects stay zero),
// bound to the chunk's VAO at binding 3; no buffer for a chunk without textured objects.
Result<void> add_texture_coordinates(const Scene& scene, GLuint vao, const SceneChunk& range,
                                     GLuint& buffer) {
  std::vector<glm::vec2> uvs;
  for (const Object& o : scene.objects) {
    if (o.first_index < range.first_index ||
        o.first_index >= range.first_index + range.index_count || !scene.textured(o))
      continue;
    if (uvs.empty()) uvs.resize(range.vertex_count);
    std::copy_n(scene.uvs.begin() + o.first_uv, o.vertex_count,
                uvs.begin() + (o.first_vertex - range.first_vertex));
  }
  if (uvs.empty()) return {};
  if (auto made = make_buffer(buffer, "texture coordinate buffer", uvs.size() * sizeof(glm::vec2),
                              uvs.data(), 0);
      !made)
    return made;
  glVertexArrayVertexBuffer(vao, 3, buffer, 0, sizeof(glm::vec2));
  set_attribute(vao, kTexcoordAttrib, 2, GL_FLOAT, GL_FALSE, 0, 3);
  return {};
}

}  // namespace

struct Renderer::State {
  // The scene's geometry, chunked (scene_chunks.hpp); each chunk's VAO also reads the
  // materials, one per instance.
  struct Chunk {
    SceneChunk range;
    GLuint vertex_buffer = 0, index_buffer = 0, vao = 0;
    GLuint uv_buffer = 0;  // textured scenes: the chunk's texture coordinates (0 elsewhere)
    GLuint indexed_vao = 0;  // the same, its indices from indexed_buffer (DrawList::scene_indices)
  };
  std::vector<Chunk> chunks;
  // Drawn instanced (Scene::instances, instance_layout.hpp): the chunks hold the scene's
  // stored form; `layout` maps held index and vertex numbers onto it. Not placed: the chunks
  // hold the scene as it is (no instances, or InstanceDrawing::expanded).
  static constexpr uint32_t kOwn = InstanceLayout::kOwn;
  InstanceLayout layout;
  // Draw records (a command's baseInstance: material colour, texturing, placement): the
  // materials, then the white one, then per instance two, in its material and in white.
  std::vector<Placement> placements;  // per record; empty in a scene without instances
  std::vector<uint32_t> instance_materials;  // per instance
  GLuint placement_buffer = 0;
  // Records of this frame's instanced commands (a scene mesh's range drawn for several
  // instances in one command, DrawRange::instance), after the fixed ones: each a copy of its
  // instance's record. Their materials and texturing are copied from the fixed records'.
  uint32_t frame_records_first = 0, frame_records_capacity = 0;
  std::vector<Material> record_materials;             // the fixed records'
  std::vector<MaterialTexturing> record_texturing;    // the fixed records' (textured scenes)
  std::vector<Material> frame_materials;
  std::vector<MaterialTexturing> frame_texturing;
  std::vector<Placement> frame_placements;
  GLuint command_placement_buffer = 0;  // the visibility pass's, per command
  size_t command_placement_capacity = 0;
  uint64_t geometry_bytes = 0;  // of the chunks' buffers
  bool placed() const { return layout.placed(); }
  uint32_t instance_record(uint32_t instance, bool white) const {
    return white_material + 1 + 2 * instance + (white ? 1 : 0);
  }
  // A piece of a scene range that one command draws: `count` indices from the held scene's
  // `held_at`, which are the uploaded `uploaded_at` of chunk `chunk`, with draw record `record`.
  struct Piece {
    uint32_t held_at, uploaded_at, count;
    size_t chunk;
    uint32_t record;
  };
  // The pieces of held indices [first, first + count) of `material`, split at instances and
  // chunks; `white`: drawn in the white material (draw_everything_at_once).
  template <class F>
  void for_each_piece(uint32_t first, uint32_t count, uint32_t material, bool white,
                      F&& f) const {
    for (uint32_t at = first, end = first + count; at < end;) {
      const InstanceLayout::Run run = layout.index_run(at, end);
      uint32_t record = white ? white_material : material;
      if (run.instance != kOwn) {
        FF_ASSERT(white || material == instance_materials[run.instance],
                  "range of material %u over instance %u, whose material is %u", material,
                  run.instance, instance_materials[run.instance]);
        record = instance_record(run.instance, white);
      }
      const size_t c = chunk_of(chunk_ranges, run.uploaded_at);
      const SceneChunk& chunk = chunk_ranges[c];
      FF_ASSERT(run.uploaded_at >= chunk.first_index &&
                    run.uploaded_at < chunk.first_index + chunk.index_count,
                "range [%u, %u) outside every chunk", at, end);
      const uint32_t n =
          std::min(run.count, chunk.first_index + chunk.index_count - run.uploaded_at);
      f(Piece{at, run.uploaded_at, n, c, record});
      at += n;
    }
  }
  // This frame's DrawList::scene_indices in uploaded vertex numbers, and per triangle its
  // instance (kOwn: none): placed scenes only (else the list's own are drawn).
  std::vector<uint32_t> placed_indices;
  std::vector<uint32_t> triangle_instances;
  // How a material is drawn: its texture array (-1: untextured) and whether back faces are
  // drawn (double-sided). Ordered: opaque ranges are grouped by it.
  struct Drawing {
    int array = -1;
    bool double_sided = false;
    auto operator<=>(const Drawing&) const = default;
  };
  // Consecutive scene commands of one vertex array (a chunk's or a scene mesh's) and one way
  // of drawing, drawn by one multi-draw.
  struct SceneBatch {
    GLuint vao;
    size_t first_command, count;
    Drawing drawing;
    uint32_t mesh = 0;  // 0: the scene's own buffers
    glm::vec2 fade{1.0f, 0.0f};  // faded batches: FadedRange's coverage and complement
  };
  std::vector<SceneBatch> opaque_batches, transparent_batches;
  bool culling_off = false;       // drawing the transparent pass, which draws both sides anyway
  std::vector<Drawing> drawings;  // per material, the white one last
  bool uniform_drawing = true;    // every material is drawn alike: no grouping
  std::vector<DrawRange> sorted_ranges;  // opaque ranges grouped by drawing, order kept within
  GLuint material_buffer = 0, indirect_buffer = 0;
  // Textured scenes only: the arrays and each material's texturing, read per instance.
  std::unique_ptr<SceneTextures> textures;
  GLuint texturing_buffer = 0;
  GLuint vao = 0, program = 0;  // vao: bound between draws, reads nothing
  // Textured scenes: the program of textured batches (untextured ones keep `program`).
  GLuint textured_scene_program = 0;
  // DrawList::faded: the same programs keeping part of the pixels (kFadeUniform).
  GLuint faded_program = 0, faded_textured_program = 0;
  // Untextured, single-sided opaque batches: the colour lit and tinted at the vertices.
  GLuint one_sided_program = 0;
  std::vector<SceneBatch> faded_batches;
  std::vector<DrawRange> fade_group;
  std::vector<SceneBatch> fade_group_batches;
  // Every scene program (those not built are 0).
  std::array<GLuint, 5> scene_programs() const {
    return {program, textured_scene_program, faded_program, faded_textured_program,
            one_sided_program};
  }
  GpuResources resources;
  GLuint proxy_program = 0, textured_program = 0;
  // A run of consecutive MeshDraws of one mesh and texture, drawn by one call: commands in
  // the indirect buffer, or (more than kMeshRangesPerCall) indices gathered into the stream.
  struct MeshRun {
    size_t begin, end;     // into DrawList::meshes
    size_t first_command;  // gathered == false
    size_t stream_offset;  // gathered == true, in indices
    bool gathered;
  };
  std::vector<MeshRun> runs;
  std::vector<uint32_t> stream;  // this frame's gathered indices
  GLuint stream_buffer = 0;
  size_t stream_capacity = 0;  // in indices
  // Backdrop quads and annotation lines: streamed every frame.
  GLuint quad_program = 0, quad_vao = 0, quad_buffer = 0, line_vao = 0, line_buffer = 0;
  size_t quad_capacity = 0, line_capacity = 0;  // in vertices
  std::vector<QuadVertex> quad_vertices;
  std::vector<ProxyVertex> line_vertices;
  GLuint timer[2] = {0, 0};  // GL_TIMESTAMP queries at the frame's start and end
  GLuint framebuffer = 0, color_target = 0, depth_target = 0;  // offscreen, 0 = default
  int offscreen_width = 0, offscreen_height = 0;
  int frame_width = 0, frame_height = 0;  // of the last frame drawn, for capture()
  uint32_t index_count = 0;
  std::vector<SceneChunk> chunk_ranges;  // chunks[i].range, for chunk_of
  uint32_t white_material = 0;           // after the scene's materials, for draw_everything_at_once
  size_t indirect_capacity = 0;          // in commands
  std::vector<DrawCommand> commands;     // staging, capacity kept between frames
  bool has_timer = false;
  float clear_alpha = 1.0f;
  // This frame's DrawList::scene_indices, read by the chunks' indexed_vao.
  GLuint indexed_buffer = 0;
  size_t indexed_capacity = 0;  // in indices
  std::vector<DrawRange> sorted_runs;
  // The visibility pass: its programs, per command the first triangle, the occupancy bits.
  std::vector<uint8_t> see_through;  // per material: blended or cut out
  GLuint visibility_depth_program = 0, visibility_mark_program = 0;
  GLuint first_triangle_buffer = 0, occupancy_buffer = 0;
  size_t first_triangle_capacity = 0, occupancy_words = 0;

  ~State() {
    for (const Chunk& c : chunks) {
      const GLuint chunk_buffers[] = {c.vertex_buffer, c.index_buffer, c.uv_buffer};
      glDeleteBuffers(3, chunk_buffers);
      const GLuint chunk_vaos[] = {c.vao, c.indexed_vao};
      glDeleteVertexArrays(2, chunk_vaos);
    }
    glDeleteBuffers(1, &indexed_buffer);
    glDeleteBuffers(1, &placement_buffer);
    glDeleteBuffers(1, &command_placement_buffer);
    const GLuint buffers[] = {material_buffer, indirect_buffer,       stream_buffer,
                              quad_buffer,     line_buffer,           texturing_buffer,
                              occupancy_buffer, first_triangle_buffer};
    glDeleteBuffers(8, buffers);
    glDeleteProgram(visibility_depth_program);
    glDeleteProgram(visibility_mark_program);
    const GLuint vaos[] = {vao, quad_vao, line_vao};
    glDeleteVertexArrays(3, vaos);
    glDeleteProgram(program);
    glDeleteProgram(textured_scene_program);
    glDeleteProgram(faded_program);
    glDeleteProgram(faded_textured_program);
    glDeleteProgram(one_sided_program);
    glDeleteProgram(proxy_program);
    glDeleteProgram(textured_program);
    glDeleteProgram(quad_program);
    glDeleteQueries(2, timer);
    glDeleteFramebuffers(1, &framebuffer);
    const GLuint targets[] = {color_target, depth_target};
    glDeleteRenderbuffers(2, targets);
  }

  // Appends the commands of scene ranges, split where a range crosses chunks, and their
  // batches: runs of one chunk and one way of drawing, in the list's order (blending depends
  // on it). Where materials are drawn differently, opaque ranges are first grouped by drawing
  // (depth-tested, their order does not change the image), so that each multi-draw samples
  // one texture array (a per-pixel choice among arrays costs every array's fetch on
  // llvmpipe) and culls or not as a whole.
  void add_scene_ranges(const std::vector<DrawRange>& ranges, std::vector<SceneBatch>& batches,
                        bool opaque) {
    batches.clear();
    const std::vector<DrawRange>* in = &ranges;
    // Opaque ranges that name instances are also grouped by what they draw (mesh and range), so
    // that the copies of one range are one instanced command.
    const bool copies = opaque && frame_records_capacity > 0 &&
                        std::count_if(ranges.begin(), ranges.end(), [](const DrawRange& r) {
                          return r.instance != kNoInstance;
                        }) > 1;
    if (opaque && (!uniform_drawing || copies)) {
      sorted_ranges = ranges;
      const auto key = [&](const DrawRange& r) {
        const bool copy = r.instance != kNoInstance;
        return std::tuple(drawings[r.material], copy, copy ? r.mesh.id : 0u,
                          copy ? r.first_index : 0u, copy ? r.index_count : 0u);
      };
      std::stable_sort(sorted_ranges.begin(), sorted_ranges.end(),
                       [&](const DrawRange& a, const DrawRange& b) { return key(a) < key(b); });
      in = &sorted_ranges;
    }
    for (size_t i = 0; i < in->size(); ++i) {
      const DrawRange& r = (*in)[i];
      if (r.mesh) {
        i += add_scene_mesh_ranges(*in, i, batches) - 1;
        continue;
      }
      FF_ASSERT(r.instance == kNoInstance, "a range of the scene's own buffers names instance %u",
                r.instance);
      FF_ASSERT(r.first_index % 3 == 0 && r.index_count % 3 == 0 &&
                    uint64_t(r.first_index) + r.index_count <= index_count &&
                    r.material < white_material,
                "range [%u, +%u) material %u outside the scene's %u indices and %u materials",
                r.first_index, r.index_count, r.material, index_count, white_material);
      const Drawing drawing = drawings[r.material];
      for_each_piece(r.first_index, r.index_count, r.material, false, [&](const Piece& p) {
        const SceneChunk& chunk = chunk_ranges[p.chunk];
        const GLuint chunk_vao = chunks[p.chunk].vao;
        if (batches.empty() || batches.back().vao != chunk_vao ||
            batches.back().drawing != drawing)
          batches.push_back({chunk_vao, commands.size(), 0, drawing});
        commands.push_back({p.count, 1, p.uploaded_at - chunk.first_index,
                            -GLint(chunk.first_vertex), p.record});
        batches.back().count++;
      });
    }
  }

  // Runs of DrawList::scene_indices: a command each (split where they cross chunks), after
  // the batches of ranges; opaque runs grouped by drawing as the ranges are.
  void add_indexed_runs(const DrawList& list, const std::vector<DrawRange>& runs,
                        std::vector<SceneBatch>& batches, bool opaque) {
    const std::vector<DrawRange>* in = &runs;
    if (opaque && !uniform_drawing) {
      sorted_runs = runs;
      std::stable_sort(sorted_runs.begin(), sorted_runs.end(),
                       [&](const DrawRange& a, const DrawRange& b) {
                         return drawings[a.material] < drawings[b.material];
                       });
      in = &sorted_runs;
    }
    for (const DrawRange& r : *in) {
      FF_ASSERT(r.first_index % 3 == 0 && r.index_count % 3 == 0 &&
                    uint64_t(r.first_index) + r.index_count <= list.scene_indices.size() &&
                    r.material < white_material,
                "indexed run [%u, +%u) material %u outside the list's %zu indices", r.first_index,
                r.index_count, r.material, list.scene_indices.size());
      const Drawing drawing = drawings[r.material];
      const std::vector<uint32_t>& indices = placed() ? placed_indices : list.scene_indices;
      // A command per run of triangles in one chunk and of one instance (or none).
      const auto instance = [&](uint32_t at) {
        return placed() ? triangle_instances[at / 3] : kOwn;
      };
      for (uint32_t at = r.first_index, end = r.first_index + r.index_count; at < end;) {
        const size_t c = chunk_of_vertex(chunk_ranges, indices[at]);
        const uint32_t own = instance(at);
        uint32_t stop = at + 3;
        while (stop < end && chunk_of_vertex(chunk_ranges, indices[stop]) == c &&
               instance(stop) == own)
          stop += 3;
        if (batches.empty() || batches.back().vao != chunks[c].indexed_vao ||
            batches.back().drawing != drawing)
          batches.push_back({chunks[c].indexed_vao, commands.size(), 0, drawing});
        FF_ASSERT(own == kOwn || r.material == instance_materials[own],
                  "indexed run of material %u over instance %u, whose material is %u",
                  r.material, own, own == kOwn ? 0 : instance_materials[own]);
        commands.push_back({stop - at, 1, at, -GLint(chunk_ranges[c].first_vertex),
                            own == kOwn ? r.material : instance_record(own, false)});
        batches.back().count++;
        at = stop;
      }
    }
  }

  // Placed scenes: the list's scene_indices in uploaded vertex numbers, and their triangles'
  // instances (a triangle's corners lie in one object).
  void place_scene_indices(const DrawList& list) {
    if (placed()) layout.place_vertices(list.scene_indices, placed_indices, triangle_instances);
  }

  void upload_scene_indices(const DrawList& list) {
    if (list.scene_indices.empty()) return;
    if (list.scene_indices.size() > indexed_capacity) {
      indexed_capacity = std::bit_ceil(list.scene_indices.size());
      glDeleteBuffers(1, &indexed_buffer);
      const Result<void> made =
          make_buffer(indexed_buffer, "scene index stream", indexed_capacity * sizeof(uint32_t),
                      nullptr, GL_DYNAMIC_STORAGE_BIT);
      FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
      for (const Chunk& c : chunks) glVertexArrayElementBuffer(c.indexed_vao, indexed_buffer);
    }
    const std::vector<uint32_t>& indices = placed() ? placed_indices : list.scene_indices;
    glNamedBufferSubData(indexed_buffer, 0, GLsizeiptr(indices.size() * sizeof(uint32_t)),
                         indices.data());
  }

  // A range of a scene mesh, ranges[at]: one command, indices from the mesh's start; with the
  // ranges after it that draw the same for other instances, one instanced command whose
  // records this frame makes (as long as there is room). Returns the ranges it took.
  size_t add_scene_mesh_ranges(const std::vector<DrawRange>& ranges, size_t at,
                               std::vector<SceneBatch>& batches) {
    const DrawRange& r = ranges[at];
    const GpuMesh& mesh = resources.mesh(r.mesh);
    FF_ASSERT(mesh.kind == MeshKind::scene, "scene range names mesh %u, which is no scene mesh",
              r.mesh.id);
    FF_ASSERT(r.first_index % 3 == 0 && r.index_count % 3 == 0 &&
                  uint64_t(r.first_index) + r.index_count <= mesh.index_count &&
                  r.material < white_material,
              "range [%u, +%u) material %u outside mesh %u's %u indices and %u materials",
              r.first_index, r.index_count, r.material, r.mesh.id, mesh.index_count,
              white_material);
    size_t n = 1;
    if (r.instance != kNoInstance)
      while (at + n < ranges.size() && frame_placements.size() + n < frame_records_capacity &&
             same_range_for_instances(r, ranges[at + n]))
        ++n;
    for (size_t k = at; k < at + n; ++k)
      FF_ASSERT(ranges[k].instance == kNoInstance ||
                    (ranges[k].instance < instance_materials.size() &&
                     instance_materials[ranges[k].instance] == r.material),
                "range of mesh %u placed by instance %u of %zu, whose material is not %u",
                r.mesh.id, ranges[k].instance, instance_materials.size(), r.material);
    uint32_t record =
        r.instance == kNoInstance ? r.material : instance_record(r.instance, false);
    if (n > 1) {
      record = frame_records_first + uint32_t(frame_placements.size());
      for (size_t k = at; k < at + n; ++k) {
        const uint32_t fixed = instance_record(ranges[k].instance, false);
        frame_placements.push_back(placements[fixed]);
        frame_materials.push_back(record_materials[fixed]);
        if (!record_texturing.empty()) frame_texturing.push_back(record_texturing[fixed]);
      }
    }
    const Drawing drawing = drawings[r.material];
    if (batches.empty() || batches.back().vao != mesh.vao || batches.back().drawing != drawing)
      batches.push_back({mesh.vao, commands.size(), 0, drawing, r.mesh.id});
    commands.push_back({r.index_count, GLuint(n), r.first_index, 0, record});
    batches.back().count++;
    return n;
  }

  // This frame's records of instanced commands, to their buffers; the next frame starts anew.
  void upload_frame_records() {
    if (!frame_placements.empty()) {
      const GLintptr first = frame_records_first;
      glNamedBufferSubData(placement_buffer, first * GLintptr(sizeof(Placement)),
                           GLsizeiptr(frame_placements.size() * sizeof(Placement)),
                           frame_placements.data());
      glNamedBufferSubData(material_buffer, first * GLintptr(sizeof(Material)),
                           GLsizeiptr(frame_materials.size() * sizeof(Material)),
                           frame_materials.data());
      if (!frame_texturing.empty())
        glNamedBufferSubData(texturing_buffer, first * GLintptr(sizeof(MaterialTexturing)),
                             GLsizeiptr(frame_texturing.size() * sizeof(MaterialTexturing)),
                             frame_texturing.data());
    }
    frame_placements.clear();
    frame_materials.clear();
    frame_texturing.clear();
  }

  // What every vertex array of scene geometry reads besides its vertices (binding 0) and
  // texture coordinates (binding 3): the materials, one per instance (each draw command's
  // baseInstance is its material index), and in textured scenes their texturing.
  void bind_scene_attributes(GLuint vao) const {
    glVertexArrayVertexBuffer(vao, 1, material_buffer, 0, sizeof(Material));
    glVertexArrayBindingDivisor(vao, 1, 1);
    set_attribute(vao, kPositionAttrib, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, position));
    set_attribute(vao, kNormalAttrib, 4, GL_INT_2_10_10_10_REV, GL_TRUE, offsetof(Vertex, normal));
    set_attribute(vao, kColorAttrib, 4, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(Vertex, color));
    set_attribute(vao, kMaterialAttrib, 4, GL_FLOAT, GL_FALSE, 0, 1);  // per instance
    if (placement_buffer) bind_placements(vao, placement_buffer);
    if (!textures) return;
    glVertexArrayVertexBuffer(vao, 2, texturing_buffer, 0, sizeof(MaterialTexturing));
    glVertexArrayBindingDivisor(vao, 2, 1);
    glEnableVertexArrayAttrib(vao, kTexturingAttrib);
    glVertexArrayAttribIFormat(vao, kTexturingAttrib, 3, GL_INT, 0);
    glVertexArrayAttribBinding(vao, kTexturingAttrib, 2);
    set_attribute(vao, kCutoffAttrib, 1, GL_FLOAT, GL_FALSE, offsetof(MaterialTexturing, cutoff),
                  2);
  }

  // Binding 5 of a scene vertex array: placements, one per draw record (PLACED programs).
  static void bind_placements(GLuint vao, GLuint buffer) {
    glVertexArrayVertexBuffer(vao, 5, buffer, 0, sizeof(Placement));
    glVertexArrayBindingDivisor(vao, 5, 1);
    for (GLuint i = 0; i < 3; ++i) {
      set_attribute(vao, kPlacementAttrib + i, 4, GL_FLOAT, GL_FALSE,
                    offsetof(Placement, rows) + i * sizeof(glm::vec4), 5);
      set_attribute(vao, kNormalPlacementAttrib + i, 3, GL_FLOAT, GL_FALSE,
                    offsetof(Placement, normal_rows) + i * sizeof(glm::vec4), 5);
    }
  }

  void draw_scene_batches(const std::vector<SceneBatch>& batches,
                          const std::vector<DrawList::Tint>& tints, bool faded = false) {
    const GLuint plain = faded ? faded_program : program;
    const GLuint textured = faded ? faded_textured_program : textured_scene_program;
    // Untextured single-sided batches outside the transparent pass see only fronts: the
    // one-sided program lights them at the vertices whole (plain, where none is built).
    const GLuint one_sided = faded || culling_off || !one_sided_program ? plain : one_sided_program;
    glUseProgram(plain);
    glm::vec4 current(0.0f);
    glm::vec2 fade(-1.0f);
    for (const SceneBatch& b : batches) {
      glm::vec4 tint(0.0f);
      for (const DrawList::Tint& t : tints)
        if (t.mesh == b.mesh) tint = t.colour;
      if (tint != current) {
        for (GLuint p : {plain, textured, one_sided})
          if (p) glProgramUniform4fv(p, kTintUniform, 1, &tint.x);
        current = tint;
      }
      if (faded && b.fade != fade) {
        for (GLuint p : {plain, textured})
          if (p) glProgramUniform2fv(p, kFadeUniform, 1, &b.fade.x);
        fade = b.fade;
      }
      glBindVertexArray(b.vao);
      const int array = b.drawing.array;
      if (array >= 0) {  // the textured program samples this batch's array on unit 0
        glUseProgram(textured);
        textures->bind(array);
      }
      const bool one = array < 0 && !b.drawing.double_sided && one_sided != plain;
      if (one) glUseProgram(one_sided);
      if (b.drawing.double_sided) glDisable(GL_CULL_FACE);
      glMultiDrawElementsIndirect(
          GL_TRIANGLES, GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(b.first_command * sizeof(DrawCommand)), GLsizei(b.count),
          0);
      if (b.drawing.double_sided && !culling_off) glEnable(GL_CULL_FACE);
      if (array >= 0 || one) glUseProgram(plain);
    }
    if (current != glm::vec4(0.0f)) {
      const glm::vec4 none(0.0f);
      for (GLuint p : {plain, textured, one_sided})
        if (p) glProgramUniform4fv(p, kTintUniform, 1, &none.x);
    }
    glUseProgram(program);
    glBindVertexArray(vao);
  }

  // The commands and batches of DrawList::faded: runs of one coverage drawn as opaque ranges
  // are, each batch carrying its coverage.
  void add_faded_ranges(const std::vector<FadedRange>& faded) {
    faded_batches.clear();
    for (size_t i = 0; i < faded.size();) {
      fade_group.clear();
      size_t e = i;
      for (; e < faded.size() && faded[e].coverage == faded[i].coverage &&
             faded[e].complement == faded[i].complement;
           ++e)
        fade_group.push_back(faded[e].range);
      add_scene_ranges(fade_group, fade_group_batches, true);
      for (SceneBatch& b : fade_group_batches) {
        b.fade = {std::clamp(faded[i].coverage, 0.0f, 1.0f), faded[i].complement ? 1.0f : 0.0f};
        faded_batches.push_back(b);
      }
      i = e;
    }
  }

  void reserve_commands(size_t count) {
    if (count <= indirect_capacity) return;
    indirect_capacity = std::max<size_t>(256, std::bit_ceil(count));
    glDeleteBuffers(1, &indirect_buffer);
    // Per-frame code has no error channel; a few MB of commands failing to fit is fatal.
    const Result<void> made =
        make_buffer(indirect_buffer, "indirect draw commands",
                    indirect_capacity * sizeof(DrawCommand), nullptr, GL_DYNAMIC_STORAGE_BIT);
    FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
  }

  // Splits the list's mesh draws into runs and writes their commands (after the scene's) and
  // gathered indices; uploads the stream.
  void plan_meshes(const DrawList& list) {
    runs.clear();
    stream.clear();
    for (size_t b = 0; b < list.meshes.size();) {
      const MeshDraw& first = list.meshes[b];
      const GpuMesh& mesh = resources.mesh(first.mesh);
      FF_ASSERT(mesh.kind != MeshKind::scene, "mesh %u is a scene mesh: draw it by DrawRange",
                first.mesh.id);
      const bool textured = mesh.kind == MeshKind::textured;
      FF_ASSERT(textured == bool(first.texture), "mesh %u is %s but its draw names texture %u",
                first.mesh.id, textured ? "textured" : "a proxy mesh", first.texture.id);
      if (first.texture) resources.texture(first.texture);  // asserts that it is live
      size_t e = b;
      while (e < list.meshes.size() && list.meshes[e].mesh == first.mesh &&
             list.meshes[e].texture == first.texture) {
        const MeshDraw& d = list.meshes[e];
        FF_ASSERT(d.first_index % 3 == 0 && d.index_count % 3 == 0 &&
                      uint64_t(d.first_index) + d.index_count <= mesh.index_count,
                  "mesh range [%u, +%u) outside mesh %u's %u indices", d.first_index, d.index_count,
                  d.mesh.id, mesh.index_count);
        ++e;
      }
      MeshRun run{b, e, commands.size(), stream.size(), e - b > kMeshRangesPerCall};
      for (size_t i = b; i < e; ++i) {
        const MeshDraw& d = list.meshes[i];
        if (run.gathered)
          stream.insert(stream.end(), mesh.indices.begin() + d.first_index,
                        mesh.indices.begin() + d.first_index + d.index_count);
        else
          commands.push_back({d.index_count, 1, d.first_index, 0, 0});
      }
      runs.push_back(run);
      b = e;
    }
    if (stream.empty()) return;
    if (stream.size() > stream_capacity) {
      stream_capacity = std::bit_ceil(stream.size());
      glDeleteBuffers(1, &stream_buffer);
      const Result<void> made =
          make_buffer(stream_buffer, "mesh index stream", stream_capacity * sizeof(uint32_t),
                      nullptr, GL_DYNAMIC_STORAGE_BIT);
      FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
    }
    glNamedBufferSubData(stream_buffer, 0, GLsizeiptr(stream.size() * sizeof(uint32_t)),
                         stream.data());
  }

  // The planned runs, depth-tested and writing depth like opaque geometry; alpha below one
  // blends. Returns the draw commands issued.
  uint64_t draw_meshes(const glm::mat4& view_projection, const DrawList& list) {
    if (runs.empty()) return 0;
    if (proxy_program == 0) proxy_program = build_proxy_program();
    if (textured_program == 0) textured_program = build_textured_program();
    for (GLuint p : {proxy_program, textured_program})
      glProgramUniformMatrix4fv(p, kViewProjectionUniform, 1, GL_FALSE,
                                glm::value_ptr(view_projection));
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    uint64_t calls = 0;
    for (const MeshRun& run : runs) {
      const MeshDraw& first = list.meshes[run.begin];
      const GpuMesh& mesh = resources.mesh(first.mesh);
      glUseProgram(first.texture ? textured_program : proxy_program);
      if (first.texture) glBindTextureUnit(0, resources.texture(first.texture).texture);
      glBindVertexArray(mesh.vao);
      if (run.gathered) {
        size_t count = 0;
        for (size_t i = run.begin; i < run.end; ++i) count += list.meshes[i].index_count;
        glVertexArrayElementBuffer(mesh.vao, stream_buffer);
        glDrawElements(GL_TRIANGLES, GLsizei(count), GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(run.stream_offset * sizeof(uint32_t)));
        glVertexArrayElementBuffer(mesh.vao, mesh.index_buffer);
        ++calls;
      } else {
        glMultiDrawElementsIndirect(
            GL_TRIANGLES, GL_UNSIGNED_INT,
            reinterpret_cast<const void*>(run.first_command * sizeof(DrawCommand)),
            GLsizei(run.end - run.begin), 0);
        calls += run.end - run.begin;
      }
    }
    glBindVertexArray(vao);
    glUseProgram(program);
    glDisable(GL_BLEND);
    return calls;
  }

  // Binds the target, sets every piece of state the frame depends on (another user of the
  // context, such as an ImGui overlay, may have changed it), clears and starts the timer.
  void begin_frame(const glm::mat4& view_projection, int width, int height, bool clear_first = true) {
    FF_ASSERT(framebuffer == 0 || (width == offscreen_width && height == offscreen_height),
              "view is %dx%d but the offscreen target is %dx%d", width, height, offscreen_width,
              offscreen_height);
    frame_width = width;
    frame_height = height;
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    // Reversed-Z (View::projection_matrix): depth in [0, 1], 1 at the near plane, 0 at infinity.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_MULTISAMPLE);  // pixels must be exactly reproducible between techniques
    glDisable(GL_FRAMEBUFFER_SRGB);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthRangef(0.0f, 1.0f);
    glDepthFunc(GL_GREATER);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDisable(GL_BLEND);

    if (has_timer) glQueryCounter(timer[0], GL_TIMESTAMP);
    const float far_depth = 0.0f;
    const float clear[4] = {kSkyColor[0], kSkyColor[1], kSkyColor[2], clear_alpha};
    if (clear_first) {
      glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, clear);
      glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &far_depth);
    }
    glUseProgram(program);
    glBindVertexArray(vao);
    for (GLuint p : scene_programs())
      if (p)
        glProgramUniformMatrix4fv(p, kViewProjectionUniform, 1, GL_FALSE,
                                  glm::value_ptr(view_projection));
  }

  // Grows a stream buffer (and points `vao`'s binding 0 at it) to hold `count` vertices.
  void reserve_stream(GLuint& buffer, size_t& capacity, GLuint vao_, size_t count, size_t stride,
                      const char* what) {
    if (count <= capacity) return;
    capacity = std::max<size_t>(64, std::bit_ceil(count));
    glDeleteBuffers(1, &buffer);
    const Result<void> made =
        make_buffer(buffer, what, capacity * stride, nullptr, GL_DYNAMIC_STORAGE_BIT);
    FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
    glVertexArrayVertexBuffer(vao_, 0, buffer, 0, GLsizei(stride));
  }

  // The backdrop quads, after the opaque geometry: a blended backdrop that fills only the
  // pixels no geometry covers (every fragment at the far depth 0, tested GEQUAL, not written:
  // early depth rejection skips the texturing of covered pixels), or (in_world) depth-tested,
  // depth-writing and two-sided at their place.
  void draw_backdrop(const glm::mat4& view_projection, const DrawList& list) {
    if (list.backdrop.empty()) return;
    if (quad_program == 0) {
      quad_program = build_quad_program();
      glCreateVertexArrays(1, &quad_vao);
      set_attribute(quad_vao, kPositionAttrib, 3, GL_FLOAT, GL_FALSE,
                    offsetof(QuadVertex, position));
      set_attribute(quad_vao, kTexcoordAttrib, 2, GL_FLOAT, GL_FALSE,
                    offsetof(QuadVertex, texcoord));
    }
    static constexpr glm::vec2 kCornerTexcoords[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    quad_vertices.clear();
    for (const TexturedQuad& q : list.backdrop) {
      FF_ASSERT(resources.texture(q.texture).texture != 0,
                "backdrop quad shows texture %u, which holds no image", q.texture.id);
      for (int c = 0; c < 4; ++c) quad_vertices.push_back({q.corners[c], kCornerTexcoords[c]});
    }
    reserve_stream(quad_buffer, quad_capacity, quad_vao, quad_vertices.size(), sizeof(QuadVertex),
                   "backdrop quads");
    glNamedBufferSubData(quad_buffer, 0, GLsizeiptr(quad_vertices.size() * sizeof(QuadVertex)),
                         quad_vertices.data());
    glUseProgram(quad_program);
    glProgramUniformMatrix4fv(quad_program, kViewProjectionUniform, 1, GL_FALSE,
                              glm::value_ptr(view_projection));
    glBindVertexArray(quad_vao);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    if (list.backdrop_mode == BackdropMode::far) {
      glDepthRangef(0.0f, 0.0f);  // reversed-Z: 0 is infinitely far, where the sky was cleared
      glDepthFunc(GL_GEQUAL);
      glDepthMask(GL_FALSE);
    }
    // A signed difference is added in two passes, its positive part added and its negative
    // part subtracted: an 8-bit target clamps a negative fragment colour to 0 before blending.
    auto pass = [&](size_t i, GLenum equation, float offset, float sign) {
      glBlendEquation(equation);
      glProgramUniform2f(quad_program, kPartUniform, offset, sign);
      glDrawArrays(GL_TRIANGLE_FAN, GLint(4 * i), 4);
    };
    for (size_t i = 0; i < list.backdrop.size(); ++i) {
      const TexturedQuad& q = list.backdrop[i];
      glBindTextureUnit(0, resources.texture(q.texture).texture);
      glProgramUniform1f(quad_program, kOpacityUniform, q.opacity);
      if (q.blend == TexturedQuad::Blend::over) {
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        pass(i, GL_FUNC_ADD, 0.0f, 1.0f);
        continue;
      }
      glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE, GL_ZERO, GL_ONE);
      if (q.blend == TexturedQuad::Blend::add) {
        pass(i, GL_FUNC_ADD, 0.0f, 1.0f);
        continue;
      }
      pass(i, GL_FUNC_ADD, 128.0f / 255.0f, 1.0f);
      pass(i, GL_FUNC_REVERSE_SUBTRACT, 128.0f / 255.0f, -1.0f);
    }
    glBlendEquation(GL_FUNC_ADD);
    glDepthRangef(0.0f, 1.0f);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glEnable(GL_CULL_FACE);
    glBindVertexArray(vao);
    glUseProgram(program);
  }

  // Annotation lines over everything, unlit, through the proxy program.
  void draw_lines(const glm::mat4& view_projection, const DrawList& list) {
    if (list.lines.empty()) return;
    if (proxy_program == 0) proxy_program = build_proxy_program();
    if (line_vao == 0) {
      glCreateVertexArrays(1, &line_vao);
      set_attribute(line_vao, kPositionAttrib, 3, GL_FLOAT, GL_FALSE,
                    offsetof(ProxyVertex, position));
      set_attribute(line_vao, kColorAttrib, 4, GL_UNSIGNED_BYTE, GL_TRUE,
                    offsetof(ProxyVertex, color));
    }
    line_vertices.clear();
    for (const LineSegment& l : list.lines) {
      line_vertices.push_back({l.from, l.color});
      line_vertices.push_back({l.to, l.color});
    }
    reserve_stream(line_buffer, line_capacity, line_vao, line_vertices.size(), sizeof(ProxyVertex),
                   "annotation lines");
    glNamedBufferSubData(line_buffer, 0, GLsizeiptr(line_vertices.size() * sizeof(ProxyVertex)),
                         line_vertices.data());
    glUseProgram(proxy_program);
    glProgramUniformMatrix4fv(proxy_program, kViewProjectionUniform, 1, GL_FALSE,
                              glm::value_ptr(view_projection));
    glBindVertexArray(line_vao);
    glDisable(GL_DEPTH_TEST);
    glDrawArrays(GL_LINES, 0, GLsizei(line_vertices.size()));
    glEnable(GL_DEPTH_TEST);
    glBindVertexArray(vao);
    glUseProgram(program);
  }

  // Reads the timer synchronously: this waits for the GPU, which the benchmark does anyway.
  // On llvmpipe the timestamps see only the rasteriser threads (vertex processing and binning
  // run in the calling thread), so gpu_ms there reads far below the frame's time.
  FrameStats end_frame(FrameStats stats) {
    if (has_timer) {
      glQueryCounter(timer[1], GL_TIMESTAMP);
      GLuint64 start = 0, end = 0;
      glGetQueryObjectui64v(timer[0], GL_QUERY_RESULT, &start);
      glGetQueryObjectui64v(timer[1], GL_QUERY_RESULT, &end);
      stats.gpu_ms = end > start ? double(end - start) * 1e-6 : 0.0;
    }
    return stats;
  }
};

Renderer::Renderer() : state_(std::make_unique<State>()) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create(const Scene& scene, uint64_t chunk_bytes,
                                                   InstanceDrawing instance_drawing) {
  FF_ASSERT(epoxy_gl_version() >= 45, "needs a current OpenGL 4.5 context (version %d)",
            epoxy_gl_version());
  FF_ASSERT(scene.indices.size() <= UINT32_MAX, "%zu indices", scene.indices.size());
  std::unique_ptr<Renderer> renderer(new Renderer());
  State& s = *renderer->state_;  // deletes what was made if a step below fails

  std::vector<Material> materials = scene.materials;
  s.white_material = uint32_t(materials.size());
  materials.push_back(Material{glm::vec4(1.0f)});
  s.index_count = uint32_t(scene.indices.size());
  // Instances drawn instanced: the chunks hold the stored form, the layout maps onto it.
  const bool placed = instance_drawing == InstanceDrawing::placed && !scene.instances.empty() &&
                      !scene.indices.empty();
  Scene stored;
  if (placed) {
    stored = uploaded_form(scene);
    s.layout = InstanceLayout(scene, stored);
  }
  // Draw records past the materials and the white one: per instance its material, white. Made
  // however the scene is uploaded: a scene mesh's range may name an instance (DrawRange).
  if (!scene.instances.empty()) {
    s.placements.assign(materials.size(), identity_placement());
    for (const Instance& instance : scene.instances) {
      const Placement p = placement_of(instance);
      s.instance_materials.push_back(scene.objects[instance.object].material);
      materials.push_back(scene.materials[s.instance_materials.back()]);
      materials.push_back(Material{glm::vec4(1.0f)});
      s.placements.push_back(p);
      s.placements.push_back(p);
    }
    // Room for the records of instanced commands, rewritten each frame (State::frame_*).
    s.frame_records_first = uint32_t(s.placements.size());
    s.frame_records_capacity = uint32_t(std::min<size_t>(2 * scene.instances.size() + 16, 65536));
    s.placements.resize(s.placements.size() + s.frame_records_capacity, identity_placement());
    if (auto made = make_buffer(s.placement_buffer, "placement buffer",
                                s.placements.size() * sizeof(Placement), s.placements.data(),
                                GL_DYNAMIC_STORAGE_BIT);
        !made)
      return made.error();
    s.record_materials = materials;
    materials.resize(s.placements.size(), Material{glm::vec4(1.0f)});
  }
  const Scene& uploaded = placed ? stored : scene;
  // A scene without geometry (its index, the geometry left on disk) gets no buffers: its
  // objects are drawn from scene meshes (streamed through gpu/mesh_pool.hpp).
  if (!uploaded.indices.empty()) {
    auto planned = plan_scene_chunks(uploaded, chunk_bytes);
    if (!planned) return planned.error();
    s.chunk_ranges = std::move(*planned);
  }
  if (auto made = make_buffer(s.material_buffer, "material buffer",
                              materials.size() * sizeof(Material), materials.data(),
                              s.frame_records_capacity ? GL_DYNAMIC_STORAGE_BIT : 0);
      !made)
    return made.error();
  const bool textured = std::any_of(scene.materials.begin(), scene.materials.end(),
                                    [](const Material& m) { return m.textured(); });
  for (uint32_t i = 0; i <= s.white_material; ++i) {
    const Material& m = materials[i];
    s.drawings.push_back({-1, m.double_sided != 0});
    s.see_through.push_back(m.transparent() || m.alpha_mode == AlphaMode::mask);
  }
  if (textured) {
    auto textures = SceneTextures::create(scene);
    if (!textures) return textures.error();
    s.textures = std::make_unique<SceneTextures>(std::move(*textures));
    std::vector<MaterialTexturing> texturing = s.textures->materials();
    texturing.push_back({});  // the white material: untextured
    for (uint32_t material : s.instance_materials) {  // the instances' records
      texturing.push_back(s.textures->materials()[material]);
      texturing.push_back({});
    }
    s.record_texturing = texturing;
    texturing.resize(texturing.size() + s.frame_records_capacity);
    if (auto made = make_buffer(s.texturing_buffer, "material texturing buffer",
                                texturing.size() * sizeof(MaterialTexturing), texturing.data(),
                                s.frame_records_capacity ? GL_DYNAMIC_STORAGE_BIT : 0);
        !made)
      return made.error();
  }
  if (s.textures)
    for (size_t i = 0; i < scene.materials.size(); ++i)
      s.drawings[i].array = s.textures->materials()[i].array;
  s.uniform_drawing = std::all_of(s.drawings.begin(), s.drawings.end(),
                                  [&](const State::Drawing& d) { return d == s.drawings[0]; });
  for (const SceneChunk& range : s.chunk_ranges) {
    State::Chunk& c = s.chunks.emplace_back();
    c.range = range;
    if (auto made = make_buffer(c.vertex_buffer, "vertex buffer",
                                size_t(range.vertex_count) * sizeof(Vertex),
                                uploaded.vertices.data() + range.first_vertex, 0);
        !made)
      return made.error();
    if (auto made = make_buffer(c.index_buffer, "index buffer",
                                size_t(range.index_count) * sizeof(uint32_t),
                                uploaded.indices.data() + range.first_index, 0);
        !made)
      return made.error();
    glCreateVertexArrays(1, &c.vao);
    glVertexArrayVertexBuffer(c.vao, 0, c.vertex_buffer, 0, sizeof(Vertex));
    glVertexArrayElementBuffer(c.vao, c.index_buffer);
    s.bind_scene_attributes(c.vao);
    if (textured)
      if (auto ok = add_texture_coordinates(uploaded, c.vao, range, c.uv_buffer); !ok)
        return ok.error();
    s.geometry_bytes += uint64_t(range.vertex_count) * (sizeof(Vertex) +
                                                        (c.uv_buffer ? sizeof(glm::vec2) : 0)) +
                        uint64_t(range.index_count) * sizeof(uint32_t);
    glCreateVertexArrays(1, &c.indexed_vao);
    glVertexArrayVertexBuffer(c.indexed_vao, 0, c.vertex_buffer, 0, sizeof(Vertex));
    s.bind_scene_attributes(c.indexed_vao);
    if (c.uv_buffer) {
      glVertexArrayVertexBuffer(c.indexed_vao, 3, c.uv_buffer, 0, sizeof(glm::vec2));
      set_attribute(c.indexed_vao, kTexcoordAttrib, 2, GL_FLOAT, GL_FALSE, 0, 3);
    }
  }
  glCreateVertexArrays(1, &s.vao);

  const bool placements = s.placement_buffer != 0;
  s.program = build_scene_program(false, placements);
  s.faded_program = build_scene_program(true, placements);
  s.one_sided_program = build_scene_program(false, placements, true);
  if (textured) {
    s.textured_scene_program = build_textured_scene_program(false, placements);
    s.faded_textured_program = build_textured_scene_program(true, placements);
  }
  const std::array<glm::vec3, 2> lights = light_directions();
  for (GLuint p : s.scene_programs()) {
    if (!p) continue;
    glProgramUniform3fv(p, kLightDirUniform, 2, glm::value_ptr(lights[0]));
    glProgramUniform1f(p, kLightWeightUniform, kLightWeight);
    glProgramUniform1f(p, kAmbientUniform, kAmbient);
  }

  // Timestamps rather than GL_TIME_ELAPSED: Mesa 22's llvmpipe returns the absolute clock
  // for the first GL_TIME_ELAPSED query of a context (a start time never recorded).
  GLint timer_bits = 0;
  glGetQueryiv(GL_TIMESTAMP, GL_QUERY_COUNTER_BITS, &timer_bits);
  s.has_timer = timer_bits > 0;
  if (s.has_timer) glCreateQueries(GL_TIMESTAMP, 2, s.timer);
  return renderer;
}

FrameStats Renderer::draw(const View& view, const DrawList& list) {
  return draw_with(view.view_projection(), view.width, view.height, list);
}

FrameStats Renderer::draw_with(const glm::mat4& view_projection, int width, int height,
                               const DrawList& list) {
  State& s = *state_;
  const auto upload_start = std::chrono::steady_clock::now();
  for (const TextureUpload& u : list.uploads)
    if (u.pixels) {
      s.resources.upload(u);
      u.pixels = nullptr;
      u.owner.reset();
    }
  for (const SceneMeshUpload& u : list.mesh_uploads) {
    // A bounded pool (mesh_pool.hpp) holds what the GPU was sized for: failing here is a bug.
    auto replaced = s.resources.replace_scene_mesh(u.mesh, u.data->vertices, u.data->uvs,
                                                   u.data->indices);
    FF_ASSERT(replaced.ok(), "streamed mesh %u: %s", u.mesh.id,
              replaced.ok() ? "" : replaced.error().message.c_str());
    s.bind_scene_attributes(s.resources.mesh(u.mesh).vao);
  }
  for (const TexturedMeshUpload& u : list.textured_mesh_uploads) {
    auto replaced =
        s.resources.replace_textured_mesh(u.mesh, u.data->vertices, u.data->indices);
    FF_ASSERT(replaced.ok(), "streamed textured mesh %u: %s", u.mesh.id,
              replaced.ok() ? "" : replaced.error().message.c_str());
  }
  const double upload_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - upload_start)
          .count();
  s.commands.clear();
  s.add_scene_ranges(list.opaque, s.opaque_batches, true);
  s.add_scene_ranges(list.transparent, s.transparent_batches, false);
  s.place_scene_indices(list);
  s.add_indexed_runs(list, list.indexed_opaque, s.opaque_batches, true);
  s.add_indexed_runs(list, list.indexed_transparent, s.transparent_batches, false);
  s.add_faded_ranges(list.faded);
  s.upload_frame_records();
  s.upload_scene_indices(list);
  const size_t scene_commands = s.commands.size();
  s.plan_meshes(list);  // its commands follow the scene's
  s.reserve_commands(s.commands.size());
  if (!s.commands.empty())
    glNamedBufferSubData(s.indirect_buffer, 0, GLsizeiptr(s.commands.size() * sizeof(DrawCommand)),
                         s.commands.data());

  s.begin_frame(view_projection, width, height, !list.draw_over);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, s.indirect_buffer);
  s.draw_scene_batches(s.opaque_batches, list.tints);
  if (!s.faded_batches.empty()) s.draw_scene_batches(s.faded_batches, list.tints, true);
  uint64_t calls = scene_commands + s.draw_meshes(view_projection, list);
  // The backdrop behind everything opaque, under the transparent surfaces.
  s.draw_backdrop(view_projection, list);
  calls += list.backdrop.size();
  if (!s.transparent_batches.empty()) {
    // Semi-transparent surfaces after the opaque ones, in the list's order, both sides,
    // tested against but not writing depth.
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    s.culling_off = true;
    s.draw_scene_batches(s.transparent_batches, list.tints);
    s.culling_off = false;
    glDepthMask(GL_TRUE);
    glEnable(GL_CULL_FACE);
    glDisable(GL_BLEND);
  }
  s.draw_lines(view_projection, list);
  return s.end_frame({0.0, list.triangle_count(), calls, upload_ms});
}

std::vector<uint32_t> Renderer::visible_triangles(const View& view, const DrawList& list,
                                                  const glm::ivec2* pixel) {
  State& s = *state_;
  if (s.visibility_depth_program == 0) {
    s.visibility_depth_program = build_visibility_depth_program(s.placed());
    s.visibility_mark_program = build_visibility_mark_program(s.placed());
  }
  // Commands by kind: opaque one-sided, opaque two-sided, see-through; each command's
  // baseInstance is its own number, which reads its first triangle (of the scene as held)
  // and, in a placed scene, its placement.
  struct Command {
    DrawCommand command;
    size_t chunk;
    uint32_t held_first;  // index
    uint32_t record;
  };
  std::vector<Command> kinds[3];
  std::vector<uint32_t> firsts;
  // Indexed runs as ranges of one triangle each, by the triangles' numbers.
  std::vector<DrawRange> singles;
  for (const auto* runs : {&list.indexed_opaque, &list.indexed_transparent})
    for (const DrawRange& r : *runs)
      for (uint32_t k = r.first_index / 3; k < (r.first_index + r.index_count) / 3; ++k) {
        FF_ASSERT(k < list.scene_triangles.size(), "indexed run past the list's triangle numbers");
        singles.push_back({3 * list.scene_triangles[k], 3, r.material, {}});
      }
  const std::vector<DrawRange>* all_ranges[] = {&list.opaque, &list.transparent, &singles};
  for (const auto* ranges : all_ranges)
    for (const DrawRange& r : *ranges) {
      if (r.mesh) continue;
      FF_ASSERT(r.first_index % 3 == 0 && r.index_count % 3 == 0 &&
                    uint64_t(r.first_index) + r.index_count <= s.index_count &&
                    r.material < s.white_material,
                "range [%u, +%u) material %u outside the scene", r.first_index, r.index_count,
                r.material);
      const int kind = s.see_through[r.material] ? 2 : s.drawings[r.material].double_sided ? 1 : 0;
      s.for_each_piece(r.first_index, r.index_count, r.material, false,
                       [&](const State::Piece& p) {
                         const SceneChunk& chunk = s.chunk_ranges[p.chunk];
                         kinds[kind].push_back({{p.count, 1, p.uploaded_at - chunk.first_index,
                                                 -GLint(chunk.first_vertex), 0},
                                                p.chunk, p.held_at, p.record});
                       });
    }
  std::vector<DrawCommand> commands;
  std::vector<Placement> placements;  // per command, placed scenes only
  for (auto& k : kinds)
    for (Command& c : k) {
      c.command.base_instance = GLuint(commands.size());
      commands.push_back(c.command);
      firsts.push_back(c.held_first / 3);
      if (s.placed()) placements.push_back(s.placements[c.record]);
    }
  const size_t words = (size_t(s.index_count / 3) + 31) / 32;
  std::vector<uint32_t> visible;
  if (commands.empty()) return visible;
  s.reserve_commands(commands.size());
  glNamedBufferSubData(s.indirect_buffer, 0, GLsizeiptr(commands.size() * sizeof(DrawCommand)),
                       commands.data());
  if (firsts.size() > s.first_triangle_capacity) {
    s.first_triangle_capacity = std::bit_ceil(firsts.size());
    glDeleteBuffers(1, &s.first_triangle_buffer);
    const Result<void> made =
        make_buffer(s.first_triangle_buffer, "first triangles",
                    s.first_triangle_capacity * sizeof(uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
    FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
  }
  glNamedBufferSubData(s.first_triangle_buffer, 0, GLsizeiptr(firsts.size() * sizeof(uint32_t)),
                       firsts.data());
  if (words != s.occupancy_words) {
    s.occupancy_words = words;
    glDeleteBuffers(1, &s.occupancy_buffer);
    const Result<void> made = make_buffer(s.occupancy_buffer, "occupancy bits",
                                          std::max<size_t>(words, 1) * sizeof(uint32_t), nullptr,
                                          GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
  }
  const GLuint zero = 0;
  glClearNamedBufferData(s.occupancy_buffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  if (s.placed()) {
    if (placements.size() > s.command_placement_capacity) {
      s.command_placement_capacity = std::bit_ceil(placements.size());
      glDeleteBuffers(1, &s.command_placement_buffer);
      const Result<void> made = make_buffer(s.command_placement_buffer, "command placements",
                                            s.command_placement_capacity * sizeof(Placement),
                                            nullptr, GL_DYNAMIC_STORAGE_BIT);
      FF_ASSERT(made.ok(), "%s", made.error().message.c_str());
    }
    glNamedBufferSubData(s.command_placement_buffer, 0,
                         GLsizeiptr(placements.size() * sizeof(Placement)), placements.data());
  }
  for (const State::Chunk& c : s.chunks) {
    if (s.placed()) State::bind_placements(c.vao, s.command_placement_buffer);
    glVertexArrayVertexBuffer(c.vao, 4, s.first_triangle_buffer, 0, sizeof(uint32_t));
    glVertexArrayBindingDivisor(c.vao, 4, 1);
    glEnableVertexArrayAttrib(c.vao, kFirstTriangleAttrib);
    glVertexArrayAttribIFormat(c.vao, kFirstTriangleAttrib, 1, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(c.vao, kFirstTriangleAttrib, 4);
  }

  const glm::mat4 view_projection = view.view_projection();
  s.begin_frame(view_projection, view.width, view.height);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  if (pixel) {  // rows counted from the top, GL's from the bottom
    glEnable(GL_SCISSOR_TEST);
    glScissor(pixel->x, view.height - 1 - pixel->y, 1, 1);
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, s.indirect_buffer);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s.occupancy_buffer);
  // Draws the commands of kinds [from, to), runs of one vertex array a multi-draw each.
  auto draw = [&](int from, int to) {
    size_t first = 0;
    for (int k = 0; k < from; ++k) first += kinds[k].size();
    for (int k = from; k < to; ++k) {
      if (k == 1) glDisable(GL_CULL_FACE);
      for (size_t b = 0; b < kinds[k].size();) {
        size_t e = b;
        while (e < kinds[k].size() && kinds[k][e].chunk == kinds[k][b].chunk) ++e;
        glBindVertexArray(s.chunks[kinds[k][b].chunk].vao);
        glMultiDrawElementsIndirect(
            GL_TRIANGLES, GL_UNSIGNED_INT,
            reinterpret_cast<const void*>((first + b) * sizeof(DrawCommand)), GLsizei(e - b), 0);
        b = e;
      }
      first += kinds[k].size();
      glEnable(GL_CULL_FACE);
    }
  };
  for (GLuint p : {s.visibility_depth_program, s.visibility_mark_program})
    glProgramUniformMatrix4fv(p, kViewProjectionUniform, 1, GL_FALSE,
                              glm::value_ptr(view_projection));
  // The nearest opaque depth, then the opaque fragments at it and the see-through ones in
  // front of it.
  glUseProgram(s.visibility_depth_program);
  draw(0, 2);
  glUseProgram(s.visibility_mark_program);
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_EQUAL);
  draw(0, 2);
  glDepthFunc(GL_GREATER);
  glDisable(GL_CULL_FACE);  // the colour pass draws see-through surfaces two-sided
  draw(2, 3);
  glEnable(GL_CULL_FACE);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  // The other programs read no first triangle: the arrays fetch it only for this pass.
  for (const State::Chunk& c : s.chunks) {
    glDisableVertexArrayAttrib(c.vao, kFirstTriangleAttrib);
    if (s.placed()) State::bind_placements(c.vao, s.placement_buffer);
  }
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_SCISSOR_TEST);
  glBindVertexArray(s.vao);
  glUseProgram(s.program);
  std::vector<uint32_t> bits(words);
  glGetNamedBufferSubData(s.occupancy_buffer, 0, GLsizeiptr(words * sizeof(uint32_t)), bits.data());
  for (size_t w = 0; w < words; ++w)
    for (uint32_t word = bits[w]; word != 0; word &= word - 1)
      visible.push_back(uint32_t(w * 32 + size_t(std::countr_zero(word))));
  return visible;
}

std::optional<uint32_t> Renderer::pick(const Scene& scene, const View& view, const DrawList& list,
                                       int x, int y) {
  FF_ASSERT(x >= 0 && y >= 0 && x < view.width && y < view.height, "pixel %d, %d outside %d x %d",
            x, y, view.width, view.height);
  const glm::ivec2 pixel(x, y);
  const std::vector<uint32_t> there = visible_triangles(view, list, &pixel);
  // The ray through the pixel's centre, in the view's frame.
  const glm::mat4 inverse = glm::inverse(view.view_projection());
  const glm::vec2 ndc((float(x) + 0.5f) / float(view.width) * 2.0f - 1.0f,
                      1.0f - (float(y) + 0.5f) / float(view.height) * 2.0f);
  const glm::vec4 near = inverse * glm::vec4(ndc, 1.0f, 1.0f);  // reversed Z: 1 is near
  const glm::vec4 far = inverse * glm::vec4(ndc, 0.5f, 1.0f);
  const glm::vec3 origin = glm::vec3(near) / near.w;
  const glm::vec3 direction = glm::normalize(glm::vec3(far) / far.w - origin);
  std::optional<uint32_t> best;
  float nearest = INFINITY;
  for (uint32_t t : there) {
    FF_ASSERT(3 * size_t(t) + 2 < scene.indices.size(), "triangle %u outside the scene", t);
    const glm::vec3 a = scene.vertices[scene.indices[3 * size_t(t)]].position,
                    b = scene.vertices[scene.indices[3 * size_t(t) + 1]].position,
                    c = scene.vertices[scene.indices[3 * size_t(t) + 2]].position;
    // Distance along the ray to the triangle's plane (the pixel's centre lies in the
    // triangle: the rasteriser covered it).
    const glm::vec3 n = glm::cross(b - a, c - a);
    const float along = glm::dot(n, direction);
    if (along == 0.0f) continue;
    const float d = glm::dot(n, a - origin) / along;
    if (d >= 0.0f && d < nearest) {
      nearest = d;
      best = t;
    }
  }
  if (!best && !there.empty()) best = there.front();
  return best;
}

void Renderer::set_light(float heading_deg, float elevation_deg) {
  const std::array<glm::vec3, 2> lights = light_directions(heading_deg, elevation_deg);
  for (GLuint p : state_->scene_programs())
    if (p) glProgramUniform3fv(p, kLightDirUniform, 2, glm::value_ptr(lights[0]));
}

Result<MeshHandle> Renderer::create_mesh(std::span<const ProxyVertex> vertices,
                                         std::span<const uint32_t> indices) {
  return state_->resources.add_mesh(vertices.data(), vertices.size(), false, indices);
}

Result<MeshHandle> Renderer::create_textured_mesh(std::span<const TexturedVertex> vertices,
                                                  std::span<const uint32_t> indices) {
  return state_->resources.add_mesh(vertices.data(), vertices.size(), true, indices);
}

Result<MeshHandle> Renderer::create_scene_mesh(std::span<const Vertex> vertices,
                                               std::span<const glm::vec2> uvs,
                                               std::span<const uint32_t> indices) {
  auto made = state_->resources.add_scene_mesh(vertices, uvs, indices);
  if (made) state_->bind_scene_attributes(state_->resources.mesh(*made).vao);
  return made;
}

TextureHandle Renderer::create_texture() {
  return state_->resources.add_texture();
}
void Renderer::free(MeshHandle mesh) {
  state_->resources.free(mesh);
}
void Renderer::free(TextureHandle texture) {
  state_->resources.free(texture);
}
uint64_t Renderer::resource_bytes() const {
  return state_->resources.bytes();
}

uint64_t Renderer::scene_geometry_bytes() const {
  return state_->geometry_bytes;
}

bool Renderer::draws_instanced() const {
  return state_->placed();
}

void Renderer::finish() {
  glFinish();
}

FrameStats Renderer::draw_everything_at_once(const View& view) {
  State& s = *state_;
  if (s.placed()) {
    // The prototypes' geometry once and every instance's again, a multi-draw a chunk.
    s.commands.clear();
    std::vector<size_t> chunk_of_command;
    s.for_each_piece(0, s.index_count, 0, true, [&](const State::Piece& p) {
      const SceneChunk& chunk = s.chunk_ranges[p.chunk];
      s.commands.push_back(
          {p.count, 1, p.uploaded_at - chunk.first_index, -GLint(chunk.first_vertex), p.record});
      chunk_of_command.push_back(p.chunk);
    });
    std::vector<size_t> order(s.commands.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return chunk_of_command[a] < chunk_of_command[b]; });
    std::vector<DrawCommand> sorted;
    for (size_t i : order) sorted.push_back(s.commands[i]);
    s.reserve_commands(sorted.size());
    if (!sorted.empty())
      glNamedBufferSubData(s.indirect_buffer, 0, GLsizeiptr(sorted.size() * sizeof(DrawCommand)),
                           sorted.data());
    s.begin_frame(view.view_projection(), view.width, view.height);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, s.indirect_buffer);
    uint64_t calls = 0;
    for (size_t b = 0; b < order.size();) {
      size_t e = b;
      while (e < order.size() && chunk_of_command[order[e]] == chunk_of_command[order[b]]) ++e;
      glBindVertexArray(s.chunks[chunk_of_command[order[b]]].vao);
      glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                                  reinterpret_cast<const void*>(b * sizeof(DrawCommand)),
                                  GLsizei(e - b), 0);
      ++calls;
      b = e;
    }
    glBindVertexArray(s.vao);
    return s.end_frame({0.0, s.index_count / 3, std::max<uint64_t>(1, calls)});
  }
  s.begin_frame(view.view_projection(), view.width, view.height);
  for (const State::Chunk& c : s.chunks) {
    glBindVertexArray(c.vao);
    glDrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, GLsizei(c.range.index_count),
                                                  GL_UNSIGNED_INT, nullptr, 1,
                                                  -GLint(c.range.first_vertex), s.white_material);
  }
  glBindVertexArray(s.vao);
  uint64_t triangles = 0;
  for (const State::Chunk& c : s.chunks) triangles += c.range.index_count / 3;
  return s.end_frame({0.0, triangles, std::max<uint64_t>(1, s.chunks.size())});
}

void Renderer::set_offscreen(int width, int height) {
  State& s = *state_;
  if (width == s.offscreen_width && height == s.offscreen_height) return;
  glDeleteFramebuffers(1, &s.framebuffer);
  const GLuint targets[] = {s.color_target, s.depth_target};
  glDeleteRenderbuffers(2, targets);
  s.framebuffer = s.color_target = s.depth_target = 0;
  s.offscreen_width = s.offscreen_height = 0;
  if (width == 0 && height == 0) return;

  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  FF_ASSERT(width > 0 && height > 0 && width <= max_size && height <= max_size,
            "offscreen target %dx%d (limit %d)", width, height, max_size);
  glCreateRenderbuffers(1, &s.color_target);
  glNamedRenderbufferStorage(s.color_target, GL_RGBA8, width, height);
  glCreateRenderbuffers(1, &s.depth_target);
  glNamedRenderbufferStorage(s.depth_target, GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &s.framebuffer);
  glNamedFramebufferRenderbuffer(s.framebuffer, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                 s.color_target);
  glNamedFramebufferRenderbuffer(s.framebuffer, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                 s.depth_target);
  const GLenum status = glCheckNamedFramebufferStatus(s.framebuffer, GL_FRAMEBUFFER);
  FF_ASSERT(status == GL_FRAMEBUFFER_COMPLETE, "offscreen target %dx%d incomplete (0x%x)", width,
            height, status);
  s.offscreen_width = width;
  s.offscreen_height = height;
}

void Renderer::set_texture_filter(TextureFilter filter) {
  if (state_->textures) state_->textures->set_nearest(filter == TextureFilter::nearest);
}

uint64_t Renderer::scene_texture_bytes() const {
  return state_->textures ? state_->textures->bytes() : 0;
}

void Renderer::set_clear_alpha(float alpha) {
  state_->clear_alpha = alpha;
}

namespace {

// The last frame's pixels in one format (glFinish first), rows from the top: `channels`
// values of T a pixel.
template <class T>
std::vector<T> read_frame(GLuint framebuffer, int width, int height, GLenum format, GLenum type,
                          int channels) {
  FF_ASSERT(width > 0 && height > 0, "a capture before any frame was drawn");
  glFinish();
  std::vector<T> pixels(size_t(width) * size_t(height) * size_t(channels));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, format, type, pixels.data());
  // GL rows start at the bottom.
  const ptrdiff_t row = ptrdiff_t(width) * channels;
  for (int y = 0; y < height / 2; ++y)
    std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row,
                     pixels.begin() + (height - 1 - y) * row);
  return pixels;
}

}  // namespace

std::vector<uint8_t> Renderer::capture_alpha() {
  const State& s = *state_;
  return read_frame<uint8_t>(s.framebuffer, s.frame_width, s.frame_height, GL_ALPHA,
                             GL_UNSIGNED_BYTE, 1);
}

std::vector<float> Renderer::capture_depth() {
  const State& s = *state_;
  return read_frame<float>(s.framebuffer, s.frame_width, s.frame_height, GL_DEPTH_COMPONENT,
                           GL_FLOAT, 1);
}

Image Renderer::capture() {
  const State& s = *state_;
  Image image;
  image.width = s.frame_width;
  image.height = s.frame_height;
  image.rgb = read_frame<uint8_t>(s.framebuffer, s.frame_width, s.frame_height, GL_RGB,
                                  GL_UNSIGNED_BYTE, 3);
  return image;
}

}  // namespace farfield::gpu
