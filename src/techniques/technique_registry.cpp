// The techniques of this build: one line each (docs/techniques/README.md).
#include <array>

#include "brute/brute_technique.hpp"
#include "clusters/clusters_technique.hpp"
#include "colorcube/colorcube_technique.hpp"
#include "composite/composite_technique.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "hybrid/hybrid_technique.hpp"
#include "ibr/ibr_technique.hpp"
#include "octree/octree_technique.hpp"
#include "portal/portal_technique.hpp"
#include "stratified/stratified_technique.hpp"

namespace farfield {

namespace {

const std::array kTechniques = {
    &brute_descriptor,     &octree_descriptor,     &octree_paper_descriptor,
    &colorcube_descriptor, &stratified_descriptor, &composite_descriptor,
    &clusters_descriptor,  &portal_descriptor,     &portal_paper_descriptor,
    &ibr_descriptor,       &hybrid_descriptor,
};

}  // namespace

std::span<const TechniqueDescriptor* const> technique_descriptors() {
  return kTechniques;
}

Result<const TechniqueDescriptor*> find_technique(std::string_view name) {
  std::string known;
  for (const TechniqueDescriptor* d : kTechniques) {
    if (d->name == name) return d;
    known += (known.empty() ? "" : ", ") + std::string(d->name);
  }
  return make_error("unknown technique '", std::string(name), "' (known: ", known, ")");
}

Result<std::unique_ptr<Technique>> make_technique(std::string_view name,
                                                  const TechniqueSettings& settings) {
  auto descriptor = find_technique(name);
  if (!descriptor) return descriptor.error();
  auto values = parse_settings(**descriptor, settings);
  if (!values) return values.error();
  return (*descriptor)->make(*values, settings);
}

Result<void> Technique::bake(const BakeContext&) {
  return make_error("technique '", std::string(name()), "' has nothing to bake; it loads in ",
                    "moments from the scene");
}

std::string techniques_help(bool with_settings) {
  std::string help;
  for (const TechniqueDescriptor* d : kTechniques) {
    help += "  " + std::string(d->name) + ": " + std::string(d->summary);
    if (!d->paper.empty()) help += " (paper " + std::string(d->paper) + ")";
    if (d->bake == BakeUse::required) help += "; needs a bake";
    help += "\n";
    if (!with_settings) continue;
    for (const SettingSpec& s : d->settings)
      help += "      " + std::string(d->name) + "." + std::string(s.key) + ": " +
              std::string(s.help) + " [" + describe_setting(s) + "]" + (s.baked ? " (baked)" : "") +
              "\n";
  }
  return help;
}

std::string settings_table_markdown(const TechniqueDescriptor& d) {
  if (d.settings.empty()) return "No settings.\n";
  std::string out = "| setting | values | paper | baked | what it does |\n|---|---|---|---|---|\n";
  for (const SettingSpec& s : d.settings)
    out += "| `" + std::string(d.name) + "." + std::string(s.key) + "` | " + describe_setting(s) +
           " | " + (s.symbol.empty() ? "" : std::string(s.symbol)) + " | " +
           (s.baked ? "yes" : "") + " | " + std::string(s.help) + " |\n";
  return out;
}

}  // namespace farfield
