// farfield analyze viewcell: the viewcell analysis of paper 000 (Eq. 2.2, Eq. 4.1, Sec. 2.4.2)
#include <cmath>
#include <cstdio>
#include <optional>

#include "commands.hpp"
#include "farfield/techniques/stratified/viewcell_analysis.hpp"

namespace farfield::cli {

namespace {

using namespace farfield::stratified;

struct Settings {
  double alpha = 0.0, box = 0.0, model = 0.0, viewcell = 0.0;
  std::string solve;
  std::vector<double> shells;
  std::string spacing;
  double b0 = 0.0, factor = 0.0;
  int count = 0;
  std::vector<double> region;
  Throughput throughput;
  std::string density_unit = "m3";
  CLI::Option *alpha_option = nullptr, *box_option = nullptr, *model_option = nullptr,
              *viewcell_option = nullptr, *solve_option = nullptr, *shells_option = nullptr,
              *spacing_option = nullptr, *b0_option = nullptr, *throughput_option = nullptr,
              *region_option = nullptr;
};

int usage(const std::string& message) {
  std::fprintf(stderr,
               "farfield analyze viewcell: %s\nRun 'farfield analyze viewcell --help' for usage.\n",
               message.c_str());
  return 2;
}

void print_count(double viewcell, const std::array<double, 3>& region) {
  auto count = count_viewcells(viewcell, region);
  if (!count) return;  // v came out of a solve, and the region was checked before
  std::printf("viewcells over %g x %g x %g m:\n", region[0], region[1], region[2]);
  std::printf(
      "  on the grid, each axis rounded up (the paper's count)  %llu x %llu x %llu = %llu\n",
      static_cast<unsigned long long>(count->cells[0]),
      static_cast<unsigned long long>(count->cells[1]),
      static_cast<unsigned long long>(count->cells[2]),
      static_cast<unsigned long long>(count->grid));
  std::printf("  region volume / v^3 (Eq. 4.2 as written)               %.0f\n",
              count->volume_ratio);
}

void print_throughput(const Settings& s, const ThroughputBox& b) {
  const int power = s.density_unit == "m2" ? 2 : 3;
  std::printf("paper 000, Sec. 2.4.2 (box from the renderer's throughput):\n");
  std::printf("  triangles per frame  p = P = %.0f  (%g triangles/s x %g ms)\n",
              b.triangles_per_frame, s.throughput.triangles_per_second, s.throughput.frame_ms);
  std::printf("  share in view        %.4f of the box's triangles (%g x %g deg view)\n",
              b.visible_fraction, s.throughput.hfov_deg, s.throughput.vfov_deg);
  std::printf("  bounding box length  b = %.2f m  (b^%d x %g per m^%d x %.4f = p)\n", b.box, power,
              s.throughput.density, power, b.visible_fraction);
}

// Eq. 2.2: three of alpha_max, b, l, v given (b perhaps from the throughput), the fourth solved.
int run_single(const Settings& s, const std::optional<ThroughputBox>& from_throughput,
               const std::optional<std::array<double, 3>>& region) {
  enum Quantity { kAlpha, kBox, kModel, kViewcell };
  const char* names[] = {"--alpha-deg", "--box", "--model", "--viewcell"};
  double values[] = {s.alpha, s.box, s.model, s.viewcell};
  bool known[] = {s.alpha_option->count() > 0, s.box_option->count() > 0,
                  s.model_option->count() > 0, s.viewcell_option->count() > 0};
  if (from_throughput) {
    if (!known[kAlpha] && !known[kModel] && !known[kViewcell] && !s.solve_option->count()) {
      print_throughput(s, *from_throughput);  // only the box was asked for
      return 0;
    }
    values[kBox] = from_throughput->box;
    known[kBox] = true;
  }

  int unknown = -1;
  if (s.solve_option->count()) {
    const std::string& q = s.solve;
    unknown = q == "alpha" ? kAlpha : q == "box" ? kBox : q == "model" ? kModel : kViewcell;
    if (known[unknown])
      return usage("--solve " + q + ", but " +
                   (unknown == kBox && from_throughput
                        ? std::string("the box comes from --triangles-per-second")
                        : std::string(names[unknown]) + " is given"));
  } else {
    for (int i = 0; i < 4; ++i) {
      if (known[i]) continue;
      if (unknown >= 0) {
        unknown = -2;
        break;
      }
      unknown = i;
    }
  }
  for (int i = 0; i < 4 && unknown >= 0; ++i) {
    if (i != unknown && !known[i]) unknown = -2;
  }
  if (unknown < 0)
    return usage(
        "give three of --alpha-deg, --box, --model and --viewcell and the fourth is solved (or "
        "--shells / --spacing for several shells)");

  Result<double> solved =
      unknown == kAlpha   ? alpha_for_viewcell(values[kViewcell], values[kBox], values[kModel])
      : unknown == kBox   ? box_for_viewcell(values[kAlpha], values[kViewcell], values[kModel])
      : unknown == kModel ? model_for_viewcell(values[kAlpha], values[kViewcell], values[kBox])
                          : viewcell_length(values[kAlpha], values[kBox], values[kModel]);
  if (!solved) return fail(solved.error().message);
  values[unknown] = *solved;
  if (region) {  // check before printing, so that a bad region prints only its error
    if (auto ok = count_viewcells(values[kViewcell], *region); !ok) return fail(ok.error().message);
  }

  if (from_throughput) print_throughput(s, *from_throughput);
  auto mark = [&](int q) { return q == unknown ? "  (solved)" : ""; };
  std::printf("paper 000, Eq. 2.2 (one shell):\n");
  std::printf("  angular error bound  alpha_max = %.3f deg%s\n", values[kAlpha], mark(kAlpha));
  std::printf("  bounding box length  b = %.2f m%s%s\n", values[kBox], mark(kBox),
              from_throughput ? "  (from the throughput)" : "");
  std::printf("  model length         l = %.2f m%s\n", values[kModel], mark(kModel));
  std::printf("  viewcell length      v = %.2f m%s\n", values[kViewcell], mark(kViewcell));
  if (unknown == kViewcell) {
    // What `farfield bake --technique stratified` uses by default (stratified.sizing=strict).
    auto cube = strict_viewcell_length(values[kAlpha], values[kBox], values[kBox]);
    auto band = strict_viewcell_length(values[kAlpha], values[kBox], 3.0);
    if (cube && band)
      std::printf(
          "strict 3D bound (the stratified bake's default): v = %.2f m, or %.2f m for "
          "a 3 m street band\n",
          *cube, *band);
  }
  if (region) print_count(values[kViewcell], *region);
  return 0;
}

// Eq. 4.1 with l_i of Sec. 4.2.1, over the given boxes or a linear / exponential series.
int run_shells(const Settings& s, const std::optional<ThroughputBox>& from_throughput,
               const std::optional<std::array<double, 3>>& region) {
  if (!s.alpha_option->count() || !s.model_option->count())
    return usage("--shells and --spacing need --alpha-deg and --model");
  std::vector<double> boxes = s.shells;
  if (s.spacing_option->count()) {
    if (!s.b0_option->count() && !from_throughput)
      return usage(
          "--spacing needs --b0, or the renderer's throughput (--triangles-per-second, "
          "--frame-ms, --triangle-density) to derive it");
    const double b0 = s.b0_option->count() ? s.b0 : from_throughput->box;
    auto series = box_series(s.spacing == "linear" ? Spacing::linear : Spacing::exponential, b0,
                             s.factor, s.model, s.count);
    if (!series) return fail(series.error().message);
    boxes = std::move(*series);
  }
  auto shells = shell_viewcells(s.alpha, boxes, s.model);
  if (!shells) return fail(shells.error().message);
  std::vector<ViewcellCount> counts;
  if (region) {
    for (const Shell& shell : *shells) {
      auto count = count_viewcells(shell.viewcell, *region);
      if (!count) return fail(count.error().message);
      counts.push_back(*count);
    }
  }

  if (from_throughput) print_throughput(s, *from_throughput);
  std::printf("paper 000, Eq. 4.1 with l_i of Sec. 4.2.1: %zu shells", shells->size());
  if (s.spacing_option->count())
    std::printf(", %s spacing, factor %g", s.spacing.c_str(), s.factor);
  std::printf(", alpha_max = %.3f deg, l = %.2f m\n", s.alpha, s.model);
  std::printf("  shell   box b_i (m)   far l_i (m)   viewcell v_i (m)");
  if (region) std::printf("        grid    viewcells");
  std::printf("\n");
  uint64_t total = 0;
  for (size_t i = 0; i < shells->size(); ++i) {
    const Shell& shell = (*shells)[i];
    std::printf("  %5zu  %12.2f  %12.2f  %17.2f", i, shell.box, shell.far, shell.viewcell);
    if (region) {
      const ViewcellCount& c = counts[i];
      char grid[64];
      std::snprintf(
          grid, sizeof grid, "%llux%llux%llu", static_cast<unsigned long long>(c.cells[0]),
          static_cast<unsigned long long>(c.cells[1]), static_cast<unsigned long long>(c.cells[2]));
      std::printf("  %14s  %11llu", grid, static_cast<unsigned long long>(c.grid));
      total += c.grid;
    }
    std::printf("\n");
  }
  if (region) {
    std::printf("  total over %g x %g x %g m (each axis rounded up, as the paper counts): %llu\n",
                (*region)[0], (*region)[1], (*region)[2], static_cast<unsigned long long>(total));
  }
  return 0;
}

}  // namespace

void add_analyze_command(CLI::App& root, std::vector<Command>& commands) {
  CLI::App* analyze = root.add_subcommand("analyze", "Analyses from the papers: viewcell");
  analyze->require_subcommand(1);
  auto s = std::make_shared<Settings>();
  CLI::App* cmd = analyze->add_subcommand(
      "viewcell",
      "Viewcell sizes of Stratified Rendering (paper 000). One shell (Eq. 2.2): give three of "
      "--alpha-deg, --box, --model, --viewcell and the fourth is solved. Several shells (Eq. 4.1): "
      "--alpha-deg, --model and --shells, or --spacing with --b0 and --factor. The box can come "
      "from the renderer's throughput (Sec. 2.4.2). --region counts the viewcells.");
  s->alpha_option = cmd->add_option("--alpha-deg", s->alpha,
                                    "alpha_max: the angular error bound, degrees in (0, 90)");
  s->box_option = cmd->add_option("--box", s->box, "b: the bounding box length, m");
  s->model_option = cmd->add_option("--model", s->model, "l: the model length, m");
  s->viewcell_option = cmd->add_option("--viewcell", s->viewcell, "v: the viewcell length, m");
  s->solve_option =
      cmd->add_option("--solve", s->solve, "What to solve Eq. 2.2 for (default: the one not given)")
          ->check(CLI::IsMember({"v", "alpha", "box", "model"}));
  s->shells_option = cmd->add_option("--shells", s->shells,
                                     "Box lengths b_0,b_1,... of nested shells, innermost first, m")
                         ->delimiter(',');
  s->spacing_option = cmd->add_option("--spacing", s->spacing,
                                      "Shell boxes from --b0: linear (b_i+1 = f b_i) or "
                                      "exponential (b_i+1 = b_i^f), paper 000, Sec. 4.2.1")
                          ->check(CLI::IsMember({"linear", "exponential"}));
  s->b0_option = cmd->add_option("--b0", s->b0, "The innermost box of --spacing, m");
  auto* factor = cmd->add_option("--factor", s->factor, "The spacing factor f, over 1");
  auto* count = cmd->add_option("--count", s->count,
                                "Number of shells of --spacing (default: every box shorter than "
                                "--model, as the paper counts)")
                    ->check(CLI::Range(1, max_shells));
  s->region_option = cmd->add_option("--region", s->region,
                                     "Extents X,Y,Z of the navigable region, m: count viewcells")
                         ->delimiter(',')
                         ->expected(3);
  Throughput& t = s->throughput;
  s->throughput_option = cmd->add_option("--triangles-per-second", t.triangles_per_second,
                                         "The renderer's measured triangles per second (farfield "
                                         "bench: brute's mean_triangles / median_ms * 1000)");
  auto* frame = cmd->add_option("--frame-ms", t.frame_ms, "The target frame time, ms");
  auto* density = cmd->add_option("--triangle-density", t.density,
                                  "Triangles per unit of --density-unit in the scene");
  auto* unit = cmd->add_option("--density-unit", s->density_unit,
                               "m3 (per cubic metre, the paper's) or m2 (per square metre of "
                               "ground, for a model no taller than the box)")
                   ->check(CLI::IsMember({"m3", "m2"}))
                   ->capture_default_str();
  auto* hfov = cmd->add_option("--hfov-deg", t.hfov_deg, "Horizontal field of view, degrees")
                   ->capture_default_str();
  auto* vfov = cmd->add_option("--vfov-deg", t.vfov_deg, "Vertical field of view, degrees")
                   ->capture_default_str();

  // Options that only make sense together, or not together: usage errors (exit 2).
  s->throughput_option->needs(frame)->needs(density);
  frame->needs(s->throughput_option);
  density->needs(s->throughput_option);
  for (CLI::Option* o : {unit, hfov, vfov}) o->needs(s->throughput_option);
  s->throughput_option->excludes(s->box_option)->excludes(s->b0_option)->excludes(s->shells_option);
  s->shells_option->excludes(s->spacing_option);
  s->spacing_option->needs(factor);
  for (CLI::Option* o : {factor, count, s->b0_option}) o->needs(s->spacing_option);
  for (CLI::Option* o : {s->shells_option, s->spacing_option})
    o->excludes(s->box_option)->excludes(s->viewcell_option)->excludes(s->solve_option);

  commands.push_back({cmd, [s] {
                        std::optional<ThroughputBox> from_throughput;
                        if (s->throughput_option->count()) {
                          s->throughput.unit = s->density_unit == "m2"
                                                   ? DensityUnit::per_square_metre
                                                   : DensityUnit::per_cubic_metre;
                          auto box = box_from_throughput(s->throughput);
                          if (!box) return fail(box.error().message);
                          from_throughput = *box;
                        }
                        std::optional<std::array<double, 3>> region;
                        if (s->region_option->count())
                          region = {s->region[0], s->region[1], s->region[2]};
                        if (s->shells_option->count() || s->spacing_option->count())
                          return run_shells(*s, from_throughput, region);
                        return run_single(*s, from_throughput, region);
                      }});
}

}  // namespace farfield::cli
