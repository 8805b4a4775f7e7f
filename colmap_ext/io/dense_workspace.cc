#include "colmap_ext/io/dense_workspace.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <unordered_map>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

constexpr char kUndistortHint[] =
    "dense stereo needs undistorted SIMPLE_PINHOLE/PINHOLE images: the workspace must be "
    "undistorted first with `colmap image_undistorter --output_type COLMAP`";

std::string Trim(const std::string& text) {
  size_t begin = 0, end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

std::vector<std::string> SplitCommaTrimmed(const std::string& text) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    fields.push_back(Trim(text.substr(start, comma == std::string::npos ? std::string::npos
                                                                       : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

void MakeK(const SparseCamera& camera, double K[9]) {
  const std::vector<double>& p = camera.params;
  const bool simple = camera.model_id == kSimplePinholeModelId;
  const double fx = p[0], fy = simple ? p[0] : p[1];
  const double cx = simple ? p[1] : p[2], cy = simple ? p[2] : p[3];
  const double values[9] = {fx, 0, cx, 0, fy, cy, 0, 0, 1};
  std::copy(values, values + 9, K);
}

void CheckView(const SparseImage& image, const SparseCamera& camera,
               const std::string& cameras_path, const std::string& images_path) {
  const std::string image_text = "image '" + image.name + "'";
  if (camera.model_id != kSimplePinholeModelId && camera.model_id != kPinholeModelId) {
    ThrowFileError(cameras_path, "camera " + std::to_string(camera.camera_id) + " of " +
                                     image_text + " has model " +
                                     CameraModelName(camera.model_id) + "; " + kUndistortHint);
  }
  if (camera.width == 0 || camera.height == 0 || camera.width > INT_MAX ||
      camera.height > INT_MAX) {
    ThrowFileError(cameras_path, "camera " + std::to_string(camera.camera_id) + " has bad size " +
                                     std::to_string(camera.width) + "x" +
                                     std::to_string(camera.height));
  }
  for (double value : camera.params) {
    if (!std::isfinite(value)) {
      ThrowFileError(cameras_path, "camera " + std::to_string(camera.camera_id) +
                                       " has a non-finite parameter");
    }
  }
  if (!(camera.params[0] > 0) ||
      (camera.model_id == kPinholeModelId && !(camera.params[1] > 0))) {
    ThrowFileError(cameras_path, "camera " + std::to_string(camera.camera_id) +
                                     " has a non-positive focal length");
  }
  double norm2 = 0;
  for (double q : image.qvec) norm2 += q * q;
  bool finite = std::isfinite(norm2);
  for (double t : image.tvec) finite = finite && std::isfinite(t);
  if (!finite || !(norm2 > 1e-12)) {
    ThrowFileError(images_path, image_text + " has an invalid pose (quaternion of zero length "
                                             "or non-finite values)");
  }
}

// COLMAP's max_image_size rule (mvs::Image::Downsize), computed in float as COLMAP does so
// that the resulting sizes agree exactly.
void ApplyMaxImageSize(int max_image_size, DenseView* view) {
  view->width = view->original_width;
  view->height = view->original_height;
  if (max_image_size <= 0) return;
  if (view->original_width <= max_image_size && view->original_height <= max_image_size) return;
  const float factor_x = static_cast<float>(max_image_size) / view->original_width;
  const float factor_y = static_cast<float>(max_image_size) / view->original_height;
  const float factor = std::min(factor_x, factor_y);
  view->width = std::max(1, static_cast<int>(std::round(view->original_width * factor)));
  view->height = std::max(1, static_cast<int>(std::round(view->original_height * factor)));
  const double scale_x = static_cast<double>(view->width) / view->original_width;
  const double scale_y = static_cast<double>(view->height) / view->original_height;
  view->K[0] *= scale_x;
  view->K[2] *= scale_x;
  view->K[4] *= scale_y;
  view->K[5] *= scale_y;
}

// Model image index of each image id.
std::unordered_map<uint32_t, int> ImageIndexById(const SparseModel& model) {
  std::unordered_map<uint32_t, int> index;
  for (size_t i = 0; i < model.images.size(); ++i) {
    index.emplace(model.images[i].image_id, static_cast<int>(i));
  }
  return index;
}

// Tracks of the sparse points as model image indices (duplicates kept, as COLMAP does).
std::vector<std::vector<int>> TracksAsViewIndices(const SparseModel& model) {
  const std::unordered_map<uint32_t, int> index = ImageIndexById(model);
  std::vector<std::vector<int>> tracks(model.points.size());
  for (size_t p = 0; p < model.points.size(); ++p) {
    for (const SparseTrackElement& element : model.points[p].track) {
      tracks[p].push_back(index.at(element.image_id));  // the reader checked the ids
    }
  }
  return tracks;
}

// Angle between the rays from two camera centres to X, folded to [0, pi/2].
double TriangulationAngle(const double c1[3], const double c2[3], const double X[3]) {
  double a[3], b[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = X[k] - c1[k];
    b[k] = X[k] - c2[k];
  }
  const double cross[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]};
  const double sin_term = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
  const double cos_term = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  if (sin_term == 0 && cos_term == 0) return 0;  // X at a camera centre
  const double angle = std::atan2(sin_term, cos_term);
  return std::min(angle, M_PI - angle);
}

// Everything __auto__ selection needs, built once per config file.
class AutoSourceSelector {
 public:
  explicit AutoSourceSelector(const DenseWorkspace& workspace)
      : workspace_(workspace), tracks_(TracksAsViewIndices(workspace.model)) {
    const size_t num_views = workspace.views.size();
    points_of_view_.resize(num_views);
    for (size_t p = 0; p < tracks_.size(); ++p) {
      for (int view_idx : tracks_[p]) {
        std::vector<size_t>& list = points_of_view_[view_idx];
        if (list.empty() || list.back() != p) list.push_back(p);
      }
    }
    centers_.resize(num_views);
    for (size_t i = 0; i < num_views; ++i) {
      const DenseView& view = workspace.views[i];
      for (int k = 0; k < 3; ++k) {  // C = -R^T T
        centers_[i][k] = -(view.R[k] * view.T[0] + view.R[3 + k] * view.T[1] +
                           view.R[6 + k] * view.T[2]);
      }
    }
  }

  std::vector<int> Select(int ref, int max_num, double min_triangulation_angle_deg) const {
    // Shared points and their triangulation angles per other view. Like COLMAP, every pair
    // of track entries (i, j) with different images counts, so an image observing a point
    // twice counts twice.
    std::unordered_map<int, std::vector<double>> angles;
    for (size_t p : points_of_view_[ref]) {
      const std::vector<int>& track = tracks_[p];
      const double* X = workspace_.model.points[p].xyz;
      for (size_t i = 0; i < track.size(); ++i) {
        for (size_t j = 0; j < i; ++j) {
          if (track[i] == track[j] || (track[i] != ref && track[j] != ref)) continue;
          const int other = track[i] == ref ? track[j] : track[i];
          angles[other].push_back(TriangulationAngle(centers_[ref].data(), centers_[other].data(), X));
        }
      }
    }
    const double min_angle_rad = min_triangulation_angle_deg * M_PI / 180.0;
    std::vector<std::pair<int, size_t>> candidates;  // (view, shared count)
    for (auto& [other, other_angles] : angles) {
      if (Percentile75(&other_angles) >= min_angle_rad) {
        candidates.emplace_back(other, other_angles.size());
      }
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
      return a.second != b.second ? a.second > b.second : a.first < b.first;
    });
    std::vector<int> sources;
    for (size_t i = 0; i < candidates.size() && static_cast<int>(i) < max_num; ++i) {
      sources.push_back(candidates[i].first);
    }
    return sources;
  }

 private:
  // COLMAP 3.8's Percentile: the element of rank round(0.75 (n-1)) (no interpolation).
  static double Percentile75(std::vector<double>* values) {
    const size_t n = values->size();
    const size_t k = std::min(n - 1, static_cast<size_t>(std::lround(0.75 * (n - 1))));
    std::nth_element(values->begin(), values->begin() + static_cast<std::ptrdiff_t>(k),
                     values->end());
    return (*values)[k];
  }

  const DenseWorkspace& workspace_;
  std::vector<std::vector<int>> tracks_;
  std::vector<std::vector<size_t>> points_of_view_;
  std::vector<std::array<double, 3>> centers_;
};

}  // namespace

void ComputeDepthRanges(DenseWorkspace* workspace) {
  const std::vector<std::vector<int>> tracks = TracksAsViewIndices(workspace->model);
  std::vector<std::vector<float>> depths(workspace->views.size());
  std::vector<double> rounding(workspace->views.size(), 0);  // largest float rounding of a z
  for (DenseView& view : workspace->views) view.num_sparse_points = 0;
  for (size_t p = 0; p < tracks.size(); ++p) {
    // COLMAP's arithmetic (mvs::Model::ComputeDepthRanges): float point, float camera,
    // Eigen's dot product order r6 x + (r7 y + r8 z), then + t_z. This file is compiled
    // without floating-point contraction (-std=c++17), so no FMA changes the rounding.
    const double* Xd = workspace->model.points[p].xyz;
    const float X[3] = {static_cast<float>(Xd[0]), static_cast<float>(Xd[1]),
                        static_cast<float>(Xd[2])};
    for (int view_idx : tracks[p]) {
      const DenseView& view = workspace->views[view_idx];
      const float r6 = static_cast<float>(view.R[6]), r7 = static_cast<float>(view.R[7]),
                  r8 = static_cast<float>(view.R[8]), tz = static_cast<float>(view.T[2]);
      const float z = r6 * X[0] + (r7 * X[1] + r8 * X[2]) + tz;
      if (z > 0) depths[view_idx].push_back(z);
      ++workspace->views[view_idx].num_sparse_points;
      const double magnitude = std::abs(Xd[0]) + std::abs(Xd[1]) + std::abs(Xd[2]) + std::abs(view.T[2]);
      rounding[view_idx] = std::max(rounding[view_idx], magnitude * 6e-8);  // about 2^-24 each term
    }
  }
  for (size_t i = 0; i < depths.size(); ++i) {
    std::vector<float>& z = depths[i];
    workspace->views[i].depth_min = -1;
    workspace->views[i].depth_max = -1;
    if (z.empty()) continue;
    std::sort(z.begin(), z.end());
    // Index = size * 0.01f / 0.99f truncated, in float like COLMAP (for n = 100, 0.99f gives
    // 99 where exact arithmetic gives 98).
    const auto index = [&](float fraction) {
      const size_t k = static_cast<size_t>(static_cast<float>(z.size()) * fraction);
      return std::min(k, z.size() - 1);
    };
    workspace->views[i].depth_min = z[index(0.01f)] * 0.75f;
    workspace->views[i].depth_max = z[index(0.99f)] * 1.25f;
    workspace->views[i].depth_range_imprecise = rounding[i] > 0.1 * z[index(0.01f)];
  }
}

int DenseWorkspace::FindView(const std::string& name) const {
  for (size_t i = 0; i < views.size(); ++i) {
    if (views[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::string DenseWorkspace::DepthMapPath(int view, const std::string& type) const {
  return JoinPaths(path, "stereo/depth_maps/" + views.at(view).name + "." + type + ".bin");
}

std::string DenseWorkspace::NormalMapPath(int view, const std::string& type) const {
  return JoinPaths(path, "stereo/normal_maps/" + views.at(view).name + "." + type + ".bin");
}

std::string DenseWorkspace::ConsistencyGraphPath(int view, const std::string& type) const {
  return JoinPaths(path, "stereo/consistency_graphs/" + views.at(view).name + "." + type + ".bin");
}

std::string DenseWorkspace::IntermediateDir() const { return JoinPaths(path, "stereo/mpmvs"); }

namespace {

// A view's image read by `read`, checked against its camera and resized to the view's
// working size (max_image_size) by `resize`.
template <class Image, class Read, class Resize>
Image ReadViewImage(const DenseWorkspace& workspace, int view_idx, const std::string& caller,
                    Read read, Resize resize) {
  if (view_idx < 0 || static_cast<size_t>(view_idx) >= workspace.views.size()) {
    throw Error(caller + ": view index " + std::to_string(view_idx) + " out of range");
  }
  const DenseView& view = workspace.views[view_idx];
  if (!FileExists(view.image_path)) {
    ThrowFileError(view.image_path, "image file is missing (listed in the sparse model as '" +
                                        view.name + "')");
  }
  Image image = read(view.image_path);
  if (image.width != view.original_width || image.height != view.original_height) {
    ThrowFileError(view.image_path,
                   "image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                       " but its camera in the sparse model is " +
                       std::to_string(view.original_width) + "x" +
                       std::to_string(view.original_height) + "; " + kUndistortHint);
  }
  if (image.width != view.width || image.height != view.height) {
    image = resize(image, view.width, view.height);
  }
  return image;
}

}  // namespace

GrayImage DenseWorkspace::ReadGray(int view_idx) const {
  return ReadViewImage<GrayImage>(*this, view_idx, "ReadGray", ReadGrayImage, ResizeGrayImage);
}

RgbImage DenseWorkspace::ReadRgb(int view_idx) const {
  return ReadViewImage<RgbImage>(*this, view_idx, "ReadRgb", ReadRgbImage, ResizeRgbImage);
}

void CheckDenseWorkspaceFolders(const std::string& path) {
  if (FileExists(path)) ThrowFileError(path, "is a file, not a folder: give the dense workspace folder");
  if (!DirectoryExists(path)) ThrowFileError(path, "dense workspace folder does not exist");
  for (const char* sub : {"images", "sparse", "stereo"}) {
    const std::string dir = JoinPaths(path, sub);
    if (FileExists(dir)) ThrowFileError(dir, "is a file, not a folder, so this is not a COLMAP dense workspace");
    if (!DirectoryExists(dir)) {
      ThrowFileError(dir, "folder is missing, so this is not a COLMAP dense workspace; create "
                          "one with `colmap image_undistorter --output_type COLMAP`");
    }
  }
}

void CheckImageNameStaysInside(const std::string& name, const std::string& images_path) {
  bool climbs = name.empty() || name.front() == '/';
  std::stringstream parts(name);
  for (std::string part; std::getline(parts, part, '/');) climbs = climbs || part == "..";
  if (climbs) {
    ThrowFileError(images_path, "image '" + name + "' names a file outside the workspace (an absolute path or "
                                "'..'); mp-mvs writes its maps under stereo/ by this name. Give it a name below "
                                "images/ in the sparse model and move the file there");
  }
}

DenseWorkspace LoadDenseWorkspace(const std::string& path, int max_image_size) {
  CheckDenseWorkspaceFolders(path);
  DenseWorkspace workspace;
  workspace.path = path;
  const std::string sparse_dir = JoinPaths(path, "sparse");
  workspace.model = ReadSparseModel(sparse_dir);
  const std::string cameras_path = SparseModelFilePath(sparse_dir, "cameras");
  const std::string images_path = SparseModelFilePath(sparse_dir, "images");
  if (workspace.model.images.empty()) ThrowFileError(images_path, "the sparse model has no images");

  std::unordered_map<uint32_t, size_t> camera_index;
  for (size_t i = 0; i < workspace.model.cameras.size(); ++i) {
    camera_index.emplace(workspace.model.cameras[i].camera_id, i);
  }
  const std::string images_dir = JoinPaths(path, "images");
  for (const SparseImage& image : workspace.model.images) {
    const SparseCamera& camera = workspace.model.cameras[camera_index.at(image.camera_id)];
    CheckImageNameStaysInside(image.name, images_path);
    CheckView(image, camera, cameras_path, images_path);
    DenseView view;
    view.name = image.name;
    view.image_path = JoinPaths(images_dir, image.name);
    view.original_width = static_cast<int>(camera.width);
    view.original_height = static_cast<int>(camera.height);
    MakeK(camera, view.K);
    QuaternionToRotationMatrix(image.qvec, view.R);
    std::copy(image.tvec, image.tvec + 3, view.T);
    ApplyMaxImageSize(max_image_size, &view);
    workspace.views.push_back(std::move(view));
  }
  ComputeDepthRanges(&workspace);
  return workspace;
}

std::vector<int> SelectSourcesAuto(const DenseWorkspace& workspace, int ref, int max_num,
                                   double min_triangulation_angle_deg) {
  if (ref < 0 || static_cast<size_t>(ref) >= workspace.views.size()) {
    throw Error("SelectSourcesAuto: view index " + std::to_string(ref) + " out of range");
  }
  return AutoSourceSelector(workspace).Select(ref, max_num, min_triangulation_angle_deg);
}

std::vector<StereoProblem> ReadPatchMatchConfig(const std::string& cfg_path,
                                                const DenseWorkspace& workspace,
                                                double min_triangulation_angle_deg) {
  if (!FileExists(cfg_path)) ThrowFileError(cfg_path, "file does not exist");
  std::ifstream file(cfg_path);
  if (!file.is_open()) ThrowFileError(cfg_path, "cannot open file for reading");

  std::unordered_map<std::string, int> view_by_name;
  for (size_t i = 0; i < workspace.views.size(); ++i) {
    view_by_name.emplace(workspace.views[i].name, static_cast<int>(i));
  }
  std::unique_ptr<AutoSourceSelector> auto_selector;  // built on first __auto__

  std::vector<StereoProblem> problems;
  int line_number = 0;
  int ref_line_number = 0;
  std::string ref_name;
  std::string raw_line;
  const auto fail = [&](int line, const std::string& what) {
    ThrowFileError(cfg_path, "line " + std::to_string(line) + ": " + what);
  };
  while (std::getline(file, raw_line)) {
    ++line_number;
    const std::string line = Trim(raw_line);
    if (line.empty() || line[0] == '#') continue;
    if (ref_name.empty()) {
      ref_name = line;
      ref_line_number = line_number;
      if (view_by_name.count(ref_name) == 0) {
        fail(line_number, "reference image '" + ref_name + "' is not in the sparse model");
      }
      continue;
    }
    StereoProblem problem;
    problem.ref = view_by_name.at(ref_name);
    const std::vector<std::string> fields = SplitCommaTrimmed(line);
    if (line == "__all__") {
      for (size_t i = 0; i < workspace.views.size(); ++i) {
        if (static_cast<int>(i) != problem.ref) problem.src.push_back(static_cast<int>(i));
      }
    } else if (fields[0] == "__auto__") {
      int max_num = 0;
      const std::string& count = fields.size() == 2 ? fields[1] : std::string();
      const auto result = std::from_chars(count.data(), count.data() + count.size(), max_num);
      if (fields.size() != 2 || result.ec != std::errc() ||
          result.ptr != count.data() + count.size() || max_num <= 0) {
        fail(line_number, "expected '__auto__, N' with a positive integer N, got '" + line + "'");
      }
      if (!auto_selector) auto_selector = std::make_unique<AutoSourceSelector>(workspace);
      problem.src = auto_selector->Select(problem.ref, max_num, min_triangulation_angle_deg);
    } else {
      for (const std::string& name : fields) {
        if (name.empty()) fail(line_number, "empty image name in source list '" + line + "'");
        const auto it = view_by_name.find(name);
        if (it == view_by_name.end()) {
          fail(line_number, "source image '" + name + "' is not in the sparse model");
        }
        // A reference is never its own source (said so); repeated names count once.
        if (it->second == problem.ref) {
          LogWarning(cfg_path + ": line " + std::to_string(line_number) + ": reference '" + ref_name +
                     "' lists itself as a source; ignored (an image is never its own source)");
        } else if (std::find(problem.src.begin(), problem.src.end(), it->second) == problem.src.end()) {
          problem.src.push_back(it->second);
        }
      }
    }
    problems.push_back(std::move(problem));
    ref_name.clear();
  }
  if (!ref_name.empty()) {
    fail(ref_line_number, "reference image '" + ref_name +
                              "' has no source line (expected __all__, __auto__, N or a list of "
                              "names)");
  }
  return problems;
}

}  // namespace mpmvs
