#pragma once
// COLMAP's dense map files (`mvs::Mat<float>` layout, docs/colmap_interface.md §2):
// ASCII header "W&H&C&" then W*H*C little-endian float32, planar (channel-major),
// each plane row-major. Used for depth maps (C=1, camera z-depth, 0 = invalid) and normal
// maps (C=3, unit normal in the camera frame, (0,0,0) = invalid).
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {

struct FloatMap {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> data;  // size width*height*channels, planar

  FloatMap() = default;
  FloatMap(int w, int h, int c, float fill = 0.f)
      : width(w), height(h), channels(c), data(static_cast<size_t>(w) * h * c, fill) {}
  float& At(int row, int col, int channel = 0) {
    return data[(static_cast<size_t>(channel) * height + row) * width + col];
  }
  float At(int row, int col, int channel = 0) const {
    return data[(static_cast<size_t>(channel) * height + row) * width + col];
  }
  bool Empty() const { return data.empty(); }
};

// Throws Error naming the path for a missing file, a malformed header, sizes that do not
// match the file length (checked before allocating) or a channel count other than
// expected_channels (when >= 1).
FloatMap ReadFloatMap(const std::string& path, int expected_channels = -1);
// "" when path holds a complete width x height x channels map (header and payload length
// only, the values are not read); else why not ("file does not exist", "header says ...").
std::string CheckFloatMapFile(const std::string& path, int width, int height, int channels);
// Atomic write (temporary + rename).
void WriteFloatMap(const std::string& path, const FloatMap& map);

// COLMAP consistency graph: header "W&H&1&" then int32 records col,row,N,idx_1..idx_N for
// pixels with N > 0, row-major. Indices are model image indices.
struct ConsistencyGraph {
  int width = 0;
  int height = 0;
  std::vector<int32_t> data;  // the record stream
};
ConsistencyGraph ReadConsistencyGraph(const std::string& path);
void WriteConsistencyGraph(const std::string& path, const ConsistencyGraph& graph);

}  // namespace mpmvs
