// The blobs of a bake made one viewpoint at a time (ibr, hybrid: paper 003): TECHNIQUE/view/
// NNNNN/WHAT, a viewpoint's blobs written in one transaction with `done_blob` among them, so
// that a bake killed and run again goes on from the viewpoints it has; the bake's parameters
// in the meta value TECHNIQUE/params, where a bake with other parameters erases the old
// viewpoints first.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "farfield/core/result.hpp"
#include "farfield/store/store.hpp"

namespace farfield {

class ViewpointBlobs {
 public:
  ViewpointBlobs(std::string_view technique, std::string_view done_blob)
      : technique_(technique), done_(done_blob) {}
  std::string name(uint32_t view, std::string_view what) const;
  // Before a bake of `count` viewpoints with `params`: erases another bake's viewpoints,
  // records the parameters, and says on stderr how many are kept from an earlier run.
  Result<void> start(Store& store, const std::string& params, uint32_t count) const;
  Result<bool> done(const Store& store, uint32_t view) const;
  // The parameters of the pack's bake; an error naming the pack where there are none.
  Result<std::string> params(const Store& store) const;
  // An error unless every one of `count` viewpoints is done.
  Result<void> check_complete(const Store& store, uint32_t count) const;

 private:
  std::string technique_, done_;
};

}  // namespace farfield
