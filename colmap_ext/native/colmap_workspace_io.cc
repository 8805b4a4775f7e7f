#include "colmap_ext/native/colmap_workspace_io.h"

#include <algorithm>
#include <array>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "colmap/mvs/consistency_graph.h"
#include "colmap/mvs/depth_map.h"
#include "colmap/mvs/model.h"
#include "colmap/mvs/normal_map.h"
#include "colmap/mvs/workspace.h"
#include "colmap/scene/reconstruction.h"
#include "colmap/sensor/bitmap.h"
#include "colmap/util/version.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

constexpr char kUndistortHint[] =
    "dense stereo needs undistorted SIMPLE_PINHOLE/PINHOLE images: the workspace must be "
    "undistorted first with `colmap image_undistorter --output_type COLMAP`";

// COLMAP 3.12 uses std::string paths, 4.x std::filesystem::path; both convert.
template <typename PathLike>
std::string PathString(const PathLike& path) {
  return std::filesystem::path(path).string();
}

// Red channel (the grey value) of one pixel. COLMAP 4.1 returns the pixel as
// std::optional<BitmapColor>; 3.12 - 4.0 fill a BitmapColor through a pointer. The int/long
// tag makes the 4.1 form win where it compiles.
template <typename BitmapT>
auto GreyPixel(const BitmapT& bitmap, int x, int y, int) -> decltype(bitmap.GetPixel(x, y)->r) {
  return bitmap.GetPixel(x, y)->r;
}
template <typename BitmapT>
uint8_t GreyPixel(const BitmapT& bitmap, int x, int y, long) {
  colmap::BitmapColor<uint8_t> color;
  bitmap.GetPixel(x, y, &color);
  return color.r;
}

class ColmapWorkspaceIo : public WorkspaceIo {
 public:
  std::string Name() const override { return colmap::GetVersionInfo() + " mvs::Workspace"; }

  DenseWorkspace Load(const std::string& path, int max_image_size) override {
    CheckDenseWorkspaceFolders(path);
    const std::string sparse_dir = JoinPaths(path, "sparse");

    // The cameras: COLMAP's mvs::Model keeps only K, so check the camera models here.
    std::unordered_map<std::string, std::pair<int, int>> original_size;
    try {
      colmap::Reconstruction reconstruction;
      reconstruction.Read(sparse_dir);
      for (const auto& [camera_id, camera] : reconstruction.Cameras()) {
        if (camera.model_id != colmap::CameraModelId::kSimplePinhole &&
            camera.model_id != colmap::CameraModelId::kPinhole) {
          ThrowFileError(sparse_dir, "camera " + std::to_string(camera_id) + " has model " +
                                         camera.ModelName() + "; " + kUndistortHint);
        }
      }
      for (const auto& [image_id, image] : reconstruction.Images()) {
        const colmap::Camera& camera = reconstruction.Camera(image.CameraId());
        original_size[image.Name()] = {static_cast<int>(camera.width),
                                       static_cast<int>(camera.height)};
      }
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      ThrowFileError(sparse_dir, std::string("COLMAP cannot read the sparse model: ") + e.what());
    }

    // COLMAP's workspace: mvs::Model in COLMAP's model image order, images downsized by
    // COLMAP (mvs::Image::Downsize) when max_image_size is set.
    colmap::mvs::Workspace::Options options;
    options.max_image_size = max_image_size > 0 ? max_image_size : -1;
    options.image_as_rgb = false;
    options.workspace_path = path;
    options.workspace_format = "COLMAP";
    options.input_type = "photometric";
    std::unique_ptr<colmap::mvs::Workspace> workspace;
    try {
      workspace = std::make_unique<colmap::mvs::Workspace>(options);
    } catch (const std::exception& e) {
      ThrowFileError(sparse_dir, std::string("COLMAP cannot load the workspace: ") + e.what());
    }
    const colmap::mvs::Model& model = workspace->GetModel();
    if (model.images.empty()) ThrowFileError(sparse_dir, "the sparse model has no images");

    DenseWorkspace dense;
    dense.path = path;
    for (size_t i = 0; i < model.images.size(); ++i) {
      const colmap::mvs::Image& image = model.images[i];
      DenseView view;
      view.name = model.GetImageName(static_cast<int>(i));
      CheckImageNameStaysInside(view.name, sparse_dir);
      view.image_path = PathString(workspace->GetBitmapPath(static_cast<int>(i)));
      view.width = static_cast<int>(image.GetWidth());
      view.height = static_cast<int>(image.GetHeight());
      const auto size = original_size.find(view.name);
      view.original_width = size != original_size.end() ? size->second.first : view.width;
      view.original_height = size != original_size.end() ? size->second.second : view.height;
      for (int k = 0; k < 9; ++k) view.K[k] = image.GetK()[k];
      for (int k = 0; k < 9; ++k) view.R[k] = image.GetR()[k];
      for (int k = 0; k < 3; ++k) view.T[k] = image.GetT()[k];
      dense.views.push_back(std::move(view));

      SparseImage sparse_image;  // what __auto__ selection and depth ranges need
      sparse_image.image_id = static_cast<uint32_t>(i + 1);
      sparse_image.name = dense.views.back().name;
      dense.model.images.push_back(std::move(sparse_image));
    }
    // mvs::Model keeps no reprojection errors, which the depth check's tolerance reads
    // (plan/depth_check_tolerance.h): take them from the model files as colmap-mp reads them,
    // matched by position (mvs::Model's float coordinates).
    std::map<std::array<float, 3>, double> point_errors;
    try {
      for (const SparsePoint3D& point : ReadSparseModel(sparse_dir).points) {
        point_errors[{static_cast<float>(point.xyz[0]), static_cast<float>(point.xyz[1]),
                      static_cast<float>(point.xyz[2])}] = point.error;
      }
    } catch (const Error& e) {
      LogWarning(std::string(e.what()) + ": without the sparse points' reprojection errors the depth check "
                 "confirms within 1 %");
    }
    dense.model.points.reserve(model.points.size());
    for (size_t p = 0; p < model.points.size(); ++p) {
      const colmap::mvs::Model::Point& point = model.points[p];
      SparsePoint3D sparse_point;
      sparse_point.point3D_id = p + 1;
      sparse_point.xyz[0] = point.x;
      sparse_point.xyz[1] = point.y;
      sparse_point.xyz[2] = point.z;
      const auto error = point_errors.find({point.x, point.y, point.z});
      sparse_point.error = error != point_errors.end() ? error->second : -1;  // -1: none, left out
      for (const int image_idx : point.track) {
        sparse_point.track.push_back({static_cast<uint32_t>(image_idx + 1), 0});
      }
      dense.model.points.push_back(std::move(sparse_point));
    }
    // Depth ranges: mp-mvs's float replica of Model::ComputeDepthRanges, shared with
    // colmap-mp so both front ends agree bit for bit; compared with COLMAP's own here.
    ComputeDepthRanges(&dense);
    const std::vector<std::pair<float, float>> colmap_ranges = model.ComputeDepthRanges();
    int identical = 0;
    for (size_t i = 0; i < dense.views.size(); ++i) {
      identical += static_cast<float>(dense.views[i].depth_min) == colmap_ranges[i].first &&
                   static_cast<float>(dense.views[i].depth_max) == colmap_ranges[i].second;
    }
    LogInfo(Name() + ": " + std::to_string(dense.views.size()) + " images, " +
            std::to_string(dense.model.points.size()) + " sparse points; depth ranges equal to " +
            "mvs::Model::ComputeDepthRanges for " + std::to_string(identical) + " of " +
            std::to_string(dense.views.size()) + " images");
    return dense;
  }

  GrayImage ReadGray(const DenseWorkspace& workspace, int view_idx) override {
    if (view_idx < 0 || static_cast<size_t>(view_idx) >= workspace.views.size()) {
      throw Error("ReadGray: view index " + std::to_string(view_idx) + " out of range");
    }
    const DenseView& view = workspace.views[view_idx];
    if (!FileExists(view.image_path)) {
      ThrowFileError(view.image_path, "image file is missing (listed in the sparse model as '" +
                                          view.name + "')");
    }
    colmap::Bitmap bitmap;
    if (!bitmap.Read(view.image_path, /*as_rgb=*/false)) {
      ThrowFileError(view.image_path, "COLMAP cannot read this image");
    }
    if (bitmap.Width() != view.original_width || bitmap.Height() != view.original_height) {
      ThrowFileError(view.image_path,
                     "image is " + std::to_string(bitmap.Width()) + "x" +
                         std::to_string(bitmap.Height()) + " but its camera in the sparse model is " +
                         std::to_string(view.original_width) + "x" +
                         std::to_string(view.original_height) + "; " + kUndistortHint);
    }
    if (bitmap.Width() != view.width || bitmap.Height() != view.height) {
      bitmap.Rescale(view.width, view.height);  // as mvs::Workspace does for max_image_size
    }
    GrayImage gray;
    gray.width = view.width;
    gray.height = view.height;
    gray.data.resize(static_cast<size_t>(gray.width) * gray.height);
    for (int row = 0; row < gray.height; ++row) {
      for (int col = 0; col < gray.width; ++col) {
        gray.data[static_cast<size_t>(row) * gray.width + col] = GreyPixel(bitmap, col, row, 0);
      }
    }
    return gray;
  }

  void WriteDepthMap(const std::string& path, const FloatMap& depth, float depth_min,
                     float depth_max) override {
    CheckMap(path, depth, 1);
    colmap::mvs::DepthMap map(depth.width, depth.height, depth_min, depth_max);
    std::copy(depth.data.begin(), depth.data.end(), map.GetPtr());
    WriteFileViaTemporaryPath(path, [&](const std::string& tmp_path) { map.Write(tmp_path); });
  }

  void WriteNormalMap(const std::string& path, const FloatMap& normal) override {
    CheckMap(path, normal, 3);
    colmap::mvs::NormalMap map(normal.width, normal.height);
    std::copy(normal.data.begin(), normal.data.end(), map.GetPtr());
    WriteFileViaTemporaryPath(path, [&](const std::string& tmp_path) { map.Write(tmp_path); });
  }

  void WriteConsistencyGraph(const std::string& path, const ConsistencyGraph& graph) override {
    const std::vector<int> data(graph.data.begin(), graph.data.end());
    const colmap::mvs::ConsistencyGraph colmap_graph(graph.width, graph.height, data);
    WriteFileViaTemporaryPath(path,
                              [&](const std::string& tmp_path) { colmap_graph.Write(tmp_path); });
  }

 private:
  static void CheckMap(const std::string& path, const FloatMap& map, int channels) {
    if (map.width <= 0 || map.height <= 0 || map.channels != channels ||
        map.data.size() != static_cast<size_t>(map.width) * map.height * map.channels) {
      ThrowFileError(path, "cannot write a map of size " + std::to_string(map.width) + "x" +
                               std::to_string(map.height) + "x" + std::to_string(map.channels) +
                               " holding " + std::to_string(map.data.size()) + " values");
    }
  }
};

}  // namespace

std::unique_ptr<WorkspaceIo> MakeColmapWorkspaceIo() {
  return std::make_unique<ColmapWorkspaceIo>();
}

}  // namespace mpmvs
