#include "colmap_ext/pipeline/reference_problems.h"

#include "colmap_ext/pipeline/kernel_camera.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// Factors on COLMAP's sparse depth range: 0.75 -> 0.25 and 1.25 -> 2.
constexpr double kSparseRangeWidening[2] = {0.25 / 0.75, 2.0 / 1.25};

}  // namespace

ReferenceProblems LoadReferenceProblems(const DenseWorkspace& workspace, const std::string& config_path,
                                        const PatchMatchStereoOptions& colmap_options,
                                        int max_source_images) {
  const std::string cfg =
      config_path.empty() ? JoinPaths(workspace.path, "stereo/patch-match.cfg") : config_path;
  if (!FileExists(cfg)) ThrowFileError(cfg, "patch-match configuration not found");
  ReferenceProblems problems;
  for (const StereoProblem& spec : ReadPatchMatchConfig(cfg, workspace, colmap_options.min_triangulation_angle)) {
    ReferenceProblem p;
    p.ref = spec.ref;
    p.src = spec.src;
    if (static_cast<int>(p.src.size()) > max_source_images) p.src.resize(max_source_images);
    const DenseView& view = workspace.views[p.ref];
    if (colmap_options.depth_min > 0) {
      p.depth_min = static_cast<float>(colmap_options.depth_min);
      p.depth_max = static_cast<float>(colmap_options.depth_max);
    } else {
      // COLMAP's range (0.75 x 1st .. 1.25 x 99th percentile of the sparse depths) widened
      // to 0.25 x 1st .. 2 x 99th: floors, ceilings and walls near the camera lie closer than
      // any sparse point (kernels/DESIGN.md item 14).
      p.depth_min = static_cast<float>(view.depth_min * kSparseRangeWidening[0]);
      p.depth_max = static_cast<float>(view.depth_max * kSparseRangeWidening[1]);
    }
    if (p.src.empty()) {
      LogWarning("skipping " + view.name + ": no source images (patch-match.cfg / shared sparse points)");
      ++problems.num_skipped_no_sources;
    } else if (!(p.depth_min > 0 && p.depth_max > p.depth_min)) {
      LogWarning("skipping " + view.name +
                 ": it sees no sparse points, so its depth range is unknown; set "
                 "--PatchMatchStereo.depth_min and --PatchMatchStereo.depth_max");
      ++problems.num_skipped_no_depth_range;
    } else {
      for (int src : p.src) {  // the kernels cope; name the sources that cannot help
        const std::string why = DegenerateSourceReason(view, workspace.views[src], p.depth_min, p.depth_max);
        if (!why.empty()) LogWarning(view.name + ": source " + workspace.views[src].name + " contributes little or nothing: " + why);
      }
      problems.runnable.push_back(p);
    }
  }
  return problems;
}

}  // namespace mpmvs
