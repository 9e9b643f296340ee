// libFuzzer target for the bake record reader (store/bake_record.hpp): any text as a
// technique's NAME/bake metadata. An accepted record must write back and read the same.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "farfield/store/bake_record.hpp"
#include "fuzz_pack.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::scratch_pack("bake-record");
  fuzz::remove_pack(path);
  {
    auto store = farfield::Store::open(path, farfield::Store::Mode::kReadWrite);
    if (!store) std::abort();
    (void)store->set_meta("octree/bake", std::string(reinterpret_cast<const char*>(data), size));
    auto record = farfield::read_bake_record(*store, "octree");
    if (record && *record) {
      if (farfield::write_bake_record(*store, **record)) {
        auto again = farfield::read_bake_record(*store, "octree");
        if (!again || !*again || (*again)->settings != (*record)->settings ||
            (*again)->format != (*record)->format || (*again)->scene != (*record)->scene)
          std::abort();
      }
      (void)farfield::usable_bake(*store, "octree", 1, 0);
    }
  }
  fuzz::remove_pack(path);
  return 0;
}
