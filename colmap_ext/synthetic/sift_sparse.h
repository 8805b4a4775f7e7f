#pragma once
// A sparse model for a synthetic scene made the way a user's SfM makes it: from the
// rendered images alone. COLMAP's CPU SIFT features and exhaustive matches, triangulated by
// `colmap point_triangulator` with the known (exact) poses and intrinsics. Surfaces get only
// the points that matching finds on them: plain walls get few, and wrong ones if matching
// produces them.
//
// Every COLMAP step runs single-threaded (OMP_NUM_THREADS=1 too) with COLMAP's fixed random
// seed. NOT fully reproducible: COLMAP 3.8's CPU matcher (randomised FLANN kd-trees) gains
// or loses a match in a few image pairs from run to run, and so the model can differ by a
// few points between runs on the same images. The last-bit noise of COLMAP's bundle
// adjustment (its Ceres ordering follows heap addresses) is removed by rounding the point
// coordinates to `coordinate_quantum`.
#include <string>
#include <vector>

#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/synthetic/scene_renderer.h"

namespace mpmvs {

struct SiftSparseOptions {
  int max_num_features = 8192;       // SiftExtraction.max_num_features
  double coordinate_quantum = 1e-8;  // metres; point coordinates are rounded to this
  // Working folder for images, database and logs; "" = a fresh folder in the system's
  // temporary directory, removed on success (kept, and named in the error, on failure).
  std::string scratch_dir;

  void Check() const;  // throws Error
};

// names[i] is the image name of cameras[i] / images[i]; names must be in ascending order
// (COLMAP numbers the images of a new database in that order) and all cameras must share
// one set of intrinsics. The result has one PINHOLE camera with the MVS intrinsics, images
// in view order with ids 1..n and the exact poses, and only observations that have a 3-D
// point (COLMAP's SfM convention: pixel centre at +0.5), points numbered 1..N.
// Throws Error when the colmap executable is missing or a COLMAP step fails.
SparseModel TriangulateSiftSparseModel(const std::vector<SyntheticCamera>& cameras,
                                       const std::vector<std::string>& names,
                                       const std::vector<RgbImage>& images,
                                       const SiftSparseOptions& options);

// The message for a missing colmap executable (names the executable and how to set it).
std::string MissingColmapMessage(const std::string& what_for);

}  // namespace mpmvs
