#include "tests/fuzz/fuzz_readers.h"

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/ply_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/options/patch_match_options.h"
#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace fuzz {
namespace {

namespace fs = std::filesystem;

// One scratch folder per process, removed at exit (left behind only after a crash).
class ScratchDir {
 public:
  ScratchDir() {
    path_ = (fs::temp_directory_path() / ("mpmvs-fuzz-" + std::to_string(getpid()))).string();
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  const std::string& Path() const { return path_; }

 private:
  std::string path_;
};

const ScratchDir& Scratch() {
  static const ScratchDir dir;
  return dir;
}

std::string WriteScratch(const std::string& name, const std::string& bytes) {
  const std::string path = Scratch().File(name);
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), bytes.size());
  return path;
}

std::string WriteScratch(const std::string& name, const uint8_t* data, size_t size) {
  return WriteScratch(name, std::string(reinterpret_cast<const char*>(data), size));
}

// cameras, images, points3D as three parts; the model folder holds only this format.
void RunSparseModel(const uint8_t* data, size_t size, const std::string& ext) {
  std::vector<std::string> parts = SplitParts(data, size, 3);
  parts.resize(3);
  const char* stems[3] = {"cameras", "images", "points3D"};
  const std::string dir = Scratch().File("sparse_" + ext);
  fs::create_directories(dir);
  for (int i = 0; i < 3; ++i) {
    std::ofstream(dir + "/" + stems[i] + "." + ext, std::ios::binary | std::ios::trunc)
        .write(parts[i].data(), parts[i].size());
  }
  if (ext == "bin") {
    ReadSparseModelBinary(dir);
  } else {
    ReadSparseModelText(dir);
  }
}

void RunSparseBin(const uint8_t* data, size_t size) { RunSparseModel(data, size, "bin"); }
void RunSparseTxt(const uint8_t* data, size_t size) { RunSparseModel(data, size, "txt"); }

// A fixed workspace of four views seeing shared points, so that names, __all__ and
// __auto__ all resolve.
const DenseWorkspace& CfgWorkspace() {
  static const DenseWorkspace workspace = [] {
    DenseWorkspace w;
    w.path = Scratch().Path();
    SparseCamera camera;
    camera.camera_id = 1;
    camera.width = 64;
    camera.height = 48;
    camera.params = {50, 50, 32, 24};
    w.model.cameras.push_back(camera);
    const char* names[4] = {"a.png", "b.png", "dir/c.png", "d.jpg"};
    for (int i = 0; i < 4; ++i) {
      SparseImage image;
      image.image_id = i + 1;
      image.camera_id = 1;
      image.name = names[i];
      image.tvec[0] = -0.5 * i;
      for (int p = 0; p < 3; ++p) {
        SparsePoint2D point;
        point.x = 10 + 10 * p;
        point.y = 20;
        point.point3D_id = p + 1;
        image.points2D.push_back(point);
      }
      w.model.images.push_back(image);
      DenseView view;
      view.name = names[i];
      view.width = view.original_width = 64;
      view.height = view.original_height = 48;
      view.K[0] = view.K[4] = 50;
      view.K[2] = 32;
      view.K[5] = 24;
      view.K[8] = 1;
      view.R[0] = view.R[4] = view.R[8] = 1;
      view.T[0] = -0.5 * i;
      w.views.push_back(view);
    }
    for (int p = 0; p < 3; ++p) {
      SparsePoint3D point;
      point.point3D_id = p + 1;
      point.xyz[0] = p - 1.0;
      point.xyz[2] = 4;
      for (int i = 0; i < 4; ++i) point.track.push_back({static_cast<uint32_t>(i + 1), static_cast<uint32_t>(p)});
      w.model.points.push_back(point);
    }
    ComputeDepthRanges(&w);
    return w;
  }();
  return workspace;
}

void RunPatchMatchCfg(const uint8_t* data, size_t size) {
  ReadPatchMatchConfig(WriteScratch("patch-match.cfg", data, size), CfgWorkspace(), 1.0);
}

// Depth (1 channel), normal (3) and any-channel maps share the reader; the first byte picks
// which one is asked for so the fuzzer reaches every channel check.
void RunFloatMap(const uint8_t* data, size_t size) {
  const int expected[4] = {-1, 1, 3, -1};
  const int channels = size > 0 ? expected[data[0] % 4] : -1;
  if (size > 0) {
    ++data;
    --size;
  }
  const FloatMap map = ReadFloatMap(WriteScratch("map.bin", data, size), channels);
  if (map.data.size() != static_cast<size_t>(map.width) * map.height * map.channels) {
    throw std::logic_error("ReadFloatMap: data size differs from width*height*channels");
  }
}

void RunConsistencyGraph(const uint8_t* data, size_t size) {
  ReadConsistencyGraph(WriteScratch("graph.bin", data, size));
}

// A stage state file: a 7-channel map the size of its view (StageStore::ReadState).
void RunStageState(const uint8_t* data, size_t size) {
  const FloatMap state = ReadFloatMap(WriteScratch("view.geometric.state.bin", data, size), 7);
  if (state.channels != 7) throw std::logic_error("state file read with another channel count");
}

void RunPly(const uint8_t* data, size_t size) { ReadPlyPointCloud(WriteScratch("cloud.ply", data, size)); }

void RunPfm(const uint8_t* data, size_t size) {
  const PfmImage image = ReadPfm(WriteScratch("depth.pfm", data, size));
  if (image.data.size() != static_cast<size_t>(image.width) * image.height) {
    throw std::logic_error("ReadPfm: data size differs from width*height");
  }
}

// mp_patch_match_stereo's options, one argument per part, then the options' own checks.
void RunOptions(const uint8_t* data, size_t size) {
  std::vector<std::string> args = SplitParts(data, size, 64);
  while (!args.empty() && args.back().empty()) args.pop_back();
  std::string workspace_path;
  PatchMatchStereoOptions colmap_options;
  MpMvsOptions mpmvs_options;
  OptionParser parser;
  parser.AddRequired("workspace_path", &workspace_path, "");
  AddPatchMatchOptions(&parser, &colmap_options, &mpmvs_options);
  if (!parser.Parse(args)) return;
  std::string error;
  colmap_options.Check(&error);
  mpmvs_options.Check(&error);
  parser.Help();
}

}  // namespace

std::vector<std::string> SplitParts(const uint8_t* data, size_t size, size_t max_parts) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const size_t separator_size = std::strlen(kPartSeparator);
  std::vector<std::string> parts;
  size_t begin = 0;
  while (parts.size() + 1 < max_parts) {
    const size_t end = bytes.find(kPartSeparator, begin);
    if (end == std::string::npos) break;
    parts.push_back(bytes.substr(begin, end - begin));
    begin = end + separator_size;
  }
  parts.push_back(bytes.substr(std::min(begin, bytes.size())));
  return parts;
}

const std::vector<FuzzReader>& FuzzReaders() {
  static const std::vector<FuzzReader> readers = {
      {"sparse_bin", RunSparseBin},       {"sparse_txt", RunSparseTxt},
      {"patch_match_cfg", RunPatchMatchCfg}, {"float_map", RunFloatMap},
      {"consistency_graph", RunConsistencyGraph}, {"stage_state", RunStageState},
      {"ply", RunPly},                     {"pfm", RunPfm},
      {"options", RunOptions},
  };
  return readers;
}

const FuzzReader& FindFuzzReader(const std::string& name) {
  for (const FuzzReader& reader : FuzzReaders()) {
    if (name == reader.name) return reader;
  }
  throw std::invalid_argument("no fuzz reader named " + name);
}

int RunFuzzReader(const FuzzReader& reader, const uint8_t* data, size_t size) {
  try {
    reader.run(data, size);
  } catch (const Error&) {
    // A clear refusal naming the file: the expected outcome for damaged input.
  }
  return 0;
}

}  // namespace fuzz
}  // namespace mpmvs
