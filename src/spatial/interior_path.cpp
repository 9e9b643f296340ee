#include "farfield/spatial/interior_path.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <queue>
#include <vector>

#include "farfield/spatial/ray_caster.hpp"

namespace farfield {

namespace {

constexpr double kSpeed = 0.15;      // m per frame
constexpr float kThrough = 0.6f;     // a door's waypoints lie this far either side of it
constexpr float kStep = 0.1f;        // walk simulation step, m
constexpr float kKnee = 0.5f;        // steps up to this high are climbed
constexpr float kFloorMatch = 0.3f;  // a walk ends on a door's floor within this
constexpr float kTurnDeg = 6.0f;     // per frame
constexpr float kStandAndTurnDeg = 60.0f;
constexpr double kPi = 3.14159265358979323846;

// A place one can stand: feet on the ground.
struct Spot {
  glm::vec3 feet;
  uint32_t cell;
};

class Walker {
 public:
  Walker(const Scene& scene, float eye_height) : caster_(scene), eye_(eye_height) {}

  // The ground under `p` (cast down from `p`), or nan.
  float ground(const glm::vec3& p, float depth) const {
    const auto hit = caster_.cast(p, {0.0f, -1.0f, 0.0f}, depth);
    return hit ? p.y - hit->distance : NAN;
  }

  // Walks from `from` towards `to` in a straight line over the ground; appends the feet
  // positions to `trail` and returns where it ends, or nullopt where blocked.
  std::optional<glm::vec3> walk(const glm::vec3& from, const glm::vec3& to,
                                std::vector<glm::vec3>* trail) const {
    glm::vec3 feet = from;
    const glm::vec2 a(from.x, from.z), b(to.x, to.z);
    const float length = glm::length(b - a);
    const int steps = std::max(1, int(std::ceil(length / kStep)));
    const glm::vec2 dir = length > 0 ? (b - a) / length : glm::vec2(0.0f);
    for (int i = 1; i <= steps; ++i) {
      const glm::vec2 xz = a + (b - a) * (float(i) / float(steps));
      // Nothing at knee height or at the eye ahead.
      for (float h : {kKnee + 0.1f, eye_}) {
        const glm::vec3 at = feet + glm::vec3(0.0f, h, 0.0f);
        if (caster_.cast(at, {dir.x, 0.0f, dir.y}, length / float(steps) + 0.25f))
          return std::nullopt;
      }
      const float y = ground({xz.x, feet.y + kKnee, xz.y}, kKnee + 1.0f);
      if (std::isnan(y)) return std::nullopt;  // a drop or a hole
      feet = {xz.x, y, xz.y};
      if (caster_.cast(feet + glm::vec3(0.0f, 0.05f, 0.0f), {0.0f, 1.0f, 0.0f}, eye_ + 0.05f))
        return std::nullopt;  // no headroom
      if (trail) trail->push_back(feet);
    }
    return feet;
  }

 private:
  RayCaster caster_;
  float eye_;
};

struct Door {
  uint32_t portal;
  Spot side[2];  // in cells[0], cells[1]
};

}  // namespace

Result<CameraPath> interior_path(const Scene& scene, const PathOptions& o) {
  if (auto ok = validate_path_options(o); !ok) return ok.error();
  if (scene.cells.empty())
    return make_error(
        "interior paths need cells and portals (rooms and doors), e.g. a generated "
        "building; use --kind fly or orbit");
  const float eye = float(o.eye_height);
  Walker walker(scene, eye);

  // Doors: upright portals tall and wide enough, with ground at their foot on both sides.
  std::vector<Door> doors;
  std::vector<std::vector<std::pair<uint32_t, int>>> doors_of(scene.cells.size());
  for (uint32_t p = 0; p < scene.portals.size(); ++p) {
    const auto points = scene.points_of(scene.portals[p]);
    const auto plane = portal_plane(points);
    if (!plane || std::abs(plane->normal.y) > 0.3f) continue;
    float bottom = INFINITY, top = -INFINITY;
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& q : points) {
      bottom = std::min(bottom, q.y), top = std::max(top, q.y);
      lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
    const float width = glm::length(glm::vec2(hi.x - lo.x, hi.z - lo.z));
    if (top - bottom < eye + 0.1f || width < 0.6f) continue;
    const glm::vec3 n = glm::normalize(glm::vec3(plane->normal.x, 0.0f, plane->normal.z));
    const glm::vec3 foot((lo.x + hi.x) / 2, bottom, (lo.z + hi.z) / 2);
    Door d{p, {}};
    bool ok = true;
    for (int s = 0; s < 2; ++s) {
      glm::vec3 at = foot + n * (s == 0 ? kThrough : -kThrough);
      const float y = walker.ground(at + glm::vec3(0.0f, kKnee, 0.0f), kKnee + kFloorMatch);
      if (std::isnan(y) || std::abs(y - bottom) > kFloorMatch) ok = false;
      d.side[s] = {{at.x, y, at.z}, scene.portals[p].cells[s]};
    }
    if (!ok) continue;
    for (int s = 0; s < 2; ++s)
      doors_of[scene.portals[p].cells[s]].push_back({uint32_t(doors.size()), s});
    doors.push_back(d);
  }
  if (doors.empty())
    return make_error("interior paths need doors: upright portals at least ",
                      std::to_string(eye + 0.1f).substr(0, 4),
                      " m tall and 0.6 m wide with a floor on both sides; the scene has none");

  // Nodes: door sides (door * 2 + side). Within a cell, node a leads to node b where a
  // straight walk from a ends on b's floor; through a door, a side leads to the other.
  auto spot = [&](uint32_t node) { return doors[node / 2].side[node % 2]; };
  std::map<std::pair<uint32_t, uint32_t>, bool> walkable;
  auto can_walk = [&](uint32_t a, uint32_t b) {
    auto [it, fresh] = walkable.try_emplace({a, b}, false);
    if (fresh) {
      const auto end = walker.walk(spot(a).feet, spot(b).feet, nullptr);
      it->second = end && std::abs(end->y - spot(b).feet.y) < kFloorMatch;
    }
    return it->second;
  };
  auto neighbours = [&](uint32_t node, auto&& visit) {
    visit(node ^ 1u, kThrough * 2);  // through the door
    const uint32_t cell = spot(node).cell;
    for (const auto& [door, side] : doors_of[cell]) {
      const uint32_t other = door * 2 + uint32_t(side);
      if (other != node && can_walk(node, other))
        visit(other, glm::distance(spot(node).feet, spot(other).feet));
    }
  };
  auto is_room = [&](uint32_t cell) { return doors_of[cell].size() == 1; };

  // Nearest node from `start` (Dijkstra) that `goal` accepts; the nodes on the way.
  auto route_to = [&](uint32_t start, auto&& goal) -> std::vector<uint32_t> {
    std::map<uint32_t, float> dist{{start, 0.0f}};
    std::map<uint32_t, uint32_t> prev;
    using Item = std::pair<float, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    queue.push({0.0f, start});
    while (!queue.empty()) {
      const float d = queue.top().first;  // not a structured binding: the lambda below uses it
      const uint32_t node = queue.top().second;
      queue.pop();
      if (d > dist[node]) continue;
      if (node != start && goal(node)) {
        std::vector<uint32_t> route{node};
        while (route.back() != start) route.push_back(prev[route.back()]);
        std::reverse(route.begin(), route.end());
        return route;
      }
      neighbours(node, [&](uint32_t next, float step) {
        const float nd = d + step;
        if (auto it = dist.find(next); it == dist.end() || nd < it->second) {
          dist[next] = nd;
          prev[next] = node;
          queue.push({nd, next});
        }
      });
    }
    return {};
  };

  // Ways up: node pairs in one cell whose walk climbs more than a metre.
  std::vector<std::pair<uint32_t, uint32_t>> ups;
  for (uint32_t cell = 0; cell < scene.cells.size(); ++cell) {
    float low = INFINITY, high = -INFINITY;
    for (const auto& [door, side] : doors_of[cell]) {
      low = std::min(low, doors[door].side[side].feet.y);
      high = std::max(high, doors[door].side[side].feet.y);
    }
    if (high - low < 1.0f) continue;
    for (const auto& [da, sa] : doors_of[cell])
      for (const auto& [db, sb] : doors_of[cell]) {
        const uint32_t a = da * 2 + uint32_t(sa), b = db * 2 + uint32_t(sb);
        if (spot(b).feet.y - spot(a).feet.y > 1.0f && can_walk(a, b)) ups.push_back({a, b});
      }
  }
  // Start: the room door nearest a way up, on the lowest floor.
  std::optional<uint32_t> start;
  float best = INFINITY;
  for (uint32_t d = 0; d < doors.size(); ++d)
    for (int s = 0; s < 2; ++s) {
      const Spot& here = doors[d].side[s];
      if (!is_room(here.cell)) continue;
      float score = 100.0f * here.feet.y;
      float near = ups.empty() ? 0.0f : INFINITY;
      for (const auto& [a, b] : ups) near = std::min(near, glm::distance(here.feet, spot(a).feet));
      score += near;
      if (score < best) best = score, start = d * 2 + uint32_t(s);
    }
  if (!start)
    return make_error("interior paths need rooms (cells with one door); the scene has none");

  // The route: feet positions along the walk.
  std::vector<glm::vec3> trail;
  const double speed = o.speed > 0.0 ? o.speed : kSpeed;
  const double wanted = speed * double(o.frames) + 2.0;
  double length = 0.0;
  auto go = [&](const glm::vec3& from, const glm::vec3& to) {
    const size_t before = trail.size();
    walker.walk(from, to, &trail);
    for (size_t i = std::max<size_t>(before, 1); i < trail.size(); ++i)
      length += glm::distance(trail[i - 1], trail[i]);
  };
  auto centre_of = [&](uint32_t cell, const glm::vec3& feet) {
    const glm::vec3 c = scene.cells[cell].bounds.center();
    return glm::vec3(c.x, feet.y, c.z);
  };
  std::vector<uint8_t> visited(scene.cells.size(), 0);
  uint32_t at = *start;
  // Begin in the middle of the first room, facing its door.
  visited[spot(at).cell] = 1;
  const glm::vec3 middle = centre_of(spot(at).cell, spot(at).feet);
  trail.push_back(middle);
  go(middle, spot(at).feet);
  bool climb = true;
  auto follow = [&](const std::vector<uint32_t>& route) {
    for (size_t i = 1; i < route.size() && length < wanted; ++i)
      go(spot(route[i - 1]).feet, spot(route[i]).feet);
    at = route.back();
  };
  for (int legs = 0; length < wanted && legs < 1000; ++legs) {
    std::vector<uint32_t> route;
    if (climb) {
      route = route_to(at, [&](uint32_t node) {
        return std::any_of(ups.begin(), ups.end(), [&](auto& u) { return u.first == node; });
      });
      if (!route.empty()) {
        follow(route);
        for (const auto& [a, b] : ups)
          if (a == at) {
            follow({a, b});
            break;
          }
      }
    } else {
      route = route_to(at, [&](uint32_t node) {
        const uint32_t cell = spot(node).cell;
        return is_room(cell) && !visited[cell];
      });
      if (!route.empty()) {
        follow(route);
        const uint32_t cell = spot(at).cell;
        visited[cell] = 1;
        const glm::vec3 c = centre_of(cell, spot(at).feet);
        if (walker.walk(spot(at).feet, c, nullptr)) {
          go(spot(at).feet, c);
          go(c, spot(at).feet);
        }
        follow({at, at ^ 1u});
      }
    }
    if (route.empty() && !climb) break;  // nowhere left to go
    climb = !climb;
  }
  if (trail.size() < 2) return make_error("interior path: no walkable route from the first room");

  // Frames: `speed` apart along the trail, turning towards where the walk goes.
  std::vector<double> along(trail.size(), 0.0);
  for (size_t i = 1; i < trail.size(); ++i)
    along[i] = along[i - 1] + glm::distance(trail[i - 1], trail[i]);
  auto at_distance = [&](double s) {
    s = std::clamp(s, 0.0, along.back());
    const size_t i = std::min<size_t>(
        std::upper_bound(along.begin(), along.end(), s) - along.begin(), trail.size() - 1);
    if (i == 0) return trail[0];
    const double span = along[i] - along[i - 1];
    const float t = span > 0 ? float((s - along[i - 1]) / span) : 0.0f;
    return glm::mix(trail[i - 1], trail[i], t);
  };
  auto heading = [&](double s) {
    const glm::vec3 d = at_distance(s + 1.0) - at_distance(s);
    return glm::vec2(
        float(std::atan2(d.z, d.x) * 180.0 / kPi),
        float(std::atan2(d.y, std::max(1e-3f, glm::length(glm::vec2(d.x, d.z)))) * 90.0 / kPi));
  };
  CameraPath path;
  path.kind = "interior";
  double s = 0.0;
  float yaw = heading(0.0).x, pitch = 0.0f;
  for (uint32_t k = 0; k < o.frames; ++k) {
    const glm::vec2 want = heading(s);
    float turn = std::remainder(want.x - yaw, 360.0f);
    yaw += std::clamp(turn, -kTurnDeg, kTurnDeg);
    yaw = std::fmod(yaw + 360.0f, 360.0f);
    pitch += std::clamp(want.y - pitch, -2.0f, 2.0f);
    const glm::vec3 feet = at_distance(s);
    path.frames.push_back(
        {feet + glm::vec3(0.0f, eye, 0.0f), yaw, std::clamp(pitch, -30.0f, 30.0f)});
    if (std::abs(turn) < kStandAndTurnDeg) s = std::min(s + speed, along.back());
  }
  return path;
}

}  // namespace farfield
