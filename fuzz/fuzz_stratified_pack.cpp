// libFuzzer target for the stratified bake's readers (stratified_pack.hpp): the bake's
// parameter text, and a viewcell's blobs (done record, near objects, sides, coverage masks,
// delta-coded residuals with their reference viewcell) in a scratch pack, read back with
// read_cell and baked_cells. An accepted viewcell must hold whole, in-range data.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "farfield/techniques/stratified/stratified_pack.hpp"
#include "fuzz_pack.hpp"

namespace {

using fuzz::put;

constexpr uint32_t kObjects = 64;
constexpr int kResolution = 4;

// A viewcell's blobs from the fuzzed bytes.
void put_cell(farfield::Store& store, FuzzedDataProvider& in, const farfield::CellKey& key) {
  const std::string prefix = farfield::stratified::cell_prefix(0, key);
  put(store, prefix + "done", in.ConsumeRandomLengthString(16));
  put(store, prefix + "near", in.ConsumeRandomLengthString(64));
  for (int f = 0; f < farfield::stratified::kFaces; ++f) {
    if (!in.ConsumeBool()) continue;
    const std::string name = prefix + "face" + std::to_string(f);
    if (in.ConsumeBool()) {
      put(store, name, in.ConsumeRandomLengthString(3 * kResolution * kResolution + 8));
    } else {
      const int side = in.ConsumeBool() ? kResolution : in.ConsumeIntegralInRange(1, 8);
      farfield::Image image(side, side);
      const std::string pixels = in.ConsumeBytesAsString(image.rgb.size());
      std::copy(pixels.begin(), pixels.end(), image.rgb.begin());
      (void)store.put_image(name, image, farfield::ImageCodec::png());
    }
    if (in.ConsumeBool())
      put(store, prefix + "mask" + std::to_string(f), in.ConsumeRandomLengthString(24));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  namespace st = farfield::stratified;
  // The parameter text on its own, then fixed parameters for the viewcell blobs.
  (void)st::parse_params(in.ConsumeRandomLengthString(512));
  st::BakeParams params;
  params.resolution = kResolution;
  params.delta = in.ConsumeBool();
  params.codec = farfield::ImageCodec::png();
  params.shells = {{8.0, 1.0}};
  params.region = farfield::Bounds3{{0, 0, 0}, {4, 1, 4}};

  const std::string path = fuzz::scratch_pack("stratified");
  fuzz::remove_pack(path);
  {
    auto store = farfield::Store::open(path, farfield::Store::Mode::kReadWrite);
    if (!store) std::abort();
    const farfield::CellKey key{{0, 0, 0}}, reference{{1, 0, 0}};
    {
      auto transaction = store->begin();
      if (!transaction) std::abort();
      put_cell(*store, in, key);
      put_cell(*store, in, reference);
      (void)transaction->commit();
    }
    if (auto cells = st::baked_cells(*store, 0))
      for (const farfield::CellKey& k : *cells) {
        auto record = st::read_cell(*store, 0, k, params, kObjects);
        if (!record) continue;
        for (uint32_t object : record->near)
          if (object >= kObjects) std::abort();
        for (const st::FaceImage& face : record->faces)
          if (face.channels != 0 &&
              face.pixels.size() != size_t(face.width) * face.height * face.channels)
            std::abort();
      }
  }
  fuzz::remove_pack(path);
  return 0;
}
