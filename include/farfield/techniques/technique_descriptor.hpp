// How a technique describes itself (DESIGN.md): name, summary, the paper it follows, its
// settings with type, range, default, unit and the paper's symbol, whether it bakes, and its
// factory. One parser reads `--set NAME.KEY=VALUE` against the descriptors; `--help`, the
// docs tables and `info` come from them. A technique is added by its folder and one line in
// technique_registry.cpp (docs/techniques/README.md).
#pragma once

#include <limits>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "farfield/core/result.hpp"
#include "farfield/techniques/technique.hpp"

namespace farfield {

enum class SettingType : uint8_t {
  number,   // a finite decimal number within [min, max] (ends open where said)
  integer,  // a whole number within [min, max]
  flag,     // 0 or 1
  choice,   // one of `choices` ("drop|keep")
  text,     // free text the technique checks (a path, a list of numbers)
};

struct SettingSpec {
  std::string_view key;
  SettingType type;
  std::string_view default_value;  // as typed; empty: derived (the help says how)
  std::string_view help;
  std::string_view unit = {};    // "m", "deg", "px", "frames", ...
  std::string_view symbol = {};  // the paper's name for it: "alpha_max (000, Eq. 2.2)"
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false, max_open = false;  // the range excludes that end
  std::string_view choices = {};            // choice: alternatives separated by '|'
  bool baked = false;  // fixed by the bake: a run with a pack reads it from there
};

// The settings of one technique after parsing: every value valid, defaults filled in.
class SettingValues {
 public:
  double number(std::string_view key) const;  // number and integer settings
  // A number setting whose default is derived (empty): its value, or `otherwise` if none.
  double number_or(std::string_view key, double otherwise) const;
  int integer(std::string_view key) const;
  bool flag(std::string_view key) const;
  const std::string& text(std::string_view key) const;  // choice and text settings
  bool given(std::string_view key) const;               // set on the command line (not a default)

 private:
  friend struct SettingsParser;
  std::map<std::string, std::string, std::less<>> values_;
  std::map<std::string, bool, std::less<>> given_;
};

// `--set` assignments before they are sorted by technique.
struct TechniqueSettings {
  std::map<std::string, std::string> values;  // "colorcube.depth" -> "6"

  // Parses "NAME.KEY=VALUE"; the message names the assignment and the problem.
  Result<void> add(const std::string& assignment);
  // The keys under `technique` ("depth" for "colorcube.depth").
  std::map<std::string, std::string> for_technique(std::string_view technique) const;
};

enum class BakeUse : uint8_t {
  none,      // loads from the scene alone; has no bake
  optional,  // loads its bake when the pack holds one, else builds it at load
  required,  // draws only from a bake
};

struct TechniqueDescriptor {
  std::string_view name;
  std::string_view summary;  // one line for --help
  std::string_view paper;    // "004, Sec. 2.1"
  std::span<const SettingSpec> settings;
  BakeUse bake = BakeUse::none;
  int bake_format = 0;        // the pack's format of this technique's bake; raise on change
  // > 0: packs from this format on read as bake_format's where the scene has no instances (a
  // change that only instances' data made), so that they need no new bake.
  int plain_scene_format = 0;
  bool bake_renders = false;  // its bake draws the scene (BakeContext::renderer)
  // Its bake draws many small images (tables, box sides): on the calling thread alone.
  bool bake_images_small = false;
  // It walks a scene left on disk (LoadContext::on_disk: bench and view --cache-mb).
  bool streams = false;
  // Its bake spreads over the ranks of an MPI job (BakeContext::shards).
  bool distributes = false;
  // `info PACK`: lines on the technique's bake in the pack (viewcells per shell, ...).
  Result<std::string> (*describe_bake)(const Store& store) = nullptr;
  // The technique from its checked settings; `all` holds every --set, for techniques made of
  // others (composite).
  Result<std::unique_ptr<Technique>> (*make)(const SettingValues& settings,
                                             const TechniqueSettings& all) = nullptr;
  // The techniques it runs inside itself (composite's near and far), which must load too.
  std::vector<std::string> (*parts)(const SettingValues& settings) = nullptr;

  const SettingSpec* setting(std::string_view key) const;
  // The oldest bake format this farfield reads for `scene` (plain_scene_format or bake_format).
  int oldest_format(const Scene& scene) const {
    return plain_scene_format > 0 && scene.instances.empty() ? plain_scene_format : bake_format;
  }
};

// Every technique this build knows, in the order of --help.
std::span<const TechniqueDescriptor* const> technique_descriptors();
// The descriptor of `name`; an unknown name is an error that lists the known ones.
Result<const TechniqueDescriptor*> find_technique(std::string_view name);

// Checks and fills the settings of `descriptor` from `--set` (keys under its name): unknown
// keys and bad values are errors that name "--set NAME.KEY", the value and the rule.
Result<SettingValues> parse_settings(const TechniqueDescriptor& descriptor,
                                     const TechniqueSettings& settings);

// A new technique by name with its settings (parse_settings first).
Result<std::unique_ptr<Technique>> make_technique(std::string_view name,
                                                  const TechniqueSettings& settings = {});

// The rule of a setting as --help shows it: "number in (0, 90) deg, default 2".
std::string describe_setting(const SettingSpec& spec);
// --help text for every technique, a line each, with its settings when asked.
std::string techniques_help(bool with_settings = true);
// The settings of one technique as a Markdown table (docs/techniques/NAME.md holds it).
std::string settings_table_markdown(const TechniqueDescriptor& descriptor);

}  // namespace farfield
