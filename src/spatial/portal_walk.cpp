#include "farfield/spatial/portal_walk.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace farfield {

namespace {

// Planes are pushed out by this much (metres): float rounding in the tests of boxes far from
// the origin stays inside it, so narrowing never cuts what a portal shows.
constexpr float kSlack = 1e-3f;
// An eye this close to a portal's plane, within its opening, sees through it unnarrowed.
constexpr double kOpening = 1e-2;

constexpr uint32_t kMaxClipped = kMaxPortalPoints + ConvexVolume::kMaxPlanes + 8;

struct Polygon {
  glm::dvec3 points[kMaxClipped];
  uint32_t count = 0;
};

// Sutherland-Hodgman: the part of `in` where dot(n, p) + d >= 0 (a hair outside kept too).
void clip(const Polygon& in, const glm::dvec4& plane, Polygon& out) {
  out.count = 0;
  const glm::dvec3 n(plane);
  for (uint32_t i = 0; i < in.count; ++i) {
    const glm::dvec3& a = in.points[i];
    const glm::dvec3& b = in.points[(i + 1) % in.count];
    const double da = glm::dot(n, a) + plane.w + 1e-9, db = glm::dot(n, b) + plane.w + 1e-9;
    if (da >= 0.0 && out.count < kMaxClipped) out.points[out.count++] = a;
    if ((da >= 0.0) != (db >= 0.0) && out.count < kMaxClipped)
      out.points[out.count++] = a + (b - a) * (da / (da - db));
  }
}

}  // namespace

PortalWalk::PortalWalk(const Scene& scene, const PortalWalkOptions& options)
    : scene_(scene), options_(options) {
  const size_t cells = scene.cells.size();
  first_portal_.assign(cells + 1, 0);
  for (const Portal& p : scene.portals)
    for (uint32_t c : p.cells) ++first_portal_[c + 1];
  for (size_t c = 0; c < cells; ++c) first_portal_[c + 1] += first_portal_[c];
  cell_portals_.resize(first_portal_[cells]);
  std::vector<uint32_t> fill(first_portal_.begin(), first_portal_.end() - 1);
  planes_.resize(scene.portals.size());
  for (uint32_t i = 0; i < scene.portals.size(); ++i) {
    for (uint32_t c : scene.portals[i].cells) cell_portals_[fill[c]++] = i;
    // A valid scene's portals all have a plane (validate_cells).
    planes_[i] =
        portal_plane(scene.points_of(scene.portals[i])).value_or(PortalPlane{{0, 1, 0}, 0});
  }
  in_chain_.assign(scene.portals.size(), 0);
}

void PortalWalk::walk(const View& view, uint32_t start, std::vector<CellVisit>& out) {
  out.clear();
  out_ = &out;
  eye_ = view.pose.position;
  view_projection_ = view.view_projection();
  const ConvexVolume frustum = ConvexVolume::of_view(view);
  near_plane_ = frustum.planes()[4];
  visit(start, 0, UINT32_MAX, frustum, glm::vec4(-1, -1, 1, 1));
}

void PortalWalk::visit(uint32_t cell, uint32_t depth, uint32_t via, const ConvexVolume& volume,
                       const glm::vec4& rect) {
  out_->push_back({cell, depth, via, false, volume});
  for (uint32_t p : portals_of(cell)) {
    if (in_chain_[p]) continue;
    const Portal& portal = scene_.portals[p];
    const bool forward = portal.cells[0] == cell;  // towards cells[1], the normal's back
    const uint32_t to = forward ? portal.cells[1] : portal.cells[0];
    const double side = planes_[p].signed_distance(eye_) * (forward ? 1.0 : -1.0);
    ConvexVolume narrowed;
    glm::vec4 narrowed_rect = rect;
    bool seen = false;
    if (std::abs(side) < kOpening && in_opening(p)) {
      narrowed = volume;  // the eye stands in the doorway: both sides in full
      seen = true;
    } else if (side > 0.0) {  // else the portal faces away from this side
      seen = options_.clip == PortalClip::exact
                 ? narrow_exact(p, forward, volume, narrowed)
                 : narrow_rectangle(p, rect, narrowed_rect, narrowed);
    }
    if (!seen) continue;
    if (depth + 1 > options_.max_depth || out_->size() >= options_.max_visits) {
      out_->push_back({to, depth + 1, p, true, narrowed});
      continue;
    }
    in_chain_[p] = 1;
    visit(to, depth + 1, p, narrowed, narrowed_rect);
    in_chain_[p] = 0;
  }
}

bool PortalWalk::in_opening(uint32_t p) const {
  const auto points = scene_.points_of(scene_.portals[p]);
  const glm::dvec3 n(planes_[p].normal), eye(eye_);
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 a(points[i]), b(points[(i + 1) % points.size()]);
    // Counter-clockwise about n: inside is to the left of every edge.
    if (glm::dot(glm::cross(b - a, eye - a), n) < -kOpening * glm::length(b - a)) return false;
  }
  return true;
}

bool PortalWalk::narrow_exact(uint32_t p, bool forward, const ConvexVolume& volume,
                              ConvexVolume& out) const {
  Polygon a, b;
  for (const glm::vec3& q : scene_.points_of(scene_.portals[p])) a.points[a.count++] = q;
  // Clipped by every plane but the near one: a line of sight may cross the portal nearer than
  // the near plane and still meet something beyond it.
  for (const glm::vec4& plane : volume.planes()) {
    if (plane == near_plane_) continue;
    clip(a, glm::dvec4(plane), b);
    std::swap(a, b);
    if (a.count < 3) return false;
  }
  const glm::dvec3 eye(eye_);
  glm::dvec3 centre(0.0);
  for (uint32_t i = 0; i < a.count; ++i) centre += a.points[i];
  centre /= double(a.count);

  out = ConvexVolume();
  out.add(near_plane_);
  // Beyond the portal: what lies on the eye's side of it is not seen through it.
  const PortalPlane& pp = planes_[p];
  const float sign = forward ? -1.0f : 1.0f;
  out.add(glm::vec4(pp.normal * sign, pp.offset * sign + kSlack));
  for (uint32_t i = 0; i < a.count; ++i) {
    const glm::dvec3 u = a.points[i] - eye, v = a.points[(i + 1) % a.count] - eye;
    glm::dvec3 n = glm::cross(u, v);
    const double length = glm::length(n);
    if (!(length > 1e-12 * glm::length(u) * glm::length(v))) continue;  // an edge seen end-on
    n /= length;
    if (glm::dot(n, centre - eye) < 0.0) n = -n;
    out.add(glm::vec4(glm::vec3(n), float(-glm::dot(n, eye)) + kSlack));
  }
  return true;
}

bool PortalWalk::narrow_rectangle(uint32_t p, const glm::vec4& rect, glm::vec4& out_rect,
                                  ConvexVolume& out) const {
  glm::vec2 lo(INFINITY), hi(-INFINITY);
  uint32_t behind = 0;
  const auto points = scene_.points_of(scene_.portals[p]);
  for (const glm::vec3& q : points) {
    const glm::vec4 clip = view_projection_ * glm::vec4(q, 1.0f);
    if (clip.w <= 1e-5f) {
      ++behind;
      continue;
    }
    const glm::vec2 ndc(clip.x / clip.w, clip.y / clip.w);
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
  }
  if (behind == points.size()) return false;  // wholly behind the eye
  // A corner at or behind the eye: its projection is unbounded, so the whole current
  // rectangle (the paper's screen rectangles cannot say more).
  out_rect = behind > 0 ? rect
                        : glm::vec4(std::max(lo.x, rect.x), std::max(lo.y, rect.y),
                                    std::min(hi.x, rect.z), std::min(hi.y, rect.w));
  if (!(out_rect.x < out_rect.z && out_rect.y < out_rect.w)) return false;
  const glm::mat4 m = glm::transpose(view_projection_);  // m[i] is row i
  out = ConvexVolume();
  out.add(near_plane_);
  for (const glm::vec4& plane : {m[0] - out_rect.x * m[3], out_rect.z * m[3] - m[0],
                                 m[1] - out_rect.y * m[3], out_rect.w * m[3] - m[1]}) {
    const float length = glm::length(glm::vec3(plane));
    out.add(glm::vec4(glm::vec3(plane) / length, plane.w / length + kSlack));
  }
  return true;
}

}  // namespace farfield
