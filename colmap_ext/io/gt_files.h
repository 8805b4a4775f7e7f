#pragma once
// Naming of ground-truth files beside a dataset (docs/evaluation.md §1): gt/depth_<stem>.pfm and
// gt/untextured_<stem>.png, where <stem> is the image name without folders and extension;
// optional named surfaces: gt/surface_<stem>.png (grey value k: the surface on line k of
// gt/surfaces.txt, 0: none).
#include <string>

namespace mpmvs {

// "a/b/view_00.png" -> "view_00"; a name without extension is kept whole.
std::string ImageStem(const std::string& image_name);
std::string GtDepthPath(const std::string& gt_dir, const std::string& image_name);
std::string GtUntexturedMaskPath(const std::string& gt_dir, const std::string& image_name);
std::string GtSurfaceLabelPath(const std::string& gt_dir, const std::string& image_name);
std::string GtSurfaceNamesPath(const std::string& gt_dir);

}  // namespace mpmvs
