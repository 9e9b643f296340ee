#include "farfield/scene/path_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "farfield/core/assert.hpp"
#include "farfield/core/text.hpp"
#include "farfield/core/view_sphere.hpp"
#include "random.hpp"

namespace farfield {

namespace {

using glm::dvec2;
constexpr double kPi = std::numbers::pi;

constexpr double kStreetSpeed = 1.5;     // m per frame: driving; 300 frames are 450 m
constexpr double kMaxTurnDeg = 10.0;     // most yaw change per frame on a street path
constexpr double kCrossingAspect = 1.5;  // a street piece no longer than this is a crossing
constexpr uint32_t kMostStraight = 2;    // crossings driven straight through in a row
constexpr double kTouch = 0.05;          // a segment's end may miss its crossing by this
                                         // fraction of the street width
constexpr uint32_t kMostFrames = 1'000'000;

double degrees(double radians) {
  return radians * 180.0 / kPi;
}
// The heading of a direction in the XZ plane (x, z), view.hpp's convention.
double yaw_of(dvec2 d) {
  return degrees(std::atan2(d.y, d.x));
}
double cross(dvec2 a, dvec2 b) {
  return a.x * b.y - a.y * b.x;
}

// ---- The street network. -------------------------------------------------------------------

struct Rect {  // in XZ
  dvec2 lo, hi;
  dvec2 center() const { return 0.5 * (lo + hi); }
  dvec2 size() const { return hi - lo; }
  bool contains(dvec2 p, double eps) const {
    return p.x >= lo.x - eps && p.y >= lo.y - eps && p.x <= hi.x + eps && p.y <= hi.y + eps;
  }
  // How far from p (inside) along the unit direction d before leaving the rectangle.
  double exit_distance(dvec2 p, dvec2 d) const {
    double t = INFINITY;
    for (int a = 0; a < 2; ++a) {
      if (d[a] > 1e-12) t = std::min(t, (hi[a] - p[a]) / d[a]);
      if (d[a] < -1e-12) t = std::min(t, (lo[a] - p[a]) / d[a]);
    }
    return std::max(t, 0.0);
  }
};

// Rectangles bucketed on a uniform grid, for "which rectangles hold this point".
class RectIndex {
 public:
  RectIndex(const std::vector<Rect>& rects, double cell) : rects_(rects), cell_(cell) {
    for (uint32_t i = 0; i < rects.size(); ++i) {
      const auto [x0, z0] = key(rects[i].lo);
      const auto [x1, z1] = key(rects[i].hi);
      for (int64_t z = z0; z <= z1; ++z)
        for (int64_t x = x0; x <= x1; ++x) cells_[pack(x, z)].push_back(i);
    }
  }
  // Calls f(i) for each rectangle within eps of p (eps below one cell).
  template <class F>
  void near(dvec2 p, double eps, F&& f) const {
    const auto [x0, z0] = key(p - eps);
    const auto [x1, z1] = key(p + eps);
    for (int64_t z = z0; z <= z1; ++z) {
      for (int64_t x = x0; x <= x1; ++x) {
        const auto it = cells_.find(pack(x, z));
        if (it == cells_.end()) continue;
        for (uint32_t i : it->second)
          if (rects_[i].contains(p, eps)) f(i);
      }
    }
  }

 private:
  std::pair<int64_t, int64_t> key(dvec2 p) const {
    return {int64_t(std::floor(p.x / cell_)), int64_t(std::floor(p.y / cell_))};
  }
  static uint64_t pack(int64_t x, int64_t z) { return (uint64_t(x) << 32) ^ uint64_t(uint32_t(z)); }

  const std::vector<Rect>& rects_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// Crossings (nodes) joined by segments (edges); a segment's end touches its crossing.
struct Network {
  std::vector<Rect> streets;  // every street object
  std::vector<float> tops;    // street top (bounds max y) of each
  std::vector<Rect> crossings;
  std::vector<std::vector<uint32_t>> edges_of;  // per crossing: segment numbers
  struct Segment {
    uint32_t crossing[2];
    dvec2 end[2];  // the middle of the end touching crossing[k]
  };
  std::vector<Segment> segments;
  double cell = 1.0;  // of the street index: the widest street piece's short side
};

Network build_network(const Scene& scene) {
  Network net;
  std::vector<Rect> elongated;
  for (const Object& o : scene.objects) {
    if (o.kind != ObjectKind::street || o.bounds.empty()) continue;
    const Rect r{{o.bounds.min.x, o.bounds.min.z}, {o.bounds.max.x, o.bounds.max.z}};
    const double shorter = std::min(r.size().x, r.size().y);
    const double longer = std::max(r.size().x, r.size().y);
    if (shorter <= 0.0) continue;  // no surface to stand on
    net.streets.push_back(r);
    net.tops.push_back(o.bounds.max.y);
    net.cell = std::max(net.cell, shorter);
    (longer <= kCrossingAspect * shorter ? net.crossings : elongated).push_back(r);
  }
  net.edges_of.resize(net.crossings.size());
  double crossing_cell = 1e-3;
  for (const Rect& c : net.crossings)
    crossing_cell = std::max({crossing_cell, c.size().x, c.size().y});
  const RectIndex index(net.crossings, crossing_cell);
  for (const Rect& r : elongated) {
    const bool along_x = r.size().x > r.size().y;
    const double width = along_x ? r.size().y : r.size().x;
    const dvec2 c = r.center();
    const dvec2 ends[2] = {along_x ? dvec2(r.lo.x, c.y) : dvec2(c.x, r.lo.y),
                           along_x ? dvec2(r.hi.x, c.y) : dvec2(c.x, r.hi.y)};
    Network::Segment s{};
    bool joined = true;
    for (int k = 0; k < 2 && joined; ++k) {
      double best = INFINITY;
      index.near(ends[k], kTouch * width, [&](uint32_t i) {
        const double d = glm::length(net.crossings[i].center() - ends[k]);
        if (d < best) best = d, s.crossing[k] = i;
      });
      s.end[k] = ends[k];
      joined = best < INFINITY;
    }
    if (!joined || s.crossing[0] == s.crossing[1]) continue;
    for (uint32_t c2 : s.crossing) net.edges_of[c2].push_back(uint32_t(net.segments.size()));
    net.segments.push_back(s);
  }
  return net;
}

// ---- The drive: lines, arcs through crossings, turns on the spot. --------------------------

struct Piece {
  enum Type { line, arc, turn } type;
  dvec2 a;            // line: start; arc: centre; turn: where
  dvec2 b;            // line: end
  double radius = 0;  // arc
  double angle0 = 0;  // arc: polar angle of the start about the centre; turn: start yaw, rad
  double sweep = 0;   // arc, turn: signed, rad
  double frames = 0;  // how long it takes
};

// Takes the route's corners one at a time and rounds each into an arc inside its crossing,
// so the camera turns smoothly and never leaves the street. The speed on an arc drops so that
// the yaw changes by at most kMaxTurnDeg per frame.
class Drive {
 public:
  explicit Drive(double speed) : speed_(speed) {}

  // A corner of the route; `crossing` is where it may be rounded, or null (turn on the spot).
  void add(dvec2 p, const Rect* crossing) {
    if (count_ > 0 && glm::length(p - corner_.p) < 1e-9) return;
    const Corner next{p, crossing};
    if (count_ == 0) {
      at_ = p;
    } else if (count_ >= 2) {
      const dvec2 u = glm::normalize(corner_.p - before_.p), v = glm::normalize(p - corner_.p);
      if (std::abs(cross(u, v)) < 1e-9 && glm::dot(u, v) > 0.0) {  // straight on
        corner_ = next;
        return;
      }
      round(u, v, next);
      before_ = corner_;
    } else {
      before_ = corner_;
    }
    corner_ = next;
    ++count_;
  }
  // Drives to the last corner.
  void finish() {
    if (count_ > 0) line(corner_.p);
  }
  double frames() const { return frames_; }
  const std::vector<Piece>& pieces() const { return pieces_; }

 private:
  struct Corner {
    dvec2 p;
    const Rect* crossing;
  };

  void round(dvec2 u, dvec2 v, const Corner& next) {
    const dvec2 c = corner_.p;
    const double theta = std::acos(std::clamp(glm::dot(u, v), -1.0, 1.0));
    const double turn_rate = kMaxTurnDeg * kPi / 180.0;
    double t = 0.0;  // tangent length: the arc runs from c - t u to c + t v
    if (corner_.crossing && theta < kPi - 1e-3) {
      t = 0.95 *
          std::min(corner_.crossing->exit_distance(c, -u), corner_.crossing->exit_distance(c, v));
      t = std::min({t, 0.5 * glm::length(c - before_.p), 0.5 * glm::length(next.p - c)});
    }
    if (t <= 1e-6) {  // a dead end or a corner outside a crossing: stop and turn
      line(c);
      const double sweep = theta >= kPi - 1e-3 ? kPi : std::copysign(theta, cross(u, v));
      pieces_.push_back({Piece::turn, c, c, 0, std::atan2(u.y, u.x), sweep, theta / turn_rate});
      frames_ += pieces_.back().frames;
      return;
    }
    const double radius = t / std::tan(0.5 * theta), side = cross(u, v) > 0 ? 1.0 : -1.0;
    const dvec2 start = c - t * u;
    const dvec2 centre = start + side * radius * dvec2(-u.y, u.x);
    line(start);
    const double length = radius * theta;
    const double frames = length / std::min(speed_, radius * turn_rate);
    const dvec2 r0 = start - centre;
    pieces_.push_back(
        {Piece::arc, centre, {}, radius, std::atan2(r0.y, r0.x), side * theta, frames});
    frames_ += frames;
    at_ = c + t * v;
  }

  void line(dvec2 to) {
    const double length = glm::length(to - at_);
    if (length > 1e-9) {
      pieces_.push_back({Piece::line, at_, to, 0, 0, 0, length / speed_});
      frames_ += pieces_.back().frames;
    }
    at_ = to;
  }

  double speed_;
  std::vector<Piece> pieces_;
  double frames_ = 0.0;
  Corner before_{}, corner_{};
  dvec2 at_{0.0};
  uint32_t count_ = 0;
};

// Position and yaw (degrees) a fraction f through a piece.
void sample(const Piece& p, double f, dvec2& position, double& yaw) {
  switch (p.type) {
    case Piece::line:
      position = p.a + (p.b - p.a) * f;
      yaw = yaw_of(p.b - p.a);
      return;
    case Piece::arc: {
      const double angle = p.angle0 + p.sweep * f;
      const dvec2 radial(std::cos(angle), std::sin(angle));
      position = p.a + p.radius * radial;
      yaw = yaw_of(p.sweep > 0 ? dvec2(-radial.y, radial.x) : dvec2(radial.y, -radial.x));
      return;
    }
    case Piece::turn:
      position = p.a;
      yaw = degrees(p.angle0 + p.sweep * f);
      return;
  }
}

double wrap_degrees(double yaw) {  // into (-180, 180]
  yaw = std::remainder(yaw, 360.0);
  return yaw == -180.0 ? 180.0 : yaw;
}

Result<CameraPath> street_path(const Scene& scene, const PathOptions& o) {
  const Network net = build_network(scene);
  if (net.streets.empty())
    return make_error(
        "street paths need street objects, e.g. a generated city; use --kind fly "
        "or orbit");
  // Start at the joined crossing nearest the middle of the scene.
  const dvec2 middle(scene.bounds.center().x, scene.bounds.center().z);
  uint32_t at = UINT32_MAX;
  double best = INFINITY;
  for (uint32_t i = 0; i < net.crossings.size(); ++i) {
    const double d = glm::length(net.crossings[i].center() - middle);
    if (!net.edges_of[i].empty() && d < best) best = d, at = i;
  }
  if (at == UINT32_MAX)
    return make_error("street paths need crossings joined by streets; the scene has ",
                      std::to_string(net.streets.size()), " street objects, ",
                      std::to_string(net.crossings.size()),
                      " of them roughly square "
                      "(crossings), none joined by an elongated one; use --kind fly or orbit");

  // Walk the graph: at each crossing a random segment; not back the way we came unless it is
  // a dead end; a turn after kMostStraight crossings straight on; one not driven yet where
  // there is one, to see more of the city.
  const double speed = o.speed > 0.0 ? o.speed : kStreetSpeed;
  detail::Rng rng(o.seed);
  Drive drive(speed);
  drive.add(net.crossings[at].center(), &net.crossings[at]);
  std::vector<uint8_t> driven(net.segments.size(), 0);
  std::vector<uint32_t> options;
  auto keep = [&](auto&& wanted) {  // narrows the options to the wanted ones, if any
    const auto end = std::stable_partition(options.begin(), options.end(), wanted);
    if (end != options.begin()) options.erase(end, options.end());
  };
  auto leaving = [&](uint32_t e) {  // the segment's direction away from `at`
    const Network::Segment& s = net.segments[e];
    const int from = s.crossing[0] == at ? 0 : 1;
    return glm::normalize(s.end[1 - from] - s.end[from]);
  };
  uint32_t came = UINT32_MAX, straight = 0;
  dvec2 heading(0.0);
  // At least one segment, so that even a one-frame path looks along a street.
  while (came == UINT32_MAX || drive.frames() < double(o.frames - 1)) {
    options = net.edges_of[at];
    keep([&](uint32_t e) { return e != came; });
    auto is_straight = [&](uint32_t e) { return glm::dot(leaving(e), heading) > 0.9; };
    if (straight >= kMostStraight) keep([&](uint32_t e) { return !is_straight(e); });
    keep([&](uint32_t e) { return !driven[e]; });
    const uint32_t e = options[rng.range(0, uint32_t(options.size() - 1))];
    straight = is_straight(e) ? straight + 1 : 0;
    heading = leaving(e);
    const Network::Segment& s = net.segments[e];
    const int from = s.crossing[0] == at ? 0 : 1;
    at = s.crossing[1 - from];
    drive.add(s.end[from], nullptr);
    drive.add(s.end[1 - from], nullptr);
    drive.add(net.crossings[at].center(), &net.crossings[at]);
    driven[e] = 1;
    came = e;
  }
  drive.finish();

  CameraPath path;
  path.kind = "street";
  path.frames.resize(o.frames);
  const RectIndex streets(net.streets, net.cell);
  const std::vector<Piece>& pieces = drive.pieces();
  FF_ASSERT(!pieces.empty(), "a drive along a segment of %g m has no pieces",
            glm::length(net.segments[came].end[1] - net.segments[came].end[0]));
  size_t piece = 0;
  double piece_start = 0.0;
  float top = 0.0f;
  for (uint32_t k = 0; k < o.frames; ++k) {
    while (piece + 1 < pieces.size() && k > piece_start + pieces[piece].frames)
      piece_start += pieces[piece++].frames;
    const double f = std::clamp((k - piece_start) / pieces[piece].frames, 0.0, 1.0);
    dvec2 p(0.0);
    double yaw = 0.0;
    sample(pieces[piece], f, p, yaw);
    // Eye height above the highest street piece under the eye (the last one if a sloppy
    // scene leaves a crack between a segment and its crossing).
    float here = -INFINITY;
    streets.near(p, 1e-3, [&](uint32_t i) { here = std::max(here, net.tops[i]); });
    if (here > -INFINITY) top = here;
    FF_ASSERT(k > 0 || here > -INFINITY, "the start (%g, %g) is on no street", p.x, p.y);
    CameraPose& pose = path.frames[k];
    pose.position = {float(p.x), float(top + o.eye_height), float(p.y)};
    pose.yaw_deg = float(wrap_degrees(yaw));
    pose.pitch_deg = 0.0f;  // looking along the street
  }
  return path;
}

// ---- Above the scene. ----------------------------------------------------------------------

// Distance along the loop of each frame: evenly over one loop, or `speed` apart.
double loop_distance(uint32_t k, const PathOptions& o, double length) {
  return o.speed > 0.0 ? std::fmod(k * o.speed, length) : length * k / o.frames;
}

// A pose at `eye` looking at `target`.
CameraPose looking_at(const glm::dvec3& eye, const glm::dvec3& target) {
  const glm::dvec3 to = target - eye;
  CameraPose pose;
  pose.position = glm::vec3(eye);
  pose.yaw_deg = float(wrap_degrees(yaw_of({to.x, to.z})));
  pose.pitch_deg = float(degrees(std::atan2(to.y, std::hypot(to.x, to.z))));
  return pose;
}

// Fly and orbit scale with the scene alone (no constant in metres), so a 1 m model and a
// 10 km city are seen alike.
CameraPath fly_path(const Scene& scene, const PathOptions& o) {
  const glm::dvec3 c(scene.bounds.center()), size(scene.bounds.size());
  const double extent = std::max({size.x, size.z, 1e-3});
  const double a = std::max(0.35 * size.x, 0.05 * extent),
               b = std::max(0.35 * size.z, 0.05 * extent);
  const double y = scene.bounds.max.y + 0.25 * extent;
  // Arc length along the ellipse, tabulated, so frames are evenly spaced in metres.
  constexpr int kSteps = 4096;
  std::vector<double> s(kSteps + 1, 0.0);
  auto at = [&](double phi) { return dvec2(a * std::cos(phi), b * std::sin(phi)); };
  for (int i = 1; i <= kSteps; ++i)
    s[i] = s[i - 1] + glm::length(at(2 * kPi * i / kSteps) - at(2 * kPi * (i - 1) / kSteps));
  CameraPath path;
  path.kind = "fly";
  path.frames.resize(o.frames);
  for (uint32_t k = 0; k < o.frames; ++k) {
    const double d = loop_distance(k, o, s[kSteps]);
    const size_t i =
        std::clamp<size_t>(std::upper_bound(s.begin(), s.end(), d) - s.begin(), 1, kSteps);
    const double f = (d - s[i - 1]) / std::max(s[i] - s[i - 1], 1e-12);
    const double phi = 2 * kPi * (i - 1 + f) / kSteps;
    const dvec2 p = at(phi);
    // Ahead and inwards: halfway to the loop's point a quarter turn on, at mid height, so
    // that the scene's middle stays in sight.
    const dvec2 ahead = 0.5 * at(phi + 0.5 * kPi);
    path.frames[k] = looking_at({c.x + p.x, y, c.z + p.y}, {c.x + ahead.x, c.y, c.z + ahead.y});
  }
  return path;
}

}  // namespace

double whole_view_distance(const Bounds3& bounds) {
  const double sphere = std::max(0.5 * glm::length(glm::dvec3(bounds.size())), 1e-3);
  const double half_fov = std::atan(0.75);  // tan(45 degrees) x 3/4: the narrower, vertical
  return 1.05 * sphere / std::sin(half_fov);
}

namespace {

CameraPath orbit_path(const Scene& scene, const PathOptions& o) {
  // The whole scene in view, from 25 degrees above the horizon, on the sphere of paper 003's
  // viewpoints (core/view_sphere.hpp): with 72 frames, every frame is one of them.
  const double distance = whole_view_distance(scene.bounds);
  const double radius = distance * std::cos(25.0 * kPi / 180.0);
  CameraPath path;
  path.kind = "orbit";
  path.frames.resize(o.frames);
  for (uint32_t k = 0; k < o.frames; ++k) {
    const double angle_deg = o.speed > 0.0
                                 ? degrees(loop_distance(k, o, 2 * kPi * radius) / radius)
                                 : 360.0 * k / o.frames;
    path.frames[k] =
        pose_on_sphere(scene.bounds.center(), float(distance), float(angle_deg), 25.0f);
  }
  return path;
}

}  // namespace

Result<void> validate_path_options(const PathOptions& o) {
  if (o.kind != "street" && o.kind != "fly" && o.kind != "orbit" && o.kind != "interior")
    return make_error("--kind must be street, fly, orbit or interior (got \"", o.kind, "\")");
  if (o.frames == 0) return make_error("--frames must be at least 1");
  if (o.frames > kMostFrames)
    return make_error("--frames must be at most ", std::to_string(kMostFrames), " (got ",
                      std::to_string(o.frames), ")");
  if (!(std::isfinite(o.speed) && o.speed >= 0.0))
    return make_error("--speed must be a finite number >= 0, in metres per frame (got ",
                      number_text(o.speed), ")");
  if (!(std::isfinite(o.eye_height) && o.eye_height > 0.0))
    return make_error("--eye-height must be a finite number > 0, in metres (got ",
                      number_text(o.eye_height), ")");
  return {};
}

Result<CameraPath> generate_path(const Scene& scene, const PathOptions& options) {
  if (auto ok = validate_path_options(options); !ok) return ok.error();
  if (options.kind == "interior")
    return make_error("interior paths are made by interior_path (spatial/interior_path.hpp)");
  if (scene.bounds.empty())
    return make_error("the scene is empty: there is nothing to walk around");
  if (options.kind == "fly") return fly_path(scene, options);
  if (options.kind == "orbit") return orbit_path(scene, options);
  return street_path(scene, options);
}

}  // namespace farfield
