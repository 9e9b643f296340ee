// Settings of the stratified technique (paper 000), from `--set stratified.KEY=VALUE`.
// Bake settings are written into the pack and read back by the walk; walk settings apply to
// the run that sets them.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "farfield/core/bounds.hpp"
#include "farfield/core/result.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique_descriptor.hpp"
#include "farfield/techniques/stratified/viewcell_analysis.hpp"

namespace farfield::stratified {

// paper 000, Sec. 5.1: what the walk draws.
enum class Style {
  full,         // near objects and the far-field box
  near_only,    // near objects only
  far_objects,  // far objects as geometry, no near objects
  far_texture,  // the far-field box only
  brute,        // every object
};
const char* style_name(Style style);

struct StratifiedOptions {
  // Bake.
  double alpha_deg = 2.0;      // alpha_max
  double box = 0.0;            // b, metres (the innermost box with shells); 0: from the scene
  int near_triangles = 16000;  // p of Eq. 2.3, which sizes the box when box is 0
  double viewcell = 0.0;       // v; 0: from alpha and the box (see `paper_sizing`)
  // v from paper 000's Eq. 2.2 (Eq. 4.1 with shells) rather than the strict 3D bound
  // (strict_viewcell_length), which holds for every eye point and far point.
  bool paper_sizing = false;
  int resolution = 512;  // pixels per box side
  ImageCodec codec = ImageCodec::jpeg(85);
  bool delta = false;            // PNG residuals against a neighbouring viewcell (Sec. 3.1.4)
  std::string band = "auto";     // navigable heights: auto, street, all, or "Y0,Y1"
  double far_share = 0.05;       // a bake whose far fields hold less is refused
  std::string path;              // bake only the viewcells this camera path passes through
  std::optional<Bounds3> limit;  // bake only the viewcells meeting this box (x0,z0,x1,z1)
  int shells = 1;                // Ch. 4
  Spacing spacing = Spacing::exponential;
  double factor = 1.13;  // b_{i+1} / b_i (the paper's 1.13 exponential, 1.72 linear)
  // Walk.
  Style style = Style::full;
  int blend_frames = 0;  // Sec. 7.1: fade the new far field in over this many frames
  int lookahead = 2;     // viewcells prefetched ahead along the velocity (Sec. 3.2.1)
};

// The settings table of the descriptor, and the options from its checked values; checks
// between settings (delta needs png, ...) are errors that name them.
std::span<const SettingSpec> stratified_settings();
Result<StratifiedOptions> stratified_options(const SettingValues& values);

// The navigable region of `band` (street, all, Y0,Y1; not auto) within the scene's bounds:
// street is the bottom 3 m.
Result<Bounds3> navigable_region(const std::string& band, const Bounds3& scene_bounds);

}  // namespace farfield::stratified
