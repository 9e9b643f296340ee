// Names of the techniques and how to make them.
#include <array>

#include "brute/brute_technique.hpp"
#include "farfield/techniques/technique.hpp"
#include "octree/octree_technique.hpp"

namespace farfield {

namespace {

constexpr std::array kTechniques = {
    TechniqueInfo{"brute", "every object every frame (the reference)"},
    TechniqueInfo{"octree", "octree frustum culling, paper 004 (plane test, objects of partial "
                            "leaves tested)"},
    TechniqueInfo{"octree-paper", "octree culling with paper 004's own corner-projection test, "
                                  "whole leaves drawn"},
};

}  // namespace

std::span<const TechniqueInfo> known_techniques() { return kTechniques; }

Result<std::unique_ptr<Technique>> make_technique(std::string_view name) {
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
