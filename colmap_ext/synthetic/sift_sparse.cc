#include "colmap_ext/synthetic/sift_sparse.h"

#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include <Eigen/Core>

#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"

namespace mpmvs {
namespace {

std::string FormatDouble(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

std::string MakeScratchDir() {
  std::error_code ec;
  std::filesystem::path base = std::filesystem::temp_directory_path(ec);
  if (ec) base = "/tmp";
  std::string pattern = (base / "mpmvs-sift-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) {
    throw Error("cannot create a temporary folder for the SIFT sparse model in " + base.string());
  }
  return pattern;
}

// Sets an environment variable for the lifetime of the object (COLMAP inherits it).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    if (had_) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_, old_.c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

void RunStep(const std::string& step, const std::vector<std::string>& args,
             const std::string& log_path) {
  std::vector<std::string> full = {step};
  full.insert(full.end(), args.begin(), args.end());
  const int code = RunColmap(full, log_path);
  if (code != 0) {
    throw Error("colmap " + step + " failed with exit code " + std::to_string(code) +
                " while making the SIFT sparse model; see " + log_path);
  }
}

// The known cameras as COLMAP's SfM sees them: keypoints put pixel centres at +0.5, so the
// principal point moves by half a pixel for the triangulation to be exact.
SparseModel KnownPosesModel(const std::vector<SyntheticCamera>& cameras,
                            const std::vector<std::string>& names) {
  SparseModel model;
  const SyntheticCamera& c = cameras[0];
  SparseCamera camera;
  camera.camera_id = 1;
  camera.model_id = kPinholeModelId;
  camera.width = c.width;
  camera.height = c.height;
  camera.params = {c.fx, c.fy, c.cx + 0.5, c.cy + 0.5};
  model.cameras.push_back(camera);
  for (size_t v = 0; v < cameras.size(); ++v) {
    SparseImage image;
    image.image_id = static_cast<uint32_t>(v + 1);
    double R[9];
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) R[3 * r + k] = cameras[v].R(r, k);
    }
    RotationMatrixToQuaternion(R, image.qvec);
    for (int k = 0; k < 3; ++k) image.tvec[k] = cameras[v].t[k];
    image.camera_id = 1;
    image.name = names[v];
    model.images.push_back(image);
  }
  return model;
}

// COLMAP's triangulated model brought to the scene's conventions (see the header).
SparseModel CleanModel(const SparseModel& triangulated, const std::vector<SyntheticCamera>& cameras,
                       const std::vector<std::string>& names, double quantum) {
  SparseModel model = KnownPosesModel(cameras, names);
  const SyntheticCamera& c = cameras[0];
  model.cameras[0].params = {c.fx, c.fy, c.cx, c.cy};  // the MVS intrinsics, as the scene's

  // Keep observed keypoints only; (image id, old index) -> new index.
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> new_index;
  for (size_t v = 0; v < cameras.size(); ++v) {
    const int found = triangulated.FindImageByName(names[v]);
    if (found < 0) continue;  // not registered: no observations
    const SparseImage& src = triangulated.images[found];
    if (src.image_id != v + 1) {
      throw Error("colmap numbered image " + names[v] + " " + std::to_string(src.image_id) +
                  ", expected " + std::to_string(v + 1));
    }
    SparseImage& dst = model.images[v];
    for (size_t i = 0; i < src.points2D.size(); ++i) {
      if (src.points2D[i].point3D_id == UINT64_MAX) continue;
      new_index[{src.image_id, static_cast<uint32_t>(i)}] =
          static_cast<uint32_t>(dst.points2D.size());
      dst.points2D.push_back(src.points2D[i]);
    }
  }
  std::vector<const SparsePoint3D*> sorted;
  for (const SparsePoint3D& p : triangulated.points) sorted.push_back(&p);
  std::sort(sorted.begin(), sorted.end(), [](const SparsePoint3D* a, const SparsePoint3D* b) {
    return a->point3D_id < b->point3D_id;
  });
  std::map<uint64_t, uint64_t> new_id;
  for (const SparsePoint3D* src : sorted) {
    SparsePoint3D p;
    p.point3D_id = model.points.size() + 1;
    new_id[src->point3D_id] = p.point3D_id;
    for (int a = 0; a < 3; ++a) {
      p.xyz[a] = std::round(src->xyz[a] / quantum) * quantum;
      p.rgb[a] = src->rgb[a];
    }
    const Eigen::Vector3d X(p.xyz[0], p.xyz[1], p.xyz[2]);
    double error_sum = 0;
    for (const SparseTrackElement& t : src->track) {
      auto it = new_index.find({t.image_id, t.point2D_idx});
      if (it == new_index.end()) throw Error("colmap's model has a track without its keypoint");
      p.track.push_back({t.image_id, it->second});
      const SparsePoint2D& obs = model.images[t.image_id - 1].points2D[it->second];
      double x, y, z;
      if (cameras[t.image_id - 1].Project(X, &x, &y, &z)) {
        error_sum += std::hypot(x + 0.5 - obs.x, y + 0.5 - obs.y);
      }
    }
    std::sort(p.track.begin(), p.track.end(), [](const SparseTrackElement& a, const SparseTrackElement& b) {
      return a.image_id != b.image_id ? a.image_id < b.image_id : a.point2D_idx < b.point2D_idx;
    });
    p.error = p.track.empty() ? 0 : error_sum / p.track.size();
    model.points.push_back(std::move(p));
  }
  for (SparseImage& image : model.images) {
    for (SparsePoint2D& obs : image.points2D) obs.point3D_id = new_id.at(obs.point3D_id);
  }
  return model;
}

}  // namespace

void SiftSparseOptions::Check() const {
  if (max_num_features < 100) throw Error("SIFT sparse model: max_num_features must be >= 100");
  if (!(coordinate_quantum > 0 && coordinate_quantum <= 1e-3)) {
    throw Error("SIFT sparse model: coordinate_quantum must be in (0, 1e-3]");
  }
}

std::string MissingColmapMessage(const std::string& what_for) {
  return what_for + " needs the COLMAP executable '" + ColmapExecutableName() +
         "' (feature_extractor, exhaustive_matcher, point_triangulator; COLMAP 3.8 or later), "
         "which was not found on PATH. Install COLMAP (apt-get install colmap) or set "
         "MPMVS_COLMAP_EXE to its path.";
}

SparseModel TriangulateSiftSparseModel(const std::vector<SyntheticCamera>& cameras,
                                       const std::vector<std::string>& names,
                                       const std::vector<RgbImage>& images,
                                       const SiftSparseOptions& options) {
  options.Check();
  const size_t n = cameras.size();
  if (n < 2 || names.size() != n || images.size() != n) {
    throw Error("SIFT sparse model: needs >= 2 views with one name and image each");
  }
  for (size_t v = 0; v < n; ++v) {
    const SyntheticCamera& a = cameras[0];
    const SyntheticCamera& b = cameras[v];
    if (a.width != b.width || a.height != b.height || a.fx != b.fx || a.fy != b.fy ||
        a.cx != b.cx || a.cy != b.cy) {
      throw Error("SIFT sparse model: all views must share one camera (intrinsics and size)");
    }
    if (v > 0 && !(names[v - 1] < names[v])) {
      throw Error("SIFT sparse model: image names must be in ascending order");
    }
  }
  if (!ColmapAvailable()) throw Error(MissingColmapMessage("The SIFT sparse model"));

  const bool own_scratch = options.scratch_dir.empty();
  const std::string scratch = own_scratch ? MakeScratchDir() : options.scratch_dir;
  const std::string image_dir = JoinPaths(scratch, "images");
  const std::string known_dir = JoinPaths(scratch, "known_poses");
  const std::string out_dir = JoinPaths(scratch, "triangulated");
  const std::string database = JoinPaths(scratch, "database.db");
  const std::string log = JoinPaths(scratch, "colmap.log");
  for (const std::string& d : {image_dir, known_dir, out_dir}) CreateDirectories(d);
  std::error_code ec;
  std::filesystem::remove(database, ec);  // a stale database would renumber the images
  for (size_t v = 0; v < n; ++v) WriteRgbPng(JoinPaths(image_dir, names[v]), images[v]);
  const SparseModel known = KnownPosesModel(cameras, names);
  WriteSparseModelText(known, known_dir);
  const std::vector<double>& k = known.cameras[0].params;

  const ScopedEnv single_openmp_thread("OMP_NUM_THREADS", "1");
  RunStep("feature_extractor",
          {"--database_path", database, "--image_path", image_dir, "--ImageReader.camera_model",
           "PINHOLE", "--ImageReader.single_camera", "1", "--ImageReader.camera_params",
           FormatDouble(k[0]) + "," + FormatDouble(k[1]) + "," + FormatDouble(k[2]) + "," +
               FormatDouble(k[3]),
           "--SiftExtraction.use_gpu", "0", "--SiftExtraction.num_threads", "1",
           "--SiftExtraction.max_num_features", std::to_string(options.max_num_features)},
          log);
  RunStep("exhaustive_matcher", {"--database_path", database, "--SiftMatching.use_gpu", "0",
                                 "--SiftMatching.num_threads", "1"},
          log);
  // Poses and intrinsics are known: bundle adjustment moves the points only.
  RunStep("point_triangulator",
          {"--database_path", database, "--image_path", image_dir, "--input_path", known_dir,
           "--output_path", out_dir, "--Mapper.num_threads", "1", "--Mapper.ba_refine_focal_length",
           "0", "--Mapper.ba_refine_principal_point", "0", "--Mapper.ba_refine_extra_params", "0"},
          log);
  SparseModel model;
  try {
    model = CleanModel(ReadSparseModel(out_dir), cameras, names, options.coordinate_quantum);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + " (COLMAP's files are in " + scratch + ")");
  }
  if (own_scratch) std::filesystem::remove_all(scratch, ec);
  return model;
}

}  // namespace mpmvs
