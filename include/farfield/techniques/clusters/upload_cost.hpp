// What taking in streamed data costs a frame (issue 16): milliseconds a byte of meshes and a
// byte of textures, learnt from the frames that took some in (the renderer times its uploads:
// FrameStats::upload_ms), weighted towards the last ten or so. A new GPU buffer or texture
// costs its memory's first touch (on this 2-core VM 3.6 ms a MB with 4 KB pages), and a
// texture its mipmaps besides: on the 100M street a 512^2 box tile took 5.3 ms a MB against
// the pages' meshes' 1.7, so that one rate for both priced the frames that took tiles in at
// half their cost. The two rates are the least-squares fit of each frame's time to its two
// byte counts; while they cannot be told apart (one kind seen so far, or always in the same
// proportion), both are the pooled rate.
#pragma once

#include <cstdint>

#include "farfield/gpu/draw_list.hpp"

namespace farfield {

class UploadCost {
 public:
  void observe(UploadBytes bytes, double ms);
  // None before a frame that took something in was measured.
  double predict_ms(UploadBytes bytes) const;
  double ms_per_mesh_byte() const { return rates().meshes; }
  double ms_per_texture_byte() const { return rates().textures; }

 private:
  struct Rates {
    double meshes = 0.0, textures = 0.0;
  };
  Rates rates() const;
  static constexpr double kKeep = 0.9;
  // Decayed sums: bytes (m: meshes, t: textures) against milliseconds (y).
  double mm_ = 0.0, mt_ = 0.0, tt_ = 0.0, my_ = 0.0, ty_ = 0.0;
  double bytes_ = 0.0, ms_ = 0.0;  // pooled
};

}  // namespace farfield
