#include "farfield/scene/tree_generator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "farfield/core/text.hpp"
#include "farfield/core/assert.hpp"
#include "mesh_primitives.hpp"
#include "random.hpp"

namespace farfield {

namespace {

using detail::Rng;
using detail::splitmix64;

constexpr uint32_t kMostIterations = 12;
constexpr size_t kMostSymbols = size_t(1) << 26;  // the derived string, bytes
constexpr uint64_t kMostTriangles = 50'000'000;   // per tree
constexpr float kTrunkRadius = 0.07f;             // of the first segment, in units of its length
constexpr float kTropism = 0.08f;                 // bend towards the ground per segment (ABOP's e)
constexpr float kLeafWidth = 0.45f;               // of a leaf's length
// Shortest and thinnest segment: deep branches of tiny ratios stay drawable, never reach 0.
constexpr float kLeast = 1e-6f;
const glm::vec3 kBark{0.36f, 0.25f, 0.16f}, kLeaf{0.20f, 0.46f, 0.13f};

// Independent streams for the turtle and the leaves: changing --leaves keeps the branches.
Rng stream(uint64_t seed, uint64_t which) {
  uint64_t state = seed ^ (which * 0x9e3779b97f4a7c15ull);
  return Rng(splitmix64(state));
}

// ---- The L-system. -------------------------------------------------------------------------

bool is_letter(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}
bool is_symbol(char c) {
  return is_letter(c) || std::string_view("+-&^/\\|[]").find(c) != std::string_view::npos;
}

// Empty when `word` is made of known symbols with balanced brackets, else what is wrong.
std::string check_word(std::string_view word) {
  int depth = 0;
  for (char c : word) {
    if (!is_symbol(c))
      return std::string("'") + c +
             "' is not a symbol of the L-system (letters and + - & ^ / \\ | [ ])";
    depth += c == '[' ? 1 : c == ']' ? -1 : 0;
    if (depth < 0) return "']' without '['";
  }
  return depth == 0 ? std::string() : "'[' without ']'";
}

struct Rules {
  std::array<std::string, 128> successor;
  std::array<bool, 128> rewrites{};
};

Result<Rules> parse_rules(const std::vector<std::string>& rules) {
  Rules out;
  for (const std::string& rule : rules) {
    auto bad = [&](const std::string& why) { return make_error("--rule '", rule, "': ", why); };
    if (rule.size() < 2 || rule[1] != '=' || !is_letter(rule[0]))
      return bad("must be LETTER=SUCCESSOR, e.g. A=F[+A][-A]");
    if (std::string why = check_word(std::string_view(rule).substr(2)); !why.empty())
      return bad(why);
    const auto p = static_cast<unsigned char>(rule[0]);
    if (out.rewrites[p]) return bad(std::string("a second rule for '") + rule[0] + "'");
    out.rewrites[p] = true;
    out.successor[p] = rule.substr(2);
  }
  return out;
}

Result<std::string> derive(const TreeOptions& o, const Rules& rules) {
  std::string word = o.axiom, next;
  for (uint32_t i = 0; i < o.iterations; ++i) {
    next.clear();
    for (char c : word) {
      const auto p = static_cast<unsigned char>(c);
      if (rules.rewrites[p])
        next += rules.successor[p];
      else
        next += c;
      if (next.size() > kMostSymbols)
        return make_error("--iterations ", std::to_string(o.iterations),
                          " grows the L-system past ", std::to_string(kMostSymbols),
                          " symbols at iteration ", std::to_string(i + 1), "; use fewer");
    }
    word.swap(next);
  }
  return word;
}

// ---- The turtle. ---------------------------------------------------------------------------

struct Segment {
  glm::vec3 p0, p1, side;
  float r0, r1;
  uint32_t color, cluster;
};
struct LeafSite {  // the end of the segment a cluster of leaves grows along
  glm::vec3 tip, heading;
  float length;
  uint32_t cluster;
};
struct Skeleton {
  std::vector<Segment> segments;
  std::vector<LeafSite> leaves;
  uint32_t clusters = 1;
};

// Rotates v about the unit axis k by `angle` radians (Rodrigues).
glm::vec3 rotate(const glm::vec3& v, const glm::vec3& k, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0f - c);
}

// The bracket depth whose branches become objects: the shallowest with at least objects - 1
// branches, else the one with the most. 0: no split.
uint32_t split_depth(std::string_view word, uint32_t objects) {
  if (objects <= 1) return 0;
  std::vector<uint64_t> count(1, 0);  // count[d]: branches opening at depth d
  uint32_t depth = 0;
  for (char c : word) {
    if (c == '[') {
      if (++depth >= count.size()) count.push_back(0);
      ++count[depth];
    } else if (c == ']') {
      --depth;
    }
  }
  uint32_t best = 0;
  for (uint32_t d = 1; d < count.size(); ++d) {
    if (count[d] + 1 >= objects) return d;
    if (count[d] > count[best]) best = d;
  }
  return best;
}

// Reads the string in unit space: the first segment has length 1.
Skeleton interpret(std::string_view word, const TreeOptions& o) {
  struct State {
    glm::vec3 pos{0.0f}, h{0, 1, 0}, l{-1, 0, 0}, u{0, 0, 1};  // heading, left, up
    float length = 1.0f, radius = kTrunkRadius, last = 0.0f;   // last: segment length
    uint32_t depth = 0, cluster = 0;
  };
  Rng rng = stream(o.seed, 1);
  const float jitter = static_cast<float>(o.jitter);
  auto vary = [&](double v) { return float(v) * (1.0f + jitter * rng.uniform(-1.0, 1.0)); };
  const double angle = o.branch_angle_deg * std::numbers::pi / 180.0;
  const double roll = o.divergence_deg * std::numbers::pi / 180.0;
  const glm::vec3 down(0.0f, -1.0f, 0.0f);

  Skeleton out;
  const uint32_t split = split_depth(word, o.objects);
  State s;
  std::vector<State> stack;
  auto turn = [&](glm::vec3 axis, double a) {  // the frame about one of its own axes (a copy)
    const float r = vary(a);
    s.h = rotate(s.h, axis, r), s.l = rotate(s.l, axis, r), s.u = rotate(s.u, axis, r);
  };
  for (char c : word) {
    switch (c) {
      case 'F': {
        const float length = vary(s.length);
        const float r1 = std::max(s.radius * float(o.segment_taper), kLeast);
        const glm::vec3 end = s.pos + s.h * length;
        const float shade = rng.uniform(-0.04, 0.04);
        out.segments.push_back({s.pos, end, s.l, s.radius, r1,
                                pack_color(glm::vec4(glm::clamp(kBark + shade, 0.0f, 1.0f), 1.0f)),
                                s.cluster});
        s.pos = end, s.radius = r1, s.last = length;
        // Tropism: bend by kTropism |H x T| towards the ground, then keep the frame orthonormal.
        const glm::vec3 k = glm::cross(s.h, down);
        const float sine = glm::length(k);
        if (sine > 1e-6f) {
          const glm::vec3 axis = k / sine;
          s.h = rotate(s.h, axis, kTropism * sine), s.l = rotate(s.l, axis, kTropism * sine);
        }
        s.h = glm::normalize(s.h);
        s.l = glm::normalize(s.l - glm::dot(s.l, s.h) * s.h);
        s.u = glm::cross(s.h, s.l);
        break;
      }
      case '+':
        turn(s.u, angle);
        break;
      case '-':
        turn(s.u, -angle);
        break;
      case '&':
        turn(s.l, angle);
        break;
      case '^':
        turn(s.l, -angle);
        break;
      case '/':
        turn(s.h, roll);
        break;
      case '\\':
        turn(s.h, -roll);
        break;
      case '|':
        s.h = -s.h, s.l = -s.l;  // exactly round, about the up axis
        break;
      case '[':
        stack.push_back(s);
        s.length = std::max(s.length * float(o.length_ratio), kLeast);
        s.radius = std::max(s.radius * float(o.radius_ratio), kLeast);
        if (++s.depth == split) s.cluster = out.clusters++;
        break;
      case ']':
        s = stack.back();
        stack.pop_back();
        break;
      case 'L':
        if (s.last > 0.0f) out.leaves.push_back({s.pos, s.h, s.last, s.cluster});
        break;
      default:
        break;  // a variable
    }
  }
  return out;
}

// ---- Geometry. -----------------------------------------------------------------------------

// A leaf: a rhombus from `base` along `dir`, twice, with the same corners facing opposite ways.
void leaf(SceneBuilder& b, const glm::vec3& base, const glm::vec3& dir, const glm::vec3& across,
          float size, uint32_t color) {
  const glm::vec3 mid = base + 0.5f * size * dir, side = 0.5f * kLeafWidth * size * across;
  const glm::vec3 corners[4] = {base, mid + side, base + size * dir, mid - side};
  const glm::vec3 normal = glm::normalize(glm::cross(side, dir));  // front: counter-clockwise
  for (const float facing : {1.0f, -1.0f}) {
    const uint32_t first = b.vertex_count();
    for (const glm::vec3& p : corners) b.add_vertex(p, facing * normal, color);
    if (facing > 0.0f) {
      b.add_triangle(first, first + 1, first + 2);
      b.add_triangle(first, first + 2, first + 3);
    } else {
      b.add_triangle(first, first + 2, first + 1);
      b.add_triangle(first, first + 3, first + 2);
    }
  }
}

// A unit vector uniform on the sphere.
glm::vec3 random_direction(Rng& rng) {
  const float y = rng.uniform(-1.0, 1.0), a = rng.uniform(0.0, 2.0 * std::numbers::pi);
  const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
  return {r * std::cos(a), y, r * std::sin(a)};
}

void add_leaves(SceneBuilder& b, const LeafSite& site, const TreeOptions& o, float scale,
                Rng& rng) {
  const float size = float(o.leaf_size), jitter = float(o.jitter);
  for (uint32_t k = 0; k < o.leaves; ++k) {
    // Along the last 90% of the segment, pointing outwards from it in any direction.
    const glm::vec3 base = site.tip - site.heading * (site.length * scale * rng.uniform(0.0, 0.9));
    glm::vec3 dir = random_direction(rng);
    if (glm::dot(dir, site.heading) < 0.0f)
      dir -= 1.5f * glm::dot(dir, site.heading) * site.heading;
    dir = glm::normalize(dir);
    glm::vec3 across = glm::cross(dir, random_direction(rng));
    if (glm::length(across) < 1e-3f) across = glm::cross(dir, glm::vec3(0.0f, 1.0f, 0.0f));
    if (glm::length(across) < 1e-3f) across = glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 green = kLeaf + glm::vec3(rng.uniform(-0.05, 0.05), rng.uniform(-0.07, 0.07),
                                              rng.uniform(-0.03, 0.03));
    leaf(b, base, dir, glm::normalize(across), size * (1.0f - jitter * rng.uniform()),
         pack_color(glm::vec4(glm::clamp(green, 0.0f, 1.0f), 1.0f)));
  }
}

Result<void> check_range(const char* option, double v, double lo, double hi, bool open_lo) {
  if (!(open_lo ? v > lo : v >= lo) || !(v <= hi))  // also rejects NaN
    return make_error(option, " must be in ", open_lo ? "(" : "[", number_text(lo), ", ",
                      number_text(hi), "] (got ", number_text(v), ")");
  return {};
}

}  // namespace

Result<void> validate_tree_options(const TreeOptions& o) {
  for (const Result<void>& r : {
           check_range("--iterations", o.iterations, 0, kMostIterations, false),
           check_range("--branch-angle", o.branch_angle_deg, 0.0, 180.0, false),
           check_range("--divergence", o.divergence_deg, 0.0, 360.0, false),
           check_range("--length-ratio", o.length_ratio, 0.0, 1.0, true),
           check_range("--radius-ratio", o.radius_ratio, 0.0, 1.0, true),
           check_range("--taper", o.segment_taper, 0.0, 1.0, true),
           check_range("--jitter", o.jitter, 0.0, 0.5, false),
           check_range("--height", o.height, 0.0, 1000.0, true),
           check_range("--leaf-size", o.leaf_size, 0.0, 100.0, true),
           check_range("--leaves", o.leaves, 0, 1000, false),
           check_range("--sides", o.sides, 3, 64, false),
           check_range("--objects", o.objects, 1, 100000, false),
       }) {
    if (!r) return r;
  }
  if (o.axiom.empty()) return make_error("--axiom must not be empty");
  if (std::string why = check_word(o.axiom); !why.empty())
    return make_error("--axiom '", o.axiom, "': ", why);
  if (auto rules = parse_rules(o.rules); !rules) return rules.error();
  return {};
}

Result<void> add_tree(SceneBuilder& b, const TreeOptions& o, const glm::vec3& base,
                      std::string_view tree_name, Progress* progress) {
  if (auto ok = validate_tree_options(o); !ok) return ok;
  auto rules = parse_rules(o.rules);
  auto word = derive(o, *rules);
  if (!word) return word.error();
  // Counted on the string, before the turtle allocates anything: 'L' after no 'F' draws nothing.
  const auto segments = uint64_t(std::count(word->begin(), word->end(), 'F'));
  const auto sites = uint64_t(std::count(word->begin(), word->end(), 'L'));
  const uint64_t triangles = segments * 2 * o.sides + sites * o.leaves * 4;
  if (triangles > kMostTriangles)
    return make_error("the tree would have up to ", std::to_string(triangles),
                      " triangles, over the ", std::to_string(kMostTriangles),
                      " a tree may have; use fewer --iterations, --sides or --leaves");
  if (segments == 0)
    return make_error("the L-system draws no branch: after --iterations ",
                      std::to_string(o.iterations), " the string has no 'F'");
  const Skeleton tree = interpret(*word, o);

  // Scale so that the highest branch point is at `height`.
  float top = 0.0f;
  for (const Segment& s : tree.segments) top = std::max({top, s.p0.y, s.p1.y});
  if (!(top > 0.0f))
    return make_error("the branches never rise above the base; check --axiom and --rule");
  const float scale = float(o.height) / top;
  auto place = [&](const glm::vec3& p) { return base + p * scale; };

  // Each object's primitives in the turtle's order.
  auto by_cluster = [](const auto& items) {
    std::vector<uint32_t> order(items.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return items[a].cluster < items[b].cluster; });
    return order;
  };
  const std::vector<uint32_t> segment_order = by_cluster(tree.segments);
  const std::vector<uint32_t> leaf_order = by_cluster(tree.leaves);

  const uint32_t material = b.add_material(Material{glm::vec4(1.0f)});
  Rng rng = stream(o.seed, 2);
  if (progress) progress->start("generate tree", tree.clusters);
  std::string name;
  size_t next_segment = 0, next_leaf = 0;
  for (uint32_t c = 0; c < tree.clusters; ++c) {
    name = tree_name;
    if (o.objects > 1) name += c == 0 ? std::string("/trunk") : "/subtree_" + std::to_string(c - 1);
    b.begin_object(name, ObjectKind::tree, material);
    for (; next_segment < segment_order.size(); ++next_segment) {
      const Segment& s = tree.segments[segment_order[next_segment]];
      if (s.cluster != c) break;
      const glm::vec3 p0 = place(s.p0), p1 = place(s.p1);
      if (p0 == p1) continue;  // shorter than float resolution (absurd ratios)
      mesh::tube(b, p0, p1, s.r0 * scale, s.r1 * scale, s.side, int(o.sides), s.color);
    }
    for (; next_leaf < leaf_order.size(); ++next_leaf) {
      LeafSite site = tree.leaves[leaf_order[next_leaf]];
      if (site.cluster != c) break;
      site.tip = place(site.tip);
      add_leaves(b, site, o, scale, rng);
    }
    b.end_object();
    if (progress) progress->advance();
  }
  return {};
}

Result<Scene> generate_tree(const TreeOptions& options, Progress& progress) {
  Scene scene;
  SceneBuilder builder(scene);
  if (auto ok = add_tree(builder, options, glm::vec3(0.0f), "tree", &progress); !ok)
    return ok.error();
  return scene;
}

}  // namespace farfield
