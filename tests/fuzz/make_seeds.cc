// Writes one small valid input per reader into DIR/<reader>/ (the starting corpus of
// run_fuzzers.sh), using mp-mvs's own writers so every seed is a file the readers accept.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/ply_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "tests/fuzz/fuzz_readers.h"

namespace fs = std::filesystem;
using namespace mpmvs;

namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void Write(const std::string& path, const std::string& bytes) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary).write(bytes.data(), bytes.size());
}

SparseModel TinyModel() {
  SparseModel model;
  SparseCamera pinhole;
  pinhole.camera_id = 1;
  pinhole.width = 64;
  pinhole.height = 48;
  pinhole.params = {50, 51, 32, 24};
  SparseCamera simple = pinhole;
  simple.camera_id = 2;
  simple.model_id = kSimplePinholeModelId;
  simple.params = {50, 32, 24};
  model.cameras = {pinhole, simple};
  for (int i = 0; i < 2; ++i) {
    SparseImage image;
    image.image_id = i + 1;
    image.camera_id = i + 1;
    image.name = i == 0 ? "a.png" : "dir/b.png";
    image.tvec[0] = -0.5 * i;
    image.points2D = {{10, 20, 1}, {30, 20, UINT64_MAX}};
    model.images.push_back(image);
  }
  SparsePoint3D point;
  point.point3D_id = 1;
  point.xyz[2] = 4;
  point.track = {{1, 0}, {2, 0}};
  model.points = {point};
  return model;
}

std::string JoinedModel(const std::string& dir, const std::string& ext) {
  const std::string sep = fuzz::kPartSeparator;
  return ReadAll(dir + "/cameras." + ext) + sep + ReadAll(dir + "/images." + ext) + sep +
         ReadAll(dir + "/points3D." + ext);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: mpmvs_fuzz_seeds DIR\n";
    return 2;
  }
  const std::string out = argv[1];
  const std::string tmp = (fs::temp_directory_path() / "mpmvs-fuzz-seeds").string();
  fs::create_directories(tmp + "/bin");
  fs::create_directories(tmp + "/txt");
  WriteSparseModelBinary(TinyModel(), tmp + "/bin");
  WriteSparseModelText(TinyModel(), tmp + "/txt");
  Write(out + "/sparse_bin/seed_model", JoinedModel(tmp + "/bin", "bin"));
  Write(out + "/sparse_txt/seed_model", JoinedModel(tmp + "/txt", "txt"));

  Write(out + "/patch_match_cfg/seed_names", "# comment\na.png\nb.png, dir/c.png\nb.png\n__all__\n");
  Write(out + "/patch_match_cfg/seed_auto", "dir/c.png\n__auto__, 2\nd.jpg\n\n__all__\n");

  FloatMap depth(3, 2, 1, 1.5f);
  WriteFloatMap(tmp + "/depth.bin", depth);
  Write(out + "/float_map/seed_depth", std::string(1, '\1') + ReadAll(tmp + "/depth.bin"));
  FloatMap normal(2, 2, 3, 0.f);
  WriteFloatMap(tmp + "/normal.bin", normal);
  Write(out + "/float_map/seed_normal", std::string(1, '\2') + ReadAll(tmp + "/normal.bin"));
  FloatMap state(2, 2, 7, 0.25f);
  WriteFloatMap(tmp + "/state.bin", state);
  Write(out + "/stage_state/seed_state", ReadAll(tmp + "/state.bin"));

  ConsistencyGraph graph;
  graph.width = 3;
  graph.height = 2;
  graph.data = {0, 0, 2, 1, 3, 2, 1, 1, 0};
  WriteConsistencyGraph(tmp + "/graph.bin", graph);
  Write(out + "/consistency_graph/seed_graph", ReadAll(tmp + "/graph.bin"));

  PlyPointCloud cloud;
  cloud.has_normals = cloud.has_colors = true;
  cloud.points = {{1, 2, 3, 0, 0, 1, 10, 20, 30}, {4, 5, 6, 1, 0, 0, 40, 50, 60}};
  WritePlyPointCloud(tmp + "/cloud.ply", cloud);
  Write(out + "/ply/seed_binary", ReadAll(tmp + "/cloud.ply"));
  Write(out + "/ply/seed_ascii",
        "ply\nformat ascii 1.0\ncomment x\nelement vertex 2\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
        "1 2 3 4 5 6\n7 8 9 10 11 12\n");

  PfmImage pfm;
  pfm.width = 3;
  pfm.height = 2;
  pfm.data = {1, 2, 3, 4, 5, 6};
  WritePfm(tmp + "/depth.pfm", pfm);
  Write(out + "/pfm/seed_depth", ReadAll(tmp + "/depth.pfm"));

  const std::string sep = fuzz::kPartSeparator;
  Write(out + "/options/seed_args",
        "--workspace_path" + sep + "dense" + sep + "--PatchMatchStereo.max_image_size" + sep + "2000" + sep +
            "--PatchMatchStereo.geom_consistency=true" + sep + "--PatchMatchStereo.window_radius" + sep + "5" +
            sep + "--PatchMatchStereo.depth_min" + sep + "-1.5e-1");
  Write(out + "/options/seed_help", "-h");
  fs::remove_all(tmp);
  return 0;
}
