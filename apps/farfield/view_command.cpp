// farfield view SCENE: a window to walk through a scene (paper 000, Sec. 5.1) or orbit a model
// seen from outside (paper 003), switching technique at run time, with frame time, triangles
// and draw calls on screen; the lights turn, and a click names the object under the cursor.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include <epoxy/gl.h>  // before GLFW, which would include the system GL header
#include <GLFW/glfw3.h>
#include <glm/trigonometric.hpp>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "commands.hpp"
#include "large_pages.hpp"
#include "farfield/core/image.hpp"
#include "farfield/core/camera_path.hpp"
#include "farfield/core/navigation.hpp"
#include "farfield/gpu/lighting.hpp"
#include "farfield/gpu/renderer.hpp"
#include "farfield/gpu/window.hpp"
#include "farfield/scene/chunked_scene.hpp"
#include "farfield/scene/path_generator.hpp"
#include "farfield/scene/scene_file.hpp"
#include "farfield/spatial/walking.hpp"
#include "farfield/eval/frame_loop.hpp"
#include "farfield/eval/run_plan.hpp"
#include "farfield/store/bake_record.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::cli {

namespace {

struct ViewSettings {
  std::string scene, path, store, technique = "octree", screenshot, record;
  std::vector<std::string> settings;
  int width = 1024, height = 768, frames = 0;
  float hfov_deg = 90.0f;
  float budget_ms = 0.0f;
  float birdseye_height = 0.0f;  // > 0: start in the bird's-eye view
  bool orbit = false;            // start orbiting the scene's centre
  std::vector<float> light;      // heading, elevation
  std::vector<int> pick;         // x, y: pick this pixel once a frame is drawn
  uint64_t cache_mb = 0;         // > 0: the geometry left on disk, through a cache this large
  bool technique_given = false;
};

// What a click found: the object and triangle at a pixel.
struct Picked {
  glm::ivec2 pixel{0};
  std::optional<uint32_t> triangle, object;
};

std::string describe(const Scene& scene, const Picked& p) {
  char where[64];
  std::snprintf(where, sizeof where, "pixel (%d, %d): ", p.pixel.x, p.pixel.y);
  if (!p.triangle) return std::string(where) + "no scene triangle (sky, or a stand-in)";
  std::string text = std::string(where) + "triangle " + std::to_string(*p.triangle);
  if (p.object) {
    const Object& o = scene.objects[*p.object];
    text += " of object " + std::to_string(*p.object) + " '" +
            std::string(scene.object_name(o)) + "' (" + std::string(object_kind_name(o.kind)) +
            ", " + counted(o.triangle_count(), "triangle") + ")";
  }
  return text;
}

constexpr float kDefaultBirdseyeHeight = 300.0f;

NavigationInput keys_to_input(const gpu::Window& w) {
  auto axis = [&](int plus_a, int plus_b, int minus_a, int minus_b) {
    return float(w.key_down(plus_a) || w.key_down(plus_b)) -
           float(w.key_down(minus_a) || w.key_down(minus_b));
  };
  NavigationInput in;
  in.forward = axis(GLFW_KEY_W, GLFW_KEY_UP, GLFW_KEY_S, GLFW_KEY_DOWN);
  in.turn = axis(GLFW_KEY_D, GLFW_KEY_RIGHT, GLFW_KEY_A, GLFW_KEY_LEFT);
  in.climb = axis(GLFW_KEY_E, GLFW_KEY_PAGE_UP, GLFW_KEY_Q, GLFW_KEY_PAGE_DOWN);
  in.look = axis(GLFW_KEY_R, GLFW_KEY_HOME, GLFW_KEY_F, GLFW_KEY_END);
  in.fast = w.key_down(GLFW_KEY_LEFT_SHIFT) || w.key_down(GLFW_KEY_RIGHT_SHIFT);
  return in;
}

// Without a path: at a corner of the scene, a third of its size up, looking at its centre.
// The first pose of an orbit: the whole scene in sight.
CameraPose overview_pose(const Scene& scene) {
  auto orbit = generate_path(scene, {.kind = "orbit", .frames = 1});
  return orbit && !orbit->frames.empty() ? orbit->frames.front() : CameraPose{};
}

// Walking speeds for the scene's size: a city at 15 m/s, a 1 m model at 0.1 m/s.
NavigationSpeeds speeds_for(const Scene& scene) {
  const glm::vec3 size = scene.bounds.size();
  const float extent = std::max({size.x, size.y, size.z});
  NavigationSpeeds speeds;
  const float scale =
      std::clamp(0.1f * extent / speeds.move_m_per_s, 0.1f / speeds.move_m_per_s, 1.0f);
  speeds.move_m_per_s *= scale;
  speeds.climb_m_per_s *= scale;
  return speeds;
}

int run_viewer(ViewSettings s) {
  // With --cache-mb the geometry stays in the file and streaming techniques read what they
  // draw; others are unavailable, and so are walking and picking, which need triangles.
  std::optional<ChunkedScene> on_disk;
  std::optional<Scene> in_memory;
  if (s.cache_mb > 0) {
    auto opened = ChunkedScene::open(s.scene);
    if (!opened) return fail(opened.error().message);
    on_disk.emplace(std::move(*opened));
    if (!s.technique_given) s.technique = "brute";
  } else {
    auto read = read_scene(s.scene);
    if (!read) return fail(read.error().message);
    in_memory.emplace(std::move(*read));
  }
  const Scene* scene = on_disk ? &on_disk->index() : &*in_memory;
  CameraPath path;
  if (!s.path.empty()) {
    auto read = read_camera_path(s.path);
    if (!read) return fail(read.error().message);
    path = std::move(*read);
  }
  std::optional<Store> store;
  if (!s.store.empty()) {
    auto opened = Store::open(s.store, Store::Mode::kRead);
    if (!opened) return fail(opened.error().message);
    store.emplace(std::move(*opened));
  }
  if (s.light.size() == 2 && !(std::abs(s.light[0]) <= 360.0f && std::abs(s.light[1]) <= 90.0f))
    return usage_error("--light: a heading within -360..360 and an elevation within -90..90 "
                       "degrees, not " + number_text(s.light[0]) + ", " + number_text(s.light[1]));
  if (s.pick.size() == 2 && !(s.pick[0] >= 0 && s.pick[1] >= 0 && s.pick[0] < s.width &&
                              s.pick[1] < s.height))
    return usage_error("--pick: a pixel inside the " + std::to_string(s.width) + " x " +
                       std::to_string(s.height) + " window, not " + std::to_string(s.pick[0]) +
                       ", " + std::to_string(s.pick[1]));
  TechniqueSettings settings;
  for (const std::string& setting : s.settings)
    if (auto ok = settings.add(setting); !ok) return usage_error(ok.error().message);
  // Everything asked is checked before the window opens: the technique at start (its bake
  // included), every setting, and the files --record and --screenshot write.
  auto plan = plan_run({s.technique}, settings, store ? &*store : nullptr, *scene, true,
                       on_disk ? &*on_disk : nullptr);
  if (!plan) return fail(plan.error().message);
  if (!s.record.empty())
    if (auto ok = check_writable_file(s.record); !ok) return fail(ok.error().message);
  if (!s.screenshot.empty()) {
    if (auto ok = check_image_name(s.screenshot); !ok) return usage_error(ok.error().message);
    if (auto ok = check_writable_file(s.screenshot); !ok) return fail(ok.error().message);
  }
  // Techniques are made for every name (so bad settings fail now) but loaded when first shown:
  // some build their structures at load.
  const auto descriptors = technique_descriptors();
  std::vector<std::unique_ptr<Technique>> techniques;
  std::vector<bool> loaded(descriptors.size(), false);
  size_t current = descriptors.size();
  for (const TechniqueDescriptor* d : descriptors) {
    auto t = make_technique(d->name, settings);
    if (!t) return fail(t.error().message);
    if (d->name == s.technique) current = techniques.size();
    techniques.push_back(std::move(*t));
  }

  auto window = gpu::Window::create(s.width, s.height, "farfield: " + s.scene);
  if (!window) return fail(window.error().message);
  auto renderer = gpu::Renderer::create(*scene);
  if (!renderer) return fail(renderer.error().message);
  FrameLoop loop(**renderer);
  // The techniques free their meshes and textures through the renderer: they go first.
  struct ReleaseBeforeRenderer {
    std::vector<std::unique_ptr<Technique>>& techniques;
    ~ReleaseBeforeRenderer() { techniques.clear(); }
  } release{techniques};
  // A technique that cannot load (stratified without its bake) stays unavailable, with why.
  std::vector<std::string> unavailable(descriptors.size());
  Progress quiet(true);
  auto show = [&](size_t t) -> Result<void> {
    if (loaded[t]) return {};
    if (on_disk && !descriptors[t]->streams)
      return make_error(descriptors[t]->name, " needs the scene in memory (drop --cache-mb)");
    if (auto ok = techniques[t]->load({*scene, store ? &*store : nullptr, **renderer, quiet,
                                       on_disk ? &*on_disk : nullptr, s.cache_mb * 1000000});
        !ok)
      return ok;
    loaded[t] = true;
    return {};
  };

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui_ImplGlfw_InitForOpenGL((*window)->handle(), true);
  ImGui_ImplOpenGL3_Init("#version 450");

  CameraPath recorded{"recorded", s.scene, {}};
  // Where the viewer opens: the first pose of --path; else inside what the pack baked (the
  // start technique's bake first, then any other's: stratified's viewcells); else with the
  // whole scene in sight.
  std::optional<CameraPose> start;
  if (!path.frames.empty()) start = path.frames.front();
  for (size_t k = 0; k <= descriptors.size() && !start && store; ++k) {
    const size_t t = k == 0 ? current : k - 1;
    if (t >= descriptors.size() || descriptors[t]->bake == BakeUse::none) continue;
    auto record = read_bake_record(*store, descriptors[t]->name);
    if (record && *record && show(t)) start = techniques[t]->start_pose();
  }
  CameraPose pose = start ? *start : overview_pose(*scene);
  // Walking (paper 000, Sec. 5.1): stopped short of walls, at eye height over the ground
  // where there is ground within reach below; G flies freely.
  const RayCaster caster(*scene);
  const WalkOptions walk_options = walk_options_for(scene->bounds);
  bool walking = !on_disk, g_was_down = false;
  const NavigationSpeeds speeds = speeds_for(*scene);
  // Orbiting (O): about the scene's centre, as ibr's and hybrid's viewpoints and path --kind
  // orbit are; entered through the eye where it stands.
  bool orbiting = s.orbit, o_was_down = false;
  const float min_orbit_radius = near_plane_for(scene->bounds) * 4.0f;
  Orbit orbit = Orbit::through(pose, scene->bounds.center(), min_orbit_radius);
  float light[2] = {gpu::kLightHeadingDeg, gpu::kLightElevationDeg};
  if (s.light.size() == 2) light[0] = s.light[0], light[1] = s.light[1];
  (*renderer)->set_light(light[0], light[1]);
  // A click (or --pick) is answered at the start of the next frame, in the frame it was made
  // on: its view and selection (the pass draws into the window, which that frame redraws).
  std::optional<glm::ivec2> pick_at;
  if (s.pick.size() == 2) pick_at = glm::ivec2(s.pick[0], s.pick[1]);
  std::optional<Picked> picked;
  bool mouse_was_down = false;
  View last_view;
  bool playing = !path.frames.empty();
  size_t path_frame = 0;
  int frame = 0;
  bool tab_was_down = false, p_was_down = false, b_was_down = false, c_was_down = false;
  bool tinted = false;
  bool birdseye = s.birdseye_height > 0;
  const float birdseye_height = birdseye ? s.birdseye_height : kDefaultBirdseyeHeight;
  std::string notice;
  double smoothed_ms = 0.0;
  FrameTiming stats;
  float budget_ms = s.budget_ms;
  auto last = std::chrono::steady_clock::now();
  int exit_status = 0;
  while (!(*window)->should_close()) {
    (*window)->poll_events();
    const auto now = std::chrono::steady_clock::now();
    const float dt = std::min(std::chrono::duration<float>(now - last).count(), 0.25f);
    last = now;
    gpu::Window& w = **window;
    if (w.key_down(GLFW_KEY_ESCAPE)) w.close();
    const bool typing = ImGui::GetIO().WantCaptureKeyboard;
    const bool tab = w.key_down(GLFW_KEY_TAB), p = w.key_down(GLFW_KEY_P),
               b = w.key_down(GLFW_KEY_B), g = w.key_down(GLFW_KEY_G), c = w.key_down(GLFW_KEY_C),
               o = w.key_down(GLFW_KEY_O);
    const size_t before = current;
    if (tab && !tab_was_down && !typing) current = (current + 1) % techniques.size();
    if (p && !p_was_down && !typing && !path.frames.empty()) playing = !playing;
    if (b && !b_was_down && !typing) birdseye = !birdseye;
    if (g && !g_was_down && !typing && !on_disk) walking = !walking;
    if (c && !c_was_down && !typing) tinted = !tinted;
    if (o && !o_was_down && !typing) {
      orbiting = !orbiting;
      if (orbiting) orbit = Orbit::through(pose, scene->bounds.center(), min_orbit_radius);
    }
    o_was_down = o;
    const bool mouse = w.mouse_down(GLFW_MOUSE_BUTTON_LEFT);
    if (mouse && !mouse_was_down && !ImGui::GetIO().WantCaptureMouse) pick_at = w.cursor_pixel();
    mouse_was_down = mouse;
    c_was_down = c;
    g_was_down = g;
    tab_was_down = tab;
    p_was_down = p;
    b_was_down = b;
    for (int k = 0; k < 9 && !typing; ++k)
      if (w.key_down(GLFW_KEY_1 + k) && size_t(k) < techniques.size()) current = size_t(k);

    if (playing) {
      pose = path.frames[path_frame];
      path_frame = (path_frame + 1) % path.frames.size();
    } else if (orbiting && !typing) {
      orbit = navigate(orbit, keys_to_input(w), speeds, dt);
      pose = orbit.pose();
    } else if (!typing) {
      const CameraPose moved = navigate(pose, keys_to_input(w), speeds, dt);
      pose = walking ? walk(caster, pose, moved, walk_options) : moved;
    }
    if (!s.record.empty()) recorded.frames.push_back(pose);

    View view;
    view.pose = pose;
    w.framebuffer_size(view.width, view.height);
    view.hfov_deg = s.hfov_deg;
    view.near_m = near_plane_for(scene->bounds);
    if (pick_at && frame > 0) {
      Picked p;
      p.pixel = *pick_at;
      if (p.pixel.x >= 0 && p.pixel.y >= 0 && p.pixel.x < last_view.width &&
          p.pixel.y < last_view.height) {
        p.triangle = (*renderer)->pick(*scene, last_view, loop.last_list(), p.pixel.x, p.pixel.y);
        if (p.triangle) p.object = object_of_triangle(*scene, *p.triangle);
        std::printf("picked %s\n", describe(*scene, p).c_str());
        picked = p;
      }
      pick_at.reset();
    }
    const auto start = std::chrono::steady_clock::now();
    if (!unavailable[current].empty()) current = before;
    if (auto ok = show(current); !ok) {
      if (current == before) {  // the technique asked for at start
        exit_status = fail(ok.error().message);
        break;
      }
      unavailable[current] = ok.error().message;
      notice = std::string(techniques[current]->name()) + ": " + ok.error().message;
      current = before;
      continue;
    }
    // paper 000, Fig. 5-2: in the bird's-eye view the same selection from above.
    stats = loop.run(*techniques[current], view, uint64_t(frame), next_budget(budget_ms, stats),
                     birdseye ? birdseye_height : 0.0f, tinted);
    if (std::string failure = techniques[current]->failure(); !failure.empty()) {
      exit_status = fail(failure);
      break;
    }
    last_view = view;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    smoothed_ms = frame == 0 ? ms : 0.9 * smoothed_ms + 0.1 * ms;

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("farfield", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings);
    int selected = int(current);
    for (size_t t = 0; t < techniques.size(); ++t) {
      const std::string label = std::to_string(t + 1) + " " + std::string(techniques[t]->name());
      if (ImGui::RadioButton(label.c_str(), selected == int(t))) selected = int(t);
      if (t + 1 < techniques.size() && (t + 1) % 6 != 0) ImGui::SameLine();  // rows of six
    }
    current = size_t(selected);
    ImGui::Text("frame %.1f ms (%.0f fps)   selection %.2f ms", smoothed_ms, 1000.0 / smoothed_ms,
                stats.select_ms);
    ImGui::SliderFloat("budget ms (0: none)", &budget_ms, 0.0f, 100.0f, "%.0f");
    ImGui::Text("triangles %llu   draw calls %llu", (unsigned long long)stats.triangles,
                (unsigned long long)stats.draw_calls);
    ImGui::Text("at (%.1f, %.1f, %.1f)  heading %.0f  pitch %.0f", pose.position.x, pose.position.y,
                pose.position.z, pose.yaw_deg, pose.pitch_deg);
    // What the technique did, not only how fast: its far field, its fallbacks, what it built.
    const Technique& shown = *techniques[current];
    if (const auto box = shown.far_field_box())
      ImGui::Text("far field beyond a %.0f m box", box->size().x);
    if (const uint64_t fallback = shown.fallback_frames(); fallback > 0)
      ImGui::Text("%s drawn as plain geometry (outside the bake)",
                  counted(fallback, "frame").c_str());
    if (const std::string built = shown.describe(); !built.empty())
      ImGui::TextWrapped("%s", built.c_str());
    ImGui::Checkbox("colour by representation (C)", &tinted);
    // paper 003, Sec. 3: geometry drawn each frame can be relit (baked images keep their light).
    const bool turned = ImGui::SliderFloat("light heading", &light[0], 0.0f, 360.0f, "%.0f");
    if (ImGui::SliderFloat("light elevation", &light[1], -90.0f, 90.0f, "%.0f") || turned)
      (*renderer)->set_light(light[0], light[1]);
    if (orbiting)
      ImGui::Text("orbit: longitude %.1f  latitude %.1f  radius %.1f m", orbit.longitude_deg,
                  orbit.latitude_deg, orbit.radius);
    if (picked) {
      ImGui::TextWrapped("picked %s", describe(*scene, *picked).c_str());
      // The pixel marked (ImGui draws in window coordinates).
      const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
      const ImVec2 at(float(picked->pixel.x) / std::max(scale.x, 1e-3f),
                      float(picked->pixel.y) / std::max(scale.y, 1e-3f));
      ImGui::GetForegroundDrawList()->AddCircle(at, 9.0f, IM_COL32(255, 40, 40, 255), 0, 2.0f);
      ImGui::GetForegroundDrawList()->AddLine(ImVec2(at.x - 14, at.y), ImVec2(at.x + 14, at.y),
                                              IM_COL32(255, 40, 40, 255));
      ImGui::GetForegroundDrawList()->AddLine(ImVec2(at.x, at.y - 14), ImVec2(at.x, at.y + 14),
                                              IM_COL32(255, 40, 40, 255));
    }
    // The technique's own figures as they run (clusters: switches, clusters drawn, ...).
    if (ImGui::CollapsingHeader("figures"))
      for (const auto& [key, value] : shown.figures()) ImGui::Text("%s %.6g", key.c_str(), value);
    if (!path.frames.empty())
      ImGui::Text("path %s: frame %zu of %zu (P: %s)", path.kind.c_str(), path_frame,
                  path.frames.size(), playing ? "pause" : "play");
    if (!notice.empty()) ImGui::TextWrapped("%s", notice.c_str());
    ImGui::TextDisabled("%s  Shift fast  Tab/1-9 technique  click: pick",
                        orbiting ? "A/D round  R/F up/down  W/S nearer/farther"
                                 : "W/S move  A/D turn  E/Q up/down  R/F look");
    ImGui::TextDisabled("B bird's-eye%s  C colour  G %s  O %s", birdseye ? " (on)" : "",
                        walking ? "fly (walking now)" : "walk (flying now)",
                        orbiting ? "walk (orbiting now)" : "orbit");
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

    ++frame;
    // A pick is answered at the start of the next frame: a screenshot waits for it.
    if (!s.screenshot.empty() && frame >= std::max(s.frames, 1) && !pick_at) {
      if (auto ok = write_image((*renderer)->capture(), s.screenshot); !ok) {
        exit_status = fail(ok.error().message);
      } else {
        std::printf("wrote %s after %s (%s, %.1f ms, %s, %llu fallback)\n", s.screenshot.c_str(),
                    counted(frame, "frame").c_str(),
                    std::string(techniques[current]->name()).c_str(), smoothed_ms,
                    counted(stats.triangles, "triangle").c_str(),
                    (unsigned long long)techniques[current]->fallback_frames());
      }
      w.close();
    } else if (s.screenshot.empty() && s.frames > 0 && frame >= s.frames && !pick_at) {
      w.close();
    }
    w.swap_buffers();
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  if (!s.record.empty() && exit_status == 0) {
    if (auto ok = write_camera_path(recorded, s.record); !ok) return fail(ok.error().message);
    std::printf("recorded %s into %s\n", counted(recorded.frames.size(), "frame").c_str(),
                s.record.c_str());
  }
  return exit_status;
}

}  // namespace

void add_view_command(CLI::App& root, std::vector<Command>& commands) {
  auto s = std::make_shared<ViewSettings>();
  CLI::App* cmd = root.add_subcommand(
      "view",
      "Walk through a scene in a window. Keys: W/S or arrows forward/back, A/D turn, "
      "E/Q or PageUp/PageDown ascend/descend, R/F look up/down, Shift faster, Tab or 1-9 "
      "switch technique, B bird's-eye view, P play/pause the path, G walk/fly, O orbit the "
      "scene's centre (A/D round, R/F up/down, W/S nearer/farther), click: name the object "
      "and triangle under the cursor, Esc quit. "
      "Walking (the default) keeps the eye at eye height over the ground and stops it short of "
      "walls; where there is no ground below, it flies");
  cmd->add_option("scene", s->scene, "A .ffscene file")->required();
  cmd->add_option("--path", s->path, "Camera path to play (P pauses and resumes)");
  cmd->add_option("--store", s->store, "A .ffpack from 'farfield bake' to load techniques from");
  CLI::Option* technique =
      cmd->add_option("--technique,-t", s->technique, "Technique at start")->capture_default_str();
  cmd->add_option("--set", s->settings,
                  "Technique setting TECHNIQUE.KEY=VALUE, repeatable (e.g. colorcube.depth=6)");
  cmd->add_option("--width", s->width, "Window width, pixels")
      ->capture_default_str()
      ->check(CLI::Range(kMinImageSide, kMaxImageSide));
  cmd->add_option("--height", s->height, "Window height, pixels")
      ->capture_default_str()
      ->check(CLI::Range(kMinImageSide, kMaxImageSide));
  cmd->add_option("--hfov", s->hfov_deg, "Horizontal field of view, degrees")
      ->capture_default_str()
      ->check(number_range(kMinHfovDeg, kMaxHfovDeg));
  cmd->add_option("--frames", s->frames, "Quit after this many frames (0: run until closed)")
      ->check(CLI::Range(0, 1 << 24))
      ->capture_default_str();
  cmd->add_option("--screenshot", s->screenshot,
                  "Save the window (with its overlay) as PNG after --frames frames, then quit");
  cmd->add_option("--birdseye", s->birdseye_height,
                  "Start in the bird's-eye view from this many metres above the eye (B toggles; "
                  "300 m when not given)")
      ->check(number_range(0, 100000));
  cmd->add_option("--budget-ms", s->budget_ms,
                  "Frame-time budget for every technique, ms (0: none); a slider changes it")
      ->check(number_range(0, 10000));
  cmd->add_option("--record", s->record, "Write the poses of the session as a camera path on exit");
  cmd->add_flag("--orbit", s->orbit,
                "Start orbiting the scene's centre (O toggles): A/D round, R/F up and down, W/S "
                "nearer and farther, on the sphere of ibr's and hybrid's viewpoints and of "
                "'path --kind orbit'");
  cmd->add_option("--light", s->light,
                  "HEADING,ELEVATION: the two lights (opposite headings) turned and raised to "
                  "these degrees (default 30,14; sliders change them); images baked earlier "
                  "keep their light")
      ->expected(2)
      ->delimiter(',');
  cmd->add_option("--pick", s->pick,
                  "X,Y: once a frame is drawn, pick the scene triangle at this pixel (from the "
                  "top left) as a click does, print its object and triangle and mark it "
                  "(with --screenshot, in the picture)")
      ->expected(2)
      ->delimiter(',');
  cmd->add_option("--cache-mb", s->cache_mb,
                  "Leave the scene's geometry in its file and walk it through a cache of this "
                  "many MB of GPU meshes (techniques that stream: brute; flying only, no "
                  "picking); 0: read the scene whole")
      ->check(CLI::Range(uint64_t(0), uint64_t(1) << 20));
  commands.push_back({cmd, [s, technique] {
                        use_large_pages();
                        ViewSettings settings = *s;
                        settings.technique_given = technique->count() > 0;
                        return run_viewer(settings);
                      }});
}

}  // namespace farfield::cli
