#include "farfield/techniques/stratified/stratified_options.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::stratified {

namespace {

Result<std::vector<double>> numbers(const std::string& key, const std::string& text, size_t count) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(v))
      return make_error("--set stratified.", key, ": '", part, "' is not a number");
    out.push_back(v);
  }
  if (out.size() != count)
    return make_error("--set stratified.", key, ": expected ", std::to_string(count),
                      " comma-separated numbers (got '", text, "')");
  return out;
}

}  // namespace

const char* style_name(Style style) {
  switch (style) {
    case Style::full:
      return "full";
    case Style::near_only:
      return "near";
    case Style::far_objects:
      return "far-objects";
    case Style::far_texture:
      return "far-texture";
    case Style::brute:
      return "brute";
  }
  return "?";
}

// The descriptor's table (stratified_technique.cpp registers it).
std::span<const SettingSpec> stratified_settings() {
  static constexpr SettingSpec kSettings[] = {
      {.key = "alpha",
       .type = SettingType::number,
       .default_value = "2",
       .help = "largest angular error of a far point seen from anywhere in its viewcell",
       .unit = "deg",
       .symbol = "alpha_max (000, Eq. 2.2)",
       .min = 0,
       .max = 90,
       .min_open = true,
       .max_open = true,
       .baked = true},
      {.key = "box",
       .type = SettingType::number,
       .default_value = "0",
       .help = "side of the far-field box around a viewcell (the innermost with shells); 0: "
               "from the scene, the box whose near triangles in view number near_triangles "
               "at the scene's mean density over the ground (000, Sec. 2.4.2)",
       .unit = "m",
       .symbol = "b (000, Sec. 2.2)",
       .min = 0,
       .baked = true},
      {.key = "near_triangles",
       .type = SettingType::integer,
       .default_value = "16000",
       .help = "with box=0: the near triangles in view a frame should draw, which sizes the box "
               "(16000 gives the paper's 240 m on the default city)",
       .symbol = "p (000, Eq. 2.3)",
       .min = 1,
       .max = 1000000000,
       .baked = true},
      {.key = "viewcell",
       .type = SettingType::number,
       .default_value = "0",
       .help = "viewcell side; 0: from alpha and the box (see sizing)",
       .unit = "m",
       .symbol = "v (000, Eq. 2.2)",
       .min = 0,
       .baked = true},
      {.key = "sizing",
       .type = SettingType::choice,
       .default_value = "strict",
       .help = "viewcell length from the strict 3D bound, or from the paper's Eq. 2.2",
       .choices = "strict|paper",
       .baked = true},
      {.key = "resolution",
       .type = SettingType::integer,
       .default_value = "512",
       .help = "pixels per box side",
       .unit = "px",
       .min = 8,
       .max = 4096,
       .baked = true},
      {.key = "codec",
       .type = SettingType::choice,
       .default_value = "jpeg",
       .help = "how box sides are stored",
       .choices = "jpeg|png",
       .baked = true},
      {.key = "quality",
       .type = SettingType::integer,
       .default_value = "85",
       .help = "JPEG quality of the box sides",
       .min = 1,
       .max = 100,
       .baked = true},
      {.key = "delta",
       .type = SettingType::flag,
       .default_value = "0",
       .help = "PNG residuals against a neighbouring viewcell (000, Sec. 3.1.4; needs codec=png)",
       .baked = true},
      {.key = "band",
       .type = SettingType::text,
       .default_value = "auto",
       .help = "navigable heights: auto (street where the scene has streets and the path, if "
               "any, stays in the bottom 3 m; else the path's heights +-1.5 m), "
               "street (the bottom 3 m), all, or Y0,Y1",
       .unit = "m",
       .baked = true},
      {.key = "far_share",
       .type = SettingType::number,
       .default_value = "0.05",
       .help = "refuse a bake whose far fields would hold less than this share of the scene's "
               "triangles (nothing worth baking); 0 bakes anyway (bake only)",
       .min = 0,
       .max = 1,
       .max_open = true},
      {.key = "path",
       .type = SettingType::text,
       .default_value = "",
       .help = "bake only the viewcells this camera path passes through (bake only)"},
      {.key = "limit",
       .type = SettingType::text,
       .default_value = "",
       .help = "bake only the viewcells meeting the rectangle X0,Z0,X1,Z1 (bake only)",
       .unit = "m"},
      {.key = "shells",
       .type = SettingType::integer,
       .default_value = "1",
       .help = "nested shells of boxes (000, Ch. 4)",
       .min = 1,
       .max = 16,
       .baked = true},
      {.key = "spacing",
       .type = SettingType::choice,
       .default_value = "exponential",
       .help = "box lengths of the shells",
       .choices = "linear|exponential",
       .baked = true},
      {.key = "factor",
       .type = SettingType::number,
       .default_value = "0",
       .help = "box growth from shell to shell; 0: the paper's 1.13 (exponential) or 1.72 "
               "(linear) (000, Sec. 4.2.1)",
       .min = 0,
       .baked = true},
      {.key = "style",
       .type = SettingType::choice,
       .default_value = "full",
       .help = "what the walk draws (000, Sec. 5.1)",
       .choices = "full|near|far-objects|far-texture|brute"},
      {.key = "blend",
       .type = SettingType::integer,
       .default_value = "0",
       .help = "fade a new far field in over this many frames (000, Sec. 7.1)",
       .unit = "frames",
       .min = 0,
       .max = 120},
      {.key = "lookahead",
       .type = SettingType::integer,
       .default_value = "2",
       .help = "viewcells prefetched ahead along the velocity (000, Sec. 3.2.1)",
       .unit = "viewcells",
       .min = 0,
       .max = 16},
  };
  return kSettings;
}

Result<StratifiedOptions> stratified_options(const SettingValues& v) {
  StratifiedOptions o;
  o.alpha_deg = v.number("alpha");
  o.box = v.number("box");
  o.near_triangles = v.integer("near_triangles");
  o.far_share = v.number("far_share");
  o.viewcell = v.number("viewcell");
  o.paper_sizing = v.text("sizing") == "paper";
  o.resolution = v.integer("resolution");
  const bool png = v.text("codec") == "png";
  o.codec = png ? ImageCodec::png() : ImageCodec::jpeg(v.integer("quality"));
  o.delta = v.flag("delta");
  o.band = v.text("band");
  if (o.band != "auto")
    if (auto band = navigable_region(o.band, Bounds3{{0, 0, 0}, {1, 1, 1}}); !band)
      return band.error();
  o.path = v.text("path");
  if (const std::string& limit = v.text("limit"); !limit.empty()) {
    auto c = numbers("limit", limit, 4);
    if (!c) return c.error();
    if (!((*c)[0] < (*c)[2] && (*c)[1] < (*c)[3]))
      return make_error("--set stratified.limit=X0,Z0,X1,Z1 needs X0 < X1 and Z0 < Z1");
    o.limit =
        Bounds3{{float((*c)[0]), -1e30f, float((*c)[1])}, {float((*c)[2]), 1e30f, float((*c)[3])}};
  }
  o.shells = v.integer("shells");
  o.spacing = v.text("spacing") == "linear" ? Spacing::linear : Spacing::exponential;
  o.factor = v.number("factor");
  if (o.factor != 0 && !(o.factor > 1))
    return make_error("--set stratified.factor must be > 1 (or 0 for the paper's)");
  for (Style s :
       {Style::full, Style::near_only, Style::far_objects, Style::far_texture, Style::brute})
    if (v.text("style") == style_name(s)) o.style = s;
  o.blend_frames = v.integer("blend");
  o.lookahead = v.integer("lookahead");
  if (o.delta && !png)
    return make_error(
        "--set stratified.delta=1 needs stratified.codec=png: differences of "
        "JPEG images would add up their losses");
  if (o.factor == 0) o.factor = o.spacing == Spacing::linear ? 1.72 : 1.13;  // Sec. 4.2.1
  if (o.viewcell > 0 && o.box > 0 && o.viewcell > o.box)
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
  if (!v)
    return make_error("--set stratified.band must be auto, street, all or Y0,Y1 (got '", band,
                      "')");
  if (!((*v)[0] < (*v)[1]))
    return make_error("--set stratified.band=Y0,Y1 needs Y0 < Y1 (got '", band, "')");
  region.min.y = float((*v)[0]);
  region.max.y = float((*v)[1]);
  return region;
}

}  // namespace farfield::stratified
