// A stratified bake in a .ffpack store (docs/ffpack.md, docs/techniques/stratified.md).
//
//   meta stratified/params   the bake's settings (text, one key=value per line)
//   stratified/sI/CELL/near  shell 0 only: the viewcell's near objects (uint32, zstd)
//   stratified/sI/CELL/faceF the far field on box side F (JPEG or PNG; with delta coding a PNG
//                            of the byte-wise difference to the reference viewcell's side)
//   stratified/sI/CELL/maskF coverage of side F (zstd), for every shell but the outermost
//   stratified/sI/CELL/done  written last in the viewcell's transaction: which sides exist and
//                            the reference viewcell of a delta-coded one
//
// A viewcell is baked when its `done` blob exists: each viewcell is one transaction, so a bake
// killed at any point resumes with the viewcells it had finished.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "farfield/core/bounds.hpp"
#include "farfield/core/result.hpp"
#include "farfield/store/store.hpp"
#include "farfield/techniques/stratified/box_faces.hpp"
#include "farfield/spatial/viewcell_tree.hpp"

namespace farfield::stratified {

struct ShellParams {
  double box = 0, viewcell = 0;
};

// What a bake was made with; a resumed bake must match it.
struct BakeParams {
  uint64_t scene = 0;  // scene_fingerprint
  double alpha_deg = 0;
  Bounds3 region;
  std::vector<ShellParams> shells;  // innermost first
  int resolution = 0;
  ImageCodec codec;
  bool delta = false;
};
std::string to_text(const BakeParams& params);
Result<BakeParams> parse_params(const std::string& text);  // the message says what is wrong

inline constexpr const char* kParamsKey = "stratified/params";
std::string cell_prefix(int shell, const CellKey& key);  // "stratified/s0/CELL/"

// One side's pixels once decoded: RGB, or RGBA with coverage for inner shells.
struct FaceImage {
  int width = 0, height = 0, channels = 0;  // channels 0: the side has no far field
  std::vector<uint8_t> pixels;
};

struct CellRecord {
  std::vector<uint32_t> near;  // shell 0
  std::array<FaceImage, kFaces> faces;
  std::optional<CellKey> reference;  // delta coding
};

// Writes a viewcell (one transaction, `done` last). With `reference` (delta coding, PNG only)
// the sides are stored as differences to that record's sides.
Result<void> write_cell(Store& store, int shell, const CellKey& key, const CellRecord& record,
                        const BakeParams& params, const CellRecord* reference,
                        const std::optional<CellKey>& reference_key);

// Reads a baked viewcell, resolving delta coding; `object_count` bounds the near ids. Errors
// name the pack and the blob; a viewcell that is not baked is an error too.
Result<CellRecord> read_cell(const Store& store, int shell, const CellKey& key,
                             const BakeParams& params, uint32_t object_count);

// The baked viewcells of a shell, from the `done` names.
Result<std::vector<CellKey>> baked_cells(const Store& store, int shell);

}  // namespace farfield::stratified
