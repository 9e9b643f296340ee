// What taking in streamed data costs a frame (issue 16): milliseconds a byte, learnt from the
// frames that took some in (the renderer times its uploads: FrameStats::upload_ms), weighted
// towards the last ten or so. A new GPU buffer or texture costs its memory's first touch: on
// this 2-core VM 3.6 ms a MB, so that a frame's 4 MB of streamed pages took 15 ms that a
// model of triangles and draws alone did not foresee.
#pragma once

#include <cstdint>

namespace farfield {

class UploadCost {
 public:
  void observe(uint64_t bytes, double ms) {
    if (bytes == 0 || !(ms >= 0.0)) return;
    bytes_ = kKeep * bytes_ + double(bytes);
    ms_ = kKeep * ms_ + ms;
  }
  // None before a frame that took something in was measured.
  double predict_ms(uint64_t bytes) const {
    return bytes_ > 0.0 ? ms_ / bytes_ * double(bytes) : 0.0;
  }

 private:
  static constexpr double kKeep = 0.9;
  double bytes_ = 0.0, ms_ = 0.0;
};

}  // namespace farfield
