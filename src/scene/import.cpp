#include "farfield/scene/import.hpp"

#include "farfield/scene/instances.hpp"

#include <assimp/GltfMaterial.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "farfield/core/assert.hpp"
#include "farfield/core/file_reading.hpp"
#include "farfield/core/text.hpp"
#include "farfield/scene/texture_image.hpp"

// assimp logs nothing unless someone calls Assimp::DefaultLogger::create (its default logger
// is a NullLogger), so nothing here touches the logger.
//
// Some assimp readers hang, abort on an internal assertion or allocate without bound when a
// file is cut short or declares more elements than it holds (assimp 5.2: a PLY whose header
// is cut hangs, a PLY cut inside the body is read as garbage or aborts in Triangulate, an
// OFF that declares 10^11 vertices allocates them). check_structure() refuses such files
// before assimp sees them, for the formats where the header lets us tell.

namespace farfield {
namespace {

namespace fs = std::filesystem;

// Triangles only, without degenerate ones (zero-area by coincident corners; tiny ones stay);
// normals where the file has none, smoothed up to 80 degrees so that the hard edges of
// buildings and CAD parts stay hard; ValidateDataStructure first, so that later steps never see
// out-of-range indices.
constexpr unsigned kImportFlags = aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                  aiProcess_FindDegenerates | aiProcess_SortByPType |
                                  aiProcess_GenSmoothNormals | aiProcess_JoinIdenticalVertices;
constexpr float kSmoothingAngleDeg = 80.0f;

// A whole file mapped read-only into memory: pages are read on demand and shared with the page
// cache, so checking a multi-gigabyte scan costs no copy of it.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    struct stat st {};
    if (fd >= 0 && ::fstat(fd, &st) == 0 && st.st_size > 0) {
      void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (p != MAP_FAILED) {
        data_ = static_cast<const char*>(p);
        size_ = size_t(st.st_size);
      }
    }
    if (!data_) error_ = std::strerror(errno);
    if (fd >= 0) ::close(fd);
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  bool ok() const { return data_ != nullptr; }
  const std::string& error() const { return error_; }  // when not ok
  std::string_view view() const { return {data_, size_}; }

 private:
  const char* data_ = nullptr;
  size_t size_ = 0;
  std::string error_;
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

// Splits `text` at whitespace, one token per call.
class Tokens {
 public:
  explicit Tokens(std::string_view text) : text_(text) {}
  std::optional<std::string_view> next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
    if (pos_ == text_.size()) return std::nullopt;
    const size_t begin = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(begin, pos_ - begin);
  }
  size_t position() const { return pos_; }  // just past the last token

 private:
  std::string_view text_;
  size_t pos_ = 0;
};

bool iequals(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) ==
           std::tolower(static_cast<unsigned char>(y));
  });
}

// Parses an unsigned integer; values past 2^64 read as UINT64_MAX (a count that big is a lie
// the caller reports, not a reason to skip the check).
std::optional<uint64_t> parse_count(std::string_view s) {
  uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (end != s.data() + s.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return UINT64_MAX;
  if (ec != std::errc()) return std::nullopt;
  return v;
}

// ---- PLY: header and body walked as assimp would, without building anything --------------

struct PlyProperty {
  int size = 0;        // bytes of a scalar, or of one list item
  int count_size = 0;  // bytes of a list's count; 0 for a scalar
  bool count_signed = false;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyKind { unknown, signed_int, unsigned_int, real };

// Size in bytes and kind of a PLY scalar type; size 0 when unknown.
std::pair<int, PlyKind> ply_type(std::string_view t) {
  using enum PlyKind;
  // clang-format off
  static constexpr std::tuple<std::string_view, int, PlyKind> kTypes[] = {
      {"char", 1, signed_int},     {"int8", 1, signed_int},     {"uchar", 1, unsigned_int},
      {"uint8", 1, unsigned_int},  {"short", 2, signed_int},    {"int16", 2, signed_int},
      {"ushort", 2, unsigned_int}, {"uint16", 2, unsigned_int}, {"int", 4, signed_int},
      {"int32", 4, signed_int},    {"uint", 4, unsigned_int},   {"uint32", 4, unsigned_int},
      {"float", 4, real},          {"float32", 4, real},        {"double", 8, real},
      {"float64", 8, real}};
  // clang-format on
  for (const auto& [name, size, kind] : kTypes)
    if (name == t) return {size, kind};
  return {0, unknown};
}

// Error message of a PLY whose data ends before the header's counts are met.
Error ply_truncated(const std::string& path, const PlyElement& e, uint64_t done) {
  return make_error(path, ": truncated PLY: the header declares ", std::to_string(e.count), " '",
                    e.name, "' items but the file ends after ", std::to_string(done), " of them");
}

Result<void> check_ply_ascii(const std::string& path, std::string_view body,
                             const std::vector<PlyElement>& elements) {
  Tokens tokens(body);
  for (const PlyElement& e : elements) {
    for (uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        const auto token = tokens.next();
        if (!token) return ply_truncated(path, e, i);
        if (p.count_size == 0) continue;
        const auto n = parse_count(*token);
        if (!n)
          return make_error(path, ": not a readable model (PLY list length '", std::string(*token),
                            "' in element '", e.name, "')");
        for (uint64_t k = 0; k < *n; ++k)
          if (!tokens.next()) return ply_truncated(path, e, i);
      }
    }
  }
  return {};
}

Result<void> check_ply_binary(const std::string& path, std::string_view body,
                              const std::vector<PlyElement>& elements, bool big_endian) {
  uint64_t pos = 0;
  const uint64_t end = body.size();
  auto read_uint = [&](int size) {
    uint64_t v = 0;
    for (int b = 0; b < size; ++b) {
      const uint64_t byte = static_cast<unsigned char>(body[pos + b]);
      v |= byte << (8 * (big_endian ? size - 1 - b : b));
    }
    return v;
  };
  for (const PlyElement& e : elements) {
    const bool fixed = std::none_of(e.properties.begin(), e.properties.end(),
                                    [](const PlyProperty& p) { return p.count_size != 0; });
    if (fixed) {  // one multiplication instead of a walk
      uint64_t stride = 0;
      for (const PlyProperty& p : e.properties) stride += p.size;
      if (stride != 0 && e.count > (end - pos) / stride)
        return ply_truncated(path, e, (end - pos) / stride);
      pos += stride * e.count;
      continue;
    }
    for (uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        if (end - pos < uint64_t(p.count_size ? p.count_size : p.size))
          return ply_truncated(path, e, i);
        if (p.count_size == 0) {
          pos += p.size;
          continue;
        }
        uint64_t n = read_uint(p.count_size);
        if (p.count_signed && (n >> (8 * p.count_size - 1)) != 0)
          return make_error(path, ": not a readable model (negative PLY list length in element '",
                            e.name, "')");
        pos += p.count_size;
        if (n > (end - pos) / p.size) return ply_truncated(path, e, i);
        pos += n * p.size;
      }
    }
  }
  return {};
}

Result<void> check_ply(const std::string& path, std::string_view data) {
  auto bad_header = [&](std::string_view what) {
    return make_error(path, ": not a readable model (PLY header: ", std::string(what), ")");
  };
  std::vector<PlyElement> elements;
  std::string_view format;
  size_t pos = 0;
  bool header_done = false;
  for (bool first = true; pos < data.size() && !header_done; first = false) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string_view::npos) break;  // the header never ends
    Tokens line(data.substr(pos, eol - pos));
    pos = eol + 1;
    const auto keyword = line.next();
    if (first || !keyword) continue;
    if (*keyword == "end_header") {
      header_done = true;
    } else if (*keyword == "format") {
      format = line.next().value_or("");
    } else if (*keyword == "element") {
      const auto name = line.next();
      const auto count = parse_count(line.next().value_or(""));
      if (!name || !count) return bad_header("element line without a name and a count");
      elements.push_back({std::string(*name), *count, {}});
    } else if (*keyword == "property") {
      if (elements.empty()) return bad_header("property before any element");
      PlyProperty p;
      std::string_view type = line.next().value_or("");
      if (type == "list") {
        const auto [count_size, count_kind] = ply_type(line.next().value_or(""));
        if (count_kind != PlyKind::signed_int && count_kind != PlyKind::unsigned_int)
          return bad_header("a list count type that is not an integer");
        p.count_size = count_size;
        p.count_signed = count_kind == PlyKind::signed_int;
        type = line.next().value_or("");
      }
      p.size = ply_type(type).first;
      if (p.size == 0) return bad_header("unknown property type '" + std::string(type) + "'");
      elements.back().properties.push_back(p);
    }  // other lines are skipped, as assimp does (Blender wrote a bare "Created by ..." line)
  }
  if (!header_done) return make_error(path, ": truncated PLY: the header has no end_header line");

  const bool has_faces = std::any_of(elements.begin(), elements.end(), [](const PlyElement& e) {
    return (iequals(e.name, "face") || iequals(e.name, "tristrips")) && e.count > 0;
  });
  if (!has_faces) return make_error(path, ": contains no triangles");

  const std::string_view body = data.substr(pos);
  if (format == "ascii") return check_ply_ascii(path, body, elements);
  if (format == "binary_little_endian" || format == "binary_big_endian")
    return check_ply_binary(path, body, elements, format == "binary_big_endian");
  return bad_header("unknown format '" + std::string(format) + "'");
}

// ---- other formats: the counts in the header, or the line a complete file ends with --------

// OFF: "[ST][C][N][4][n]OFF [dim] nv nf [ne]", then one line per vertex and one per face
// ("k i1 .. ik"), as assimp reads it. A cut file has fewer lines, or a last face short of indices.
Result<void> check_off(const std::string& path, std::string_view data, std::string_view magic) {
  Tokens tokens(data);
  tokens.next();
  if (magic.find('n') != std::string_view::npos) tokens.next();         // the dimension
  const auto vertex_token = tokens.next(), face_token = tokens.next();  // the edge count may follow
  if (!face_token)
    return make_error(path, ": truncated OFF: the header has no vertex and face counts");
  const auto vertices = parse_count(*vertex_token), faces = parse_count(*face_token);
  if (!vertices || !faces) return {};  // let assimp say what is wrong
  const uint64_t needed = *vertices > UINT64_MAX - *faces ? UINT64_MAX : *vertices + *faces;

  uint64_t lines = 0;
  std::string_view last_face;
  for (size_t pos = data.find('\n', tokens.position()); pos < data.size() && lines < needed;) {
    const size_t eol = std::min(data.find('\n', pos + 1), data.size());
    const std::string_view line = data.substr(pos + 1, eol - pos - 1);
    pos = eol;
    if (!Tokens(line).next()) continue;  // blank
    if (++lines == needed) last_face = line;
  }
  auto truncated = [&] {
    return make_error(path, ": truncated OFF: the header declares ", std::to_string(*vertices),
                      " vertices and ", std::to_string(*faces), " faces but the file ends after ",
                      std::to_string(lines), " of those lines");
  };
  if (lines < needed) return truncated();
  if (*faces == 0) return {};
  Tokens face(last_face);
  const auto corners = parse_count(face.next().value_or(""));
  for (uint64_t k = 0; corners && k < *corners; ++k)
    if (!face.next()) return truncated();
  return {};
}

// The last non-blank line of `text`, without surrounding whitespace.
std::string_view last_line(std::string_view text) {
  const size_t end = text.find_last_not_of(std::string_view(" \t\r\n\f\v\0", 7));
  if (end == std::string_view::npos) return {};
  text = text.substr(0, end + 1);
  const size_t nl = text.find_last_of('\n');
  text = nl == std::string_view::npos ? text : text.substr(nl + 1);
  return text.substr(std::min(text.find_first_not_of(" \t\r\f\v"), text.size()));
}

// Whether `text` begins with `word`, compared without case.
bool starts_with(std::string_view text, std::string_view word) {
  return text.size() >= word.size() && iequals(text.substr(0, word.size()), word);
}

bool is_off_magic(std::string_view magic) {
  return magic.size() >= 3 && magic.substr(magic.size() - 3) == "OFF" &&
         magic.find_first_not_of("STCN4nOF") == std::string_view::npos;
}

Result<void> check_structure(const std::string& path, std::string_view data) {
  const std::string_view magic = Tokens(data.substr(0, 64)).next().value_or("");
  const std::string_view tail = data.substr(data.size() - std::min<size_t>(data.size(), 1024));

  if (iequals(magic, "ply")) return check_ply(path, data);
  if (is_off_magic(magic)) return check_off(path, data, magic);
  if (magic == "ISO-10303-21;" && !starts_with(last_line(tail), "END-ISO-10303-21;"))
    return make_error(path, ": truncated STEP/IFC file: it does not end with END-ISO-10303-21;");
  // ASCII STL, unless the size is that of a binary STL (whose header may also say "solid").
  if (iequals(magic, "solid")) {
    uint64_t triangles = 0;  // a binary STL's count: little-endian, at bytes 80..83
    if (data.size() >= 84)
      for (int b = 83; b >= 80; --b) triangles = triangles << 8 | uint8_t(data[b]);
    const bool binary = data.size() >= 84 && data.size() == 84 + 50 * triangles;
    if (!binary && !starts_with(last_line(tail), "endsolid"))
      return make_error(path, ": truncated STL: the ASCII file does not end with endsolid");
  }
  return {};
}

// ---- from aiScene to Scene ------------------------------------------------------------

glm::dmat4 to_glm(const aiMatrix4x4& m) {
  glm::dmat4 g;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) g[c][r] = m[r][c];  // assimp is row-major, glm column-major
  return g;
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

glm::vec4 sanitize(glm::vec4 c) {
  for (int i = 0; i < 4; ++i) c[i] = std::isfinite(c[i]) ? std::clamp(c[i], 0.0f, 1.0f) : 1.0f;
  return c;
}

Material material_of(const aiMaterial& m) {
  aiColor4D c(1.0f, 1.0f, 1.0f, 1.0f);
  if (m.Get(AI_MATKEY_BASE_COLOR, c) != AI_SUCCESS) m.Get(AI_MATKEY_COLOR_DIFFUSE, c);
  float opacity = 1.0f;
  if (m.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) c.a = opacity;
  Material out;
  aiString alpha_mode;
  if (m.Get(AI_MATKEY_GLTF_ALPHAMODE, alpha_mode) == AI_SUCCESS) {
    const std::string_view mode = alpha_mode.C_Str();
    if (mode == "OPAQUE") c.a = 1.0f;  // glTF: alpha is ignored in opaque mode
    if (mode == "MASK") out.alpha_mode = AlphaMode::mask;
    if (mode == "BLEND") out.alpha_mode = AlphaMode::blend;
    float cutoff = 0.5f;
    if (m.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS && std::isfinite(cutoff))
      out.alpha_cutoff = std::clamp(cutoff, 0.0f, 1.0f);
  }
  out.base_color = sanitize(glm::vec4(c.r, c.g, c.b, c.a));
  int two_sided = 0;  // glTF doubleSided, and the flag of the formats that have one
  if (m.Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS && two_sided) out.double_sided = 1;
  return out;
}

// The material's base-colour texture slot: glTF's base colour, else the diffuse map.
std::optional<std::pair<aiTextureType, aiString>> base_colour_texture(const aiMaterial& m) {
  for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
    aiString path;
    if (m.GetTextureCount(type) > 0 && m.GetTexture(type, 0, &path) == AI_SUCCESS &&
        path.length > 0)
      return std::pair(type, path);
  }
  return std::nullopt;
}

TextureWrap wrap_of(int mode) {
  switch (mode) {
    case aiTextureMapMode_Clamp:
    case aiTextureMapMode_Decal:
      return TextureWrap::clamp;
    case aiTextureMapMode_Mirror:
      return TextureWrap::mirror;
    default:
      return TextureWrap::repeat;
  }
}

// A texture path as written in a model: Windows separators and %XX escapes undone.
std::string file_path_of(std::string_view written) {
  std::string out;
  for (size_t i = 0; i < written.size(); ++i) {
    const char ch = written[i];
    if (ch == '\\') {
      out += '/';
    } else if (ch == '%' && i + 2 < written.size() && std::isxdigit(uint8_t(written[i + 1])) &&
               std::isxdigit(uint8_t(written[i + 2]))) {
      out += char(std::stoi(std::string(written.substr(i + 1, 2)), nullptr, 16));
      i += 2;
    } else {
      out += ch;
    }
  }
  return out;
}

// Converts one imported file; objects go straight into `scene`, which the caller rolls back
// on error.
class Converter {
 public:
  Converter(const std::string& path, const aiScene& ai, Scene& scene, const glm::dmat4& root)
      : root_(root),
        path_(path),
        stem_(fs::path(path).stem().string()),
        ai_(ai),
        scene_(scene),
        builder_(scene),
        materials_(ai.mNumMaterials, UINT32_MAX),
        untextured_(ai.mNumMaterials, UINT32_MAX) {}

  Converter& with_textures(bool drop_bad, ImportReport* report) {
    drop_bad_textures_ = drop_bad;
    report_ = report;
    return *this;
  }
  Converter& with_instances(bool instances) {
    instances_wanted_ = instances;
    return *this;
  }

  Result<void> run() {
    // Depth first with an explicit stack: a deep hierarchy cannot overflow the call stack.
    // Each entry carries the cell (room) its node lies in, if any (docs/techniques/portal.md).
    struct Entry {
      const aiNode* node;
      glm::dmat4 parent;
      int32_t cell;
    };
    std::vector<Entry> stack{{ai_.mRootNode, root_, -1}};
    while (!stack.empty()) {
      auto [node, parent, cell] = stack.back();
      stack.pop_back();
      const glm::dmat4 world = parent * to_glm(node->mTransformation);
      const std::string_view name = node->mName.C_Str();
      const Role role = role_of(name);
      if (role == Role::cell) {
        cells_.push_back({std::string(name.substr(0, name.size() - 5)), {}, {}, false});
        cell = int32_t(cells_.size() - 1);
      }
      for (unsigned i = 0; i < node->mNumMeshes; ++i) {
        const aiMesh& mesh = *ai_.mMeshes[node->mMeshes[i]];
        if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points, lines
        if (role == Role::portal || role == Role::bound) {
          if (auto r = add_cell_shape(role, name, mesh, world, cell); !r) return r;
          continue;
        }
        if (auto r = add_instance(*node, mesh, world); !r) return r;
        if (scene_.objects.empty() || scene_.objects.size() - 1 < first_object_) continue;
        (cell >= 0 ? cells_[cell].objects : shared_).push_back(uint32_t(scene_.objects.size() - 1));
      }
      for (unsigned i = node->mNumChildren; i-- > 0;)
        stack.push_back({node->mChildren[i], world, cell});
    }
    if (triangles_ == 0) return make_error(path_, ": contains no triangles");
    return finish_cells();
  }

 private:
  // Nodes named by the cell convention: "NAME-cell" (or "NAME-room") is a cell, "OTHER-portal"
  // inside it a portal to cell OTHER, "-bound" inside it the cell's box (drawn by neither).
  enum class Role { object, cell, portal, bound };
  static Role role_of(std::string_view name) {
    if (name.ends_with("-cell") || name.ends_with("-room")) return Role::cell;
    if (name.ends_with("-portal")) return Role::portal;
    if (name.ends_with("-bound")) return Role::bound;
    return Role::object;
  }
  struct CellDraft {
    std::string name;
    Bounds3 bound;  // from a -bound node
    std::vector<uint32_t> objects;
    bool has_bound;
  };
  struct PortalDraft {
    std::string node;  // for messages
    int32_t cell;
    std::string to;
    std::vector<glm::vec3> points;
  };

  Result<void> add_cell_shape(Role role, std::string_view name, const aiMesh& mesh,
                              const glm::dmat4& world, int32_t cell) {
    std::vector<glm::vec3> points(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      points[v] = glm::vec3(world * glm::dvec4(p.x, p.y, p.z, 1.0));
    }
    const std::string node(name);
    if (cell < 0)
      return make_error(path_, ": '", node, "' is not inside a cell (a node named NAME-cell)");
    if (role == Role::bound) {
      for (const glm::vec3& p : points) cells_[cell].bound.expand(p);
      cells_[cell].has_bound = true;
      return {};
    }
    std::vector<uint32_t> triangles;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f)
      if (mesh.mFaces[f].mNumIndices == 3)
        triangles.insert(triangles.end(), mesh.mFaces[f].mIndices, mesh.mFaces[f].mIndices + 3);
    auto polygon = portal_polygon_of_mesh(points, triangles);
    if (!polygon) return make_error(path_, ": portal '", node, "' ", polygon.error().message);
    portals_.push_back({node, cell, node.substr(0, node.size() - 7), std::move(*polygon)});
    return {};
  }

  // The file's cells and portals into the scene: a cell's box from its -bound node or its
  // objects; objects outside every cell are seen from all of them.
  Result<void> finish_cells() {
    if (cells_.empty()) {
      if (!portals_.empty())
        return make_error(path_, ": portal '", portals_[0].node, "' without cells");
      return {};
    }
    const uint32_t base = uint32_t(scene_.cells.size());
    for (CellDraft& c : cells_) {
      Bounds3 box = c.bound;
      if (!c.has_bound)
        for (uint32_t o : c.objects) box.expand(scene_.objects[o].bounds);
      if (box.empty())
        return make_error(path_, ": cell '", c.name, "' has no meshes and no -bound node");
      Cell cell;
      cell.bounds = box;
      cell.name_offset = uint32_t(scene_.names.size());
      cell.name_size = uint32_t(c.name.size());
      scene_.names += c.name;
      cell.first_object = uint32_t(scene_.cell_objects.size());
      scene_.cell_objects.insert(scene_.cell_objects.end(), c.objects.begin(), c.objects.end());
      scene_.cell_objects.insert(scene_.cell_objects.end(), shared_.begin(), shared_.end());
      cell.object_count = uint32_t(scene_.cell_objects.size()) - cell.first_object;
      scene_.cells.push_back(cell);
    }
    for (PortalDraft& p : portals_) {
      const auto to = std::find_if(cells_.begin(), cells_.end(),
                                   [&](const CellDraft& c) { return c.name == p.to; });
      if (to == cells_.end())
        return make_error(path_, ": portal '", p.node, "' in cell '", cells_[p.cell].name,
                          "' names cell '", p.to, "', which the file does not have");
      const uint32_t other = uint32_t(to - cells_.begin());
      if (other == uint32_t(p.cell))
        return make_error(path_, ": portal '", p.node, "' leads from cell '", p.to, "' to itself");
      // Counter-clockwise seen from its own cell: the normal points into it.
      const auto plane = portal_plane(p.points);
      const glm::vec3 inside = scene_.cells[base + p.cell].bounds.center();
      const glm::vec3 beyond = scene_.cells[base + other].bounds.center();
      if (plane->signed_distance(inside) < plane->signed_distance(beyond))
        std::reverse(p.points.begin(), p.points.end());
      scene_.portals.push_back({{base + uint32_t(p.cell), base + other},
                                uint32_t(scene_.portal_points.size()),
                                uint32_t(p.points.size())});
      scene_.portal_points.insert(scene_.portal_points.end(), p.points.begin(), p.points.end());
    }
    return {};
  }

  // "node/mesh", or one of them when the other is empty or the same; the file's stem and the
  // instance number when both are empty. Roots that a reader made up ("<OFFRoot>") count as
  // unnamed.
  std::string object_name(const aiNode& node, const aiMesh& mesh) const {
    std::string name = node.mName.C_Str();
    if (name.size() >= 2 && name.front() == '<' && name.back() == '>') name.clear();
    const std::string_view mesh_name = mesh.mName.C_Str();
    if (!mesh_name.empty() && mesh_name != name) {
      if (!name.empty()) name += '/';
      name += mesh_name;
    }
    return name.empty() ? stem_ + "/" + std::to_string(instances_) : name;
  }

  // The scene material of an assimp material, with its texture; the same without the
  // texture for a mesh that has no texture coordinates.
  Result<uint32_t> material(unsigned index, bool has_uvs) {
    if (materials_[index] == UINT32_MAX) {
      const aiMaterial& m = *ai_.mMaterials[index];
      Material out = material_of(m);
      untextured_[index] = builder_.add_material(out);
      if (auto slot = base_colour_texture(m)) {
        auto texture = texture_of(slot->second);
        if (!texture) return texture.error();
        if (*texture != kNoTexture) {
          out.texture = *texture;
          int u = aiTextureMapMode_Wrap, v = aiTextureMapMode_Wrap;
          m.Get(AI_MATKEY_MAPPINGMODE_U(slot->first, 0), u);
          m.Get(AI_MATKEY_MAPPINGMODE_V(slot->first, 0), v);
          out.wrap_u = wrap_of(u);
          out.wrap_v = wrap_of(v);
          aiString mode;
          if (scene_.textures[*texture].has_alpha && out.alpha_mode == AlphaMode::opaque &&
              m.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) != AI_SUCCESS)
            out.alpha_mode = AlphaMode::mask;  // cut-out foliage and fences in OBJ, FBX, ...
        }
      }
      materials_[index] = builder_.add_material(out);
    }
    return has_uvs ? materials_[index] : untextured_[index];
  }

  // The scene texture a model's texture path names (embedded: "*N" or an embedded file's
  // name; else a file relative to the model), read once per path; kNoTexture when it fails
  // and the user asked to drop such textures.
  Result<uint32_t> texture_of(const aiString& written) {
    const std::string key = written.C_Str();
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    Result<Texture> texture = make_error("");
    if (const aiTexture* embedded = ai_.GetEmbeddedTexture(written.C_Str())) {
      const std::string name = fs::path(path_).filename().string() + " (embedded texture " +
                               (key.starts_with("*") ? key.substr(1) : key) + ")";
      if (embedded->mHeight == 0) {  // compressed: mWidth bytes
        texture = texture_from_image_bytes(
            name, std::as_bytes(std::span(reinterpret_cast<const char*>(embedded->pcData),
                                          embedded->mWidth)));
      } else {
        Texels texels(int(embedded->mWidth), int(embedded->mHeight));
        for (size_t i = 0; i < size_t(embedded->mWidth) * embedded->mHeight; ++i) {
          const aiTexel& t = embedded->pcData[i];
          texels.rgba[i * 4 + 0] = t.r;
          texels.rgba[i * 4 + 1] = t.g;
          texels.rgba[i * 4 + 2] = t.b;
          texels.rgba[i * 4 + 3] = t.a;
        }
        texture = texture_from_texels(name, texels);
      }
    } else {
      // As written, relative to the model; else its file name beside the model (models often
      // keep the absolute path they were authored with).
      const fs::path folder = fs::path(path_).parent_path();
      fs::path file = folder / file_path_of(key);
      std::error_code ec;
      if (!fs::is_regular_file(file, ec) &&
          fs::is_regular_file(folder / fs::path(file_path_of(key)).filename(), ec))
        file = folder / fs::path(file_path_of(key)).filename();
      auto opened = ReadableFile::open(file.string());
      if (!opened) {
        texture =
            make_error(file.string(), ": texture not found (named '", key, "' in ", path_, ")");
      } else {
        auto bytes = opened->read_all();
        texture = bytes ? texture_from_image_bytes(file.string(), std::as_bytes(std::span(*bytes)))
                        : Result<Texture>(bytes.error());
      }
    }
    uint32_t index = kNoTexture;
    if (texture) {
      index = builder_.add_texture(std::move(*texture));
    } else if (!drop_bad_textures_) {
      return make_error(path_, ": ", texture.error().message,
                        " (--drop-bad-textures imports it with the material's colour instead)");
    } else if (report_) {
      report_->dropped_textures.push_back(texture.error().message);
    }
    textures_.emplace(key, index);
    return index;
  }

  Result<void> add_instance(const aiNode& node, const aiMesh& mesh, const glm::dmat4& world) {
    const std::string name = object_name(node, mesh);
    ++instances_;
    if (uint64_t(scene_.vertices.size()) + mesh.mNumVertices > UINT32_MAX ||
        uint64_t(scene_.indices.size()) + 3ull * mesh.mNumFaces > UINT32_MAX)
      return make_error(path_, ": too large: the scene would pass 2^32 vertices or indices");
    // A mesh placed again (a CAD part, a tree in a forest) repeats its first placement moved
    // by this one's world matrix times the inverse of that one's: a scene instance, which the
    // file stores once. Not where one placement mirrors and the other does not.
    if (auto first = placed_.find(&mesh); instances_wanted_ && first != placed_.end()) {
      const glm::dmat4 move = world * glm::inverse(first->second.world);
      const glm::mat3 linear(move);
      const glm::vec3 offset(move[3]);
      const Instance candidate{0, first->second.object, linear, offset};
      const double det = glm::determinant(glm::dmat3(move));
      if (std::isfinite(det) && det > 1e-12 && validate_moved(candidate)) {
        builder_.add_instance(name, ObjectKind::mesh, first->second.object, linear, offset);
        triangles_ += scene_.objects.back().triangle_count();
        return {};
      }
    }
    const size_t objects_before = scene_.objects.size();

    positions_.resize(mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      positions_[v] = glm::vec3(world * glm::dvec4(p.x, p.y, p.z, 1.0));
      if (!finite(positions_[v]))
        return make_error(path_, ": mesh '", name, "' has a vertex with a non-finite coordinate");
    }

    // Normals go through the cofactor matrix, det(M) * inverse(M)^T: the inverse transpose up
    // to scale, defined even when M is singular. A mirroring M (det < 0) also flips winding.
    const glm::dmat3 m(world);
    const bool mirrored = glm::determinant(m) < 0.0;
    glm::dmat3 cofactor(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
    if (mirrored) cofactor = -cofactor;

    const aiVector3D* uvs = mesh.mTextureCoords[0];
    auto material_index = material(mesh.mMaterialIndex, uvs != nullptr);
    if (!material_index) return material_index.error();
    builder_.begin_object(name, ObjectKind::mesh, *material_index);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      glm::vec3 normal(0.0f, 1.0f, 0.0f);
      if (mesh.mNormals) {
        const aiVector3D& n = mesh.mNormals[v];
        const glm::dvec3 t = cofactor * glm::dvec3(n.x, n.y, n.z);
        const double length = glm::length(t);
        if (std::isfinite(length) && length > 1e-30) normal = glm::vec3(t / length);
      }
      uint32_t color = 0xffffffffu;
      if (mesh.mColors[0]) {
        const aiColor4D& c = mesh.mColors[0][v];
        color = pack_color(sanitize(glm::vec4(c.r, c.g, c.b, c.a)));
      }
      // assimp gives texture coordinates from the bottom-left; the scene's are glTF's.
      glm::vec2 uv{};
      if (uvs) uv = {uvs[v].x, 1.0f - uvs[v].y};
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = {};
      builder_.add_vertex(positions_[v], normal, color, uv);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      const unsigned* i = face.mIndices;
      if (i[0] >= mesh.mNumVertices || i[1] >= mesh.mNumVertices || i[2] >= mesh.mNumVertices)
        continue;  // ValidateDataStructure has refused these already
      if (mirrored)
        builder_.add_triangle(i[0], i[2], i[1]);
      else
        builder_.add_triangle(i[0], i[1], i[2]);
      ++triangles_;
    }
    builder_.end_object();
    if (scene_.objects.size() > objects_before && !placed_.contains(&mesh))
      placed_.emplace(&mesh, Placement{uint32_t(scene_.objects.size() - 1), world});
    return {};
  }

  // Whether an instance's transform is one the scene takes (finite, not mirroring) and keeps
  // its vertices finite.
  bool validate_moved(const Instance& instance) const {
    const float det = glm::determinant(instance.linear);
    if (!std::isfinite(det) || !(det > 0.0f)) return false;
    const InstanceTransform move(instance);
    const Object& p = scene_.objects[instance.prototype];
    for (uint32_t v = 0; v < p.vertex_count; ++v)
      if (!finite(move(scene_.vertices[p.first_vertex + v]).position)) return false;
    return true;
  }

  glm::dmat4 root_;  // the parent of the file's root node: --up, then --scale
  const std::string& path_;
  std::string stem_;
  const aiScene& ai_;
  Scene& scene_;
  SceneBuilder builder_;
  std::vector<uint32_t> materials_;   // aiMaterial index -> scene material, UINT32_MAX unused
  std::vector<uint32_t> untextured_;  // the same without its texture
  std::unordered_map<std::string, uint32_t> textures_;  // path as written -> scene texture
  bool drop_bad_textures_ = false;
  bool instances_wanted_ = true;
  ImportReport* report_ = nullptr;
  std::vector<glm::vec3> positions_;
  // Each mesh's first placement as an object of its own: the prototype of later ones.
  struct Placement {
    uint32_t object;
    glm::dmat4 world;
  };
  std::unordered_map<const aiMesh*, Placement> placed_;
  uint64_t instances_ = 0, triangles_ = 0;
  size_t first_object_ = scene_.objects.size();  // this file's objects start here
  std::vector<CellDraft> cells_;
  std::vector<PortalDraft> portals_;
  std::vector<uint32_t> shared_;  // objects outside every cell
};

// The sizes of a scene's arrays, to cut it back to after a failed import.
struct Snapshot {
  explicit Snapshot(const Scene& s)
      : objects(s.objects.size()),
        materials(s.materials.size()),
        vertices(s.vertices.size()),
        indices(s.indices.size()),
        names(s.names.size()),
        uvs(s.uvs.size()),
        textures(s.textures.size()),
        cells(s.cells.size()),
        cell_objects(s.cell_objects.size()),
        portals(s.portals.size()),
        portal_points(s.portal_points.size()),
        instances(s.instances.size()),
        bounds(s.bounds) {}
  void restore(Scene& s) const {
    s.objects.resize(objects);
    s.materials.resize(materials);
    s.vertices.resize(vertices);
    s.indices.resize(indices);
    s.names.resize(names);
    s.uvs.resize(uvs);
    s.textures.resize(textures);
    s.cells.resize(cells);
    s.cell_objects.resize(cell_objects);
    s.portals.resize(portals);
    s.portal_points.resize(portal_points);
    s.instances.resize(instances);
    s.bounds = bounds;
  }
  size_t objects, materials, vertices, indices, names, uvs, textures, cells, cell_objects, portals,
      portal_points, instances;
  Bounds3 bounds;
};

Result<void> check_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) return make_error(path, ": no such file");
  if (ec) return make_error(path, ": cannot be read (", ec.message(), ")");
  if (status.type() == fs::file_type::directory) return make_error(path, ": is a directory");
  if (status.type() != fs::file_type::regular) return make_error(path, ": not a regular file");
  if (fs::file_size(path, ec) == 0 && !ec) return make_error(path, ": file is empty");
  return {};
}

// Metres per file unit where the file says so, else 1.
double file_unit_in_metres(const aiScene& ai) {
  if (!ai.mMetaData) return 1.0;
  double centimetres = 0.0;
  float as_float = 0.0f;
  if (!ai.mMetaData->Get("UnitScaleFactor", centimetres) &&
      ai.mMetaData->Get("UnitScaleFactor", as_float))
    centimetres = as_float;
  return std::isfinite(centimetres) && centimetres > 0.0 ? centimetres / 100.0 : 1.0;
}

}  // namespace

Result<void> import_model(const std::string& path, Scene& scene, const ImportOptions& options,
                          ImportReport* report) {
  if (options.up != 'y' && options.up != 'z')
    return make_error("--up must be y or z (got ", std::string(1, options.up), ")");
  if (!(std::isfinite(options.scale) && options.scale > 0.0 && options.scale <= 1e6))
    return make_error("--scale must be a number in (0, 1e6] (got ", number_text(options.scale),
                      ")");
  if (auto r = check_file(path); !r) return r;
  {
    const MappedFile file(path);
    if (!file.ok()) return make_error(path, ": cannot be read (", file.error(), ")");
    if (auto r = check_structure(path, file.view()); !r) return r;
  }

  Assimp::Importer importer;
  importer.SetPropertyFloat(AI_CONFIG_PP_GSN_MAX_SMOOTHING_ANGLE, kSmoothingAngleDeg);
  importer.SetPropertyBool(AI_CONFIG_PP_FD_REMOVE, true);
  importer.SetPropertyBool(AI_CONFIG_PP_FD_CHECKAREA, false);
  const aiScene* ai = importer.ReadFile(path, kImportFlags);
  if (!ai || !ai->mRootNode)
    return make_error(path, ": not a readable model (", importer.GetErrorString(), ")");

  const Snapshot before(scene);
  // Units from the file where the format states them and assimp leaves them as they are:
  // FBX gives centimetres per unit (UnitScaleFactor; 1, centimetres, by default), which
  // assimp 5.2 keeps in the metadata without scaling. --scale multiplies on top.
  const double scale = options.scale * file_unit_in_metres(*ai);
  // Z up to Y up is a quarter turn about X: (x, y, z) -> (x, z, -y).
  glm::dmat4 root = glm::dmat4(scale);
  root[3][3] = 1.0;
  if (options.up == 'z') root = root * glm::dmat4(1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1);
  Result<void> r =
      Converter(path, *ai, scene, root)
          .with_textures(options.drop_bad_textures, report)
          .with_instances(options.instances)
          .run();
  if (!r) before.restore(scene);
  return r;
}

Result<Scene> import_models(std::span<const std::string> paths, Progress& progress,
                            const ImportOptions& options, ImportReport* report) {
  if (paths.empty()) return make_error("import: no input files");
  Scene scene;
  progress.start("import", paths.size());
  for (const std::string& path : paths) {
    if (auto r = import_model(path, scene, options, report); !r) {
      progress.finish();
      return r.error();
    }
    progress.advance();
  }
  progress.finish();
  const std::string problem = validate_scene(scene);
  FF_ASSERT(problem.empty(), "imported scene is invalid: %s", problem.c_str());
  return scene;
}

}  // namespace farfield
