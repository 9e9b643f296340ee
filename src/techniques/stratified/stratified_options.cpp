#include "farfield/techniques/stratified/stratified_options.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "farfield/techniques/technique.hpp"

namespace farfield::stratified {

namespace {

Result<std::vector<double>> numbers(const std::string& key, const std::string& text, size_t count) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    auto v = setting_number("stratified", key, part);
    if (!v) return v.error();
    out.push_back(*v);
  }
  if (out.size() != count)
    return make_error("--set stratified.", key, ": expected ", std::to_string(count),
                      " comma-separated numbers (got '", text, "')");
  return out;
}

}  // namespace

const char* style_name(Style style) {
  switch (style) {
    case Style::full: return "full";
    case Style::near_only: return "near";
    case Style::far_objects: return "far-objects";
    case Style::far_texture: return "far-texture";
    case Style::brute: return "brute";
  }
  return "?";
}

Result<StratifiedOptions> stratified_options(const std::map<std::string, std::string>& settings) {
  StratifiedOptions o;
  int quality = 85;
  std::string codec = "jpeg";
  for (const auto& setting : settings) {
    const std::string& key = setting.first;  // named, not bound: lambdas below capture them
    const std::string& text = setting.second;
    if (key == "codec") {
      if (text != "jpeg" && text != "png")
        return make_error("--set stratified.codec must be jpeg or png (got '", text, "')");
      codec = text;
    } else if (key == "band") {
      o.band = text;
    } else if (key == "path") {
      o.path = text;
    } else if (key == "limit") {
      auto v = numbers(key, text, 4);
      if (!v) return v.error();
      const auto& c = *v;
      if (!(c[0] < c[2] && c[1] < c[3]))
        return make_error("--set stratified.limit=X0,Z0,X1,Z1 needs X0 < X1 and Z0 < Z1");
      o.limit = Bounds3{{float(c[0]), -1e30f, float(c[1])}, {float(c[2]), 1e30f, float(c[3])}};
    } else if (key == "sizing") {
      if (text != "strict" && text != "paper")
        return make_error("--set stratified.sizing must be strict or paper (got '", text, "')");
      o.paper_sizing = text == "paper";
    } else if (key == "spacing") {
      if (text != "linear" && text != "exponential")
        return make_error("--set stratified.spacing must be linear or exponential (got '", text,
                          "')");
      o.spacing = text == "linear" ? Spacing::linear : Spacing::exponential;
    } else if (key == "style") {
      bool found = false;
      for (Style s : {Style::full, Style::near_only, Style::far_objects, Style::far_texture,
                      Style::brute})
        if (text == style_name(s)) o.style = s, found = true;
      if (!found)
        return make_error("--set stratified.style must be full, near, far-objects, far-texture "
                          "or brute (got '", text, "')");
    } else {
      auto v = setting_number("stratified", key, text);
      if (!v) return v.error();
      const double x = *v;
      auto whole = [&](double lo, double hi) -> Result<int> {
        if (x != std::floor(x) || x < lo || x > hi)
          return make_error("--set stratified.", key, " must be a whole number from ",
                            std::to_string(int(lo)), " to ", std::to_string(int(hi)), " (got '",
                            text, "')");
        return int(x);
      };
      if (key == "alpha") {
        if (!(x > 0 && x < 90))
          return make_error("--set stratified.alpha: alpha_max must be in (0, 90) degrees");
        o.alpha_deg = x;
      } else if (key == "box") {
        if (!(x > 0)) return make_error("--set stratified.box must be > 0 metres");
        o.box = x;
      } else if (key == "viewcell") {
        if (!(x >= 0)) return make_error("--set stratified.viewcell must be >= 0 metres");
        o.viewcell = x;
      } else if (key == "resolution") {
        auto r = whole(8, 4096);
        if (!r) return r.error();
        o.resolution = *r;
      } else if (key == "quality") {
        auto q = whole(1, 100);
        if (!q) return q.error();
        quality = *q;
      } else if (key == "delta") {
        auto d = whole(0, 1);
        if (!d) return d.error();
        o.delta = *d == 1;
      } else if (key == "shells") {
        auto n = whole(1, 16);
        if (!n) return n.error();
        o.shells = *n;
      } else if (key == "factor") {
        if (!(x > 1)) return make_error("--set stratified.factor must be > 1");
        o.factor = x;
      } else if (key == "blend") {
        auto n = whole(0, 120);
        if (!n) return n.error();
        o.blend_frames = *n;
      } else if (key == "lookahead") {
        auto n = whole(0, 16);
        if (!n) return n.error();
        o.lookahead = *n;
      } else {
        return make_error("--set stratified.", key, ": unknown setting (known: alpha, box, "
                          "viewcell, sizing, resolution, codec, quality, delta, band, path, limit, "
                          "shells, spacing, factor, style, blend, lookahead)");
      }
    }
  }
  o.codec = codec == "png" ? ImageCodec::png() : ImageCodec::jpeg(quality);
  if (o.delta && codec != "png")
    return make_error("--set stratified.delta=1 needs stratified.codec=png: differences of "
                      "JPEG images would add up their losses");
  if (o.shells > 1 && o.factor == 1.0)
    o.factor = o.spacing == Spacing::linear ? 1.72 : 1.13;  // the paper's (Sec. 4.2.1)
  if (o.viewcell > 0 && o.viewcell > o.box)
    return make_error("--set stratified.viewcell (", std::to_string(o.viewcell),
                      " m) must not exceed stratified.box (", std::to_string(o.box), " m)");
  return o;
}

Result<Bounds3> navigable_region(const std::string& band, const Bounds3& scene) {
  if (scene.empty()) return make_error("the scene is empty: there is nowhere to walk");
  Bounds3 region = scene;
  if (band == "all") return region;
  if (band == "street") {
    region.max.y = region.min.y + 3.0f;
    return region;
  }
  auto v = numbers("band", band, 2);
  if (!v) return make_error("--set stratified.band must be street, all or Y0,Y1 (got '", band, "')");
  if (!((*v)[0] < (*v)[1]))
    return make_error("--set stratified.band=Y0,Y1 needs Y0 < Y1 (got '", band, "')");
  region.min.y = float((*v)[0]);
  region.max.y = float((*v)[1]);
  return region;
}

}  // namespace farfield::stratified
