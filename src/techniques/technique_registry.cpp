// Names of the techniques and how to make them.
#include <array>
#include <cmath>
#include <cstdlib>

#include "brute/brute_technique.hpp"
#include "colorcube/colorcube_technique.hpp"
#include "farfield/techniques/technique.hpp"
#include "octree/octree_technique.hpp"
#include "stratified/stratified_technique.hpp"

namespace farfield {

namespace {

constexpr std::array kTechniques = {
    TechniqueInfo{"brute", "every object every frame (the reference)"},
    TechniqueInfo{"octree", "octree frustum culling, paper 004 (plane test, objects of partial "
                            "leaves tested)"},
    TechniqueInfo{"octree-paper", "octree culling with paper 004's own corner-projection test, "
                                  "whole leaves drawn"},
    TechniqueInfo{"colorcube", "colour-cube octree, paper 002 (settings: colorcube.depth, cluster, "
                               "oversampling, coverage, threshold, alpha, pixels, threads)"},
    TechniqueInfo{"stratified", "viewcells with far-field boxes, paper 000; needs a bake (settings: "
                                "stratified.alpha, box, viewcell, sizing, resolution, codec, quality, "
                                "delta, band, path, limit, shells, spacing, factor, style, blend, "
                                "lookahead)"},
};

}  // namespace

std::span<const TechniqueInfo> known_techniques() { return kTechniques; }

Result<void> Technique::bake(const Scene&, Store&, Progress&) {
  return make_error("technique '", std::string(name()), "' has nothing to bake; it loads in ",
                    "moments from the scene");
}

Result<void> Technique::load_baked(const Scene& scene, const Store&) { return load(scene); }

Result<void> TechniqueSettings::add(const std::string& assignment) {
  const size_t dot = assignment.find('.'), equals = assignment.find('=');
  if (dot == std::string::npos || equals == std::string::npos || dot == 0 || equals < dot + 2)
    return make_error("--set '", assignment, "': expected TECHNIQUE.KEY=VALUE");
  values[assignment.substr(0, equals)] = assignment.substr(equals + 1);
  return {};
}

Result<double> setting_number(std::string_view technique, const std::string& key,
                              const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    return make_error("--set ", std::string(technique), ".", key, ": '", text,
                      "' is not a number");
  return v;
}

std::map<std::string, std::string> TechniqueSettings::for_technique(std::string_view technique) const {
  std::map<std::string, std::string> mine;
  const std::string prefix = std::string(technique) + ".";
  for (const auto& [key, value] : values)
    if (key.compare(0, prefix.size(), prefix) == 0) mine[key.substr(prefix.size())] = value;
  return mine;
}

Result<std::unique_ptr<Technique>> make_technique(std::string_view name,
                                                  const TechniqueSettings& settings) {
  const auto mine = settings.for_technique(name);
  if (name == "colorcube") {
    auto options = colorcube_options(mine);
    if (!options) return options.error();
    return std::unique_ptr<Technique>(std::make_unique<ColorcubeTechnique>(*options));
  }
  if (name == "stratified") {
    auto options = stratified::stratified_options(mine);
    if (!options) return options.error();
    return std::unique_ptr<Technique>(std::make_unique<StratifiedTechnique>(*options));
  }
  if (!mine.empty())
    return make_error("--set ", std::string(name), ".", mine.begin()->first, ": ",
                      std::string(name), " has no settings");
  if (name == "brute") return std::unique_ptr<Technique>(std::make_unique<BruteTechnique>());
  if (name == "octree")
    return std::unique_ptr<Technique>(
        std::make_unique<OctreeTechnique>("octree", OctreeTechniqueOptions{}));
  if (name == "octree-paper") {
    OctreeTechniqueOptions options;
    options.paper_visibility_test = true;
    options.test_objects_in_leaves = false;
    return std::unique_ptr<Technique>(std::make_unique<OctreeTechnique>("octree-paper", options));
  }
  std::string known;
  for (const auto& t : kTechniques) {
    if (!known.empty()) known += ", ";
    known += t.name;
  }
  return make_error("unknown technique '", std::string(name), "' (known: ", known, ")");
}

}  // namespace farfield
