// The one interface every rendering technique implements (DESIGN.md). A technique prepares
// itself once for a scene (load, or load_baked from what bake wrote into a .ffpack store),
// then selects what to draw for each view (select): pure CPU, no GL, no allocation in steady
// state, so it can be tested without a GPU and timed apart from drawing.
#pragma once

#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/core/view.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/techniques/draw_list.hpp"

namespace farfield {

class Store;

struct FrameBudget {
  double frame_ms = 0.0;  // target frame time; 0 = no budget (techniques that ignore it)
};

class Technique {
 public:
  virtual ~Technique() = default;
  virtual std::string_view name() const = 0;
  // Builds the technique's run-time structures for `scene`, which must outlive it.
  virtual Result<void> load(const Scene& scene) = 0;
  // Offline preprocessing into `store` (a write transaction of its own); techniques with
  // nothing worth keeping refuse.
  virtual Result<void> bake(const Scene& scene, Store& store, Progress& progress);
  // Loads what bake() wrote for this scene; techniques without a bake simply load().
  virtual Result<void> load_baked(const Scene& scene, const Store& store);
  // Every frame; clears all of `out` first (DrawList::clear keeps its capacity).
  virtual void select(const View& view, const FrameBudget& budget, DrawList& out) = 0;
  // One line on what load built (nodes, depth, ...), for reports.
  virtual std::string describe() const { return {}; }
  // The same as named numbers for bench.json (e.g. paper 002's Table 1 for colorcube).
  virtual std::vector<std::pair<std::string, double>> figures() const { return {}; }
  // Stand-in geometry that the technique's DrawList::proxies refer to, if any; valid after
  // load() for the technique's lifetime. The renderer uploads it (Renderer::set_proxies).
  virtual const ProxyMesh* proxies() const { return nullptr; }
  // Bird's-eye pictures (paper 000, Fig. 5-2): called after select() for `eye` with its list,
  // adds the technique's own marks (its viewcell, ...) and places stand-ins where they are.
  virtual void annotate(const View& /*eye*/, DrawList& /*list*/) const {}
  // The first error met while running (a damaged blob found by a background load); empty if
  // none. select() has no error channel: callers check this and stop.
  virtual std::string failure() const { return {}; }
};

// Technique settings from the command line (`--set NAME.KEY=VALUE`, e.g. colorcube.depth=6):
// each technique reads the keys under its own name and refuses the ones it does not know.
struct TechniqueSettings {
  std::map<std::string, std::string> values;  // "colorcube.depth" -> "6"

  // Parses "NAME.KEY=VALUE"; the message names the setting and the problem.
  Result<void> add(const std::string& assignment);
  // The keys under `technique` ("depth" for "colorcube.depth").
  std::map<std::string, std::string> for_technique(std::string_view technique) const;
};

// A setting's value as a finite number; the message names "--set TECHNIQUE.KEY".
Result<double> setting_number(std::string_view technique, const std::string& key,
                              const std::string& text);

// The techniques this build knows, with a line each for --help.
struct TechniqueInfo {
  std::string_view name;
  std::string_view summary;
};
std::span<const TechniqueInfo> known_techniques();

// A new technique by name; an unknown name is an error that lists the known ones, an unknown
// or malformed setting one that names it.
Result<std::unique_ptr<Technique>> make_technique(std::string_view name,
                                                  const TechniqueSettings& settings = {});

}  // namespace farfield
