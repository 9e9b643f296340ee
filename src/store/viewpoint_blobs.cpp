#include "farfield/store/viewpoint_blobs.hpp"

#include <cstdio>

namespace farfield {

std::string ViewpointBlobs::name(uint32_t view, std::string_view what) const {
  char number[16];
  std::snprintf(number, sizeof number, "%05u", view);
  return technique_ + "/view/" + number + "/" + std::string(what);
}

Result<void> ViewpointBlobs::start(Store& store, const std::string& params, uint32_t count) const {
  auto previous = store.get_meta(technique_ + "/params");
  if (!previous) return previous.error();
  if (*previous && **previous != params)
    if (auto erased = store.erase(technique_ + "/"); !erased) return erased.error();
  if (auto ok = store.set_meta(technique_ + "/params", params); !ok) return ok;
  uint32_t kept = 0;
  for (uint32_t id = 0; id < count; ++id) {
    auto is_done = done(store, id);
    if (!is_done) return is_done.error();
    kept += *is_done;
  }
  if (kept > 0)
    std::fprintf(stderr, "%s: %u of %u viewpoints already kept in the pack; continuing\n",
                 technique_.c_str(), kept, count);
  return {};
}

Result<bool> ViewpointBlobs::done(const Store& store, uint32_t view) const {
  return store.contains(name(view, done_));
}

Result<std::string> ViewpointBlobs::params(const Store& store) const {
  auto params = store.get_meta(technique_ + "/params");
  if (!params) return params.error();
  if (!*params)
    return make_error(store.path(), ": its ", technique_, " bake has no parameters; re-bake it");
  return **params;
}

Result<void> ViewpointBlobs::check_complete(const Store& store, uint32_t count) const {
  for (uint32_t id = 0; id < count; ++id) {
    auto is_done = done(store, id);
    if (!is_done) return is_done.error();
    if (!*is_done)
      return make_error(store.path(), ": its ", technique_, " bake lacks viewpoint ",
                        std::to_string(id), " of ", std::to_string(count),
                        "; run the bake again to finish it");
  }
  return {};
}

}  // namespace farfield
