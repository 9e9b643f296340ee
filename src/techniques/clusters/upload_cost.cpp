#include "farfield/techniques/clusters/upload_cost.hpp"

namespace farfield {

void UploadCost::observe(UploadBytes bytes, double ms) {
  if (bytes.total() == 0 || !(ms >= 0.0)) return;
  // In MB, so that the sums of squares stay far from double's limits.
  const double m = double(bytes.meshes) / double(1 << 20),
               t = double(bytes.textures) / double(1 << 20);
  mm_ = kKeep * mm_ + m * m;
  mt_ = kKeep * mt_ + m * t;
  tt_ = kKeep * tt_ + t * t;
  my_ = kKeep * my_ + m * ms;
  ty_ = kKeep * ty_ + t * ms;
  bytes_ = kKeep * bytes_ + (m + t);
  ms_ = kKeep * ms_ + ms;
}

UploadCost::Rates UploadCost::rates() const {
  if (!(bytes_ > 0.0)) return {};
  const double pooled = ms_ / bytes_ / double(1 << 20);
  const double det = mm_ * tt_ - mt_ * mt_;
  // Told apart only where the two kinds varied on their own (the frames' byte vectors are
  // not all on one line: the determinant is a real share of mm * tt).
  if (!(det > 1e-3 * mm_ * tt_)) return {pooled, pooled};
  const double a = (my_ * tt_ - ty_ * mt_) / det, b = (ty_ * mm_ - my_ * mt_) / det;
  if (!(a > 0.0 && b > 0.0)) return {pooled, pooled};
  return {a / double(1 << 20), b / double(1 << 20)};
}

double UploadCost::predict_ms(UploadBytes bytes) const {
  const Rates r = rates();
  return r.meshes * double(bytes.meshes) + r.textures * double(bytes.textures);
}

}  // namespace farfield
