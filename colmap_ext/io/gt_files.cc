#include "colmap_ext/io/gt_files.h"

namespace mpmvs {

std::string ImageStem(const std::string& image_name) {
  const size_t slash = image_name.find_last_of("/\\");
  std::string base = slash == std::string::npos ? image_name : image_name.substr(slash + 1);
  const size_t dot = base.find_last_of('.');
  if (dot != std::string::npos && dot > 0) base = base.substr(0, dot);
  return base;
}

std::string GtDepthPath(const std::string& gt_dir, const std::string& image_name) {
  return gt_dir + "/depth_" + ImageStem(image_name) + ".pfm";
}

std::string GtUntexturedMaskPath(const std::string& gt_dir, const std::string& image_name) {
  return gt_dir + "/untextured_" + ImageStem(image_name) + ".png";
}

std::string GtSurfaceLabelPath(const std::string& gt_dir, const std::string& image_name) {
  return gt_dir + "/surface_" + ImageStem(image_name) + ".png";
}

std::string GtSurfaceNamesPath(const std::string& gt_dir) { return gt_dir + "/surfaces.txt"; }

}  // namespace mpmvs
