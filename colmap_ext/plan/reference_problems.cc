#include "colmap_ext/plan/reference_problems.h"

#include <set>

#include "colmap_ext/plan/kernel_camera.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// Factors on COLMAP's sparse depth range: 0.75 -> 0.25 and 1.25 -> 2.
constexpr double kSparseRangeWidening[2] = {0.25 / 0.75, 2.0 / 1.25};

// The geometric stages read the sources' results: a source that patch-match.cfg does not
// list as a reference has none. As COLMAP on missing source maps, an Error before any work;
// with allow_missing_files such sources are left out of those stages, said once per image.
void CheckSourcesAreReferences(const DenseWorkspace& workspace, const std::string& cfg, const std::set<int>& listed,
                               const PatchMatchStereoOptions& colmap_options, ReferenceProblems* problems) {
  std::set<int> missing;
  std::string example;
  for (const ReferenceProblem& p : problems->runnable) {
    for (int src : p.src) {
      if (listed.count(src) || !missing.insert(src).second || !example.empty()) continue;
      example = "source " + workspace.views[src].name + " of " + workspace.views[p.ref].name;
    }
  }
  if (missing.empty()) return;
  std::string names;
  for (int v : missing) names += (names.empty() ? "" : ", ") + workspace.views[v].name;
  if (!colmap_options.allow_missing_files) {
    ThrowFileError(cfg, std::to_string(missing.size()) + " source images are not listed as references (" + names +
                            "; e.g. " + example + "), so the geometric stages have no results of theirs. List them "
                            "as references too, or rerun with --PatchMatchStereo.allow_missing_files 1 to leave them "
                            "out of the geometric stages");
  }
  LogWarning(cfg + ": " + std::to_string(missing.size()) + " source images are not listed as references (" + names +
             "): left out of the geometric stages (--PatchMatchStereo.allow_missing_files)");
}

constexpr const char* kFarFromOrigin =
    "COLMAP's single-precision arithmetic loses the depths of points this far from the world origin (move the "
    "model's origin near the scene, e.g. with colmap model_transformer)";

// Why a view has no depth range from the sparse points: it sees none, or float rounding.
std::string NoDepthRangeReason(const DenseView& view) {
  if (view.num_sparse_points == 0) return "it sees no sparse points";
  return "it sees " + std::to_string(view.num_sparse_points) + " sparse points but " +
         (view.depth_range_imprecise || view.depth_min <= 0 ? std::string(kFarFromOrigin)
                                                            : std::string("none in front of the camera"));
}

}  // namespace

ReferenceProblems LoadReferenceProblems(const DenseWorkspace& workspace, const std::string& config_path,
                                        const PatchMatchStereoOptions& colmap_options,
                                        int max_sources) {
  const std::string cfg =
      config_path.empty() ? JoinPaths(workspace.path, "stereo/patch-match.cfg") : config_path;
  if (!FileExists(cfg)) ThrowFileError(cfg, "patch-match configuration not found");
  ReferenceProblems problems;
  // A missing picture: an Error before any work, or skipped with allow_missing_files.
  auto image_missing = [&](int v, const std::string& role) {
    const DenseView& view = workspace.views[v];
    if (FileExists(view.image_path)) return false;
    if (!colmap_options.allow_missing_files) {
      ThrowFileError(view.image_path, "image of " + role + " " + view.name +
                                          " is missing; restore it, or rerun with "
                                          "--PatchMatchStereo.allow_missing_files 1 to skip it");
    }
    return true;
  };
  problems.depth_check = DepthCheckToleranceOf(workspace);
  std::set<int> listed;
  for (const StereoProblem& spec : ReadPatchMatchConfig(cfg, workspace, colmap_options.min_triangulation_angle)) {
    ReferenceProblem p;
    p.ref = spec.ref;
    p.depth_check_tolerance = problems.depth_check.relative;
    const DenseView& view = workspace.views[p.ref];
    if (!listed.insert(p.ref).second) {
      LogWarning(cfg + ": reference " + view.name + " is listed more than once; its later entries are ignored");
      continue;
    }
    if (image_missing(p.ref, "reference")) {
      LogWarning("skipping " + view.name + ": its image " + view.image_path +
                 " is missing (--PatchMatchStereo.allow_missing_files)");
      ++problems.num_skipped_missing_files;
      continue;
    }
    for (int src : spec.src) {
      if (image_missing(src, "source")) {
        LogWarning(view.name + ": source " + workspace.views[src].name + " left out, its image " +
                   workspace.views[src].image_path + " is missing (--PatchMatchStereo.allow_missing_files)");
      } else {
        p.src.push_back(src);
      }
    }
    if (static_cast<int>(p.src.size()) > max_sources) p.src.resize(max_sources);
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
      LogWarning("skipping " + view.name + ": " + NoDepthRangeReason(view) +
                 ", so its depth range is unknown; set --PatchMatchStereo.depth_min and "
                 "--PatchMatchStereo.depth_max");
      ++problems.num_skipped_no_depth_range;
    } else {
      if (colmap_options.depth_min < 0 && view.depth_range_imprecise) {
        LogWarning(view.name + ": its depth range from the sparse points is imprecise: " + kFarFromOrigin +
                   "; set --PatchMatchStereo.depth_min and --PatchMatchStereo.depth_max");
      }
      for (int src : p.src) {  // the kernels cope; name the sources that cannot help
        const std::string why = DegenerateSourceReason(view, workspace.views[src], p.depth_min, p.depth_max);
        if (!why.empty()) LogWarning(view.name + ": source " + workspace.views[src].name + " contributes little or nothing: " + why);
      }
      problems.runnable.push_back(p);
    }
  }
  if (colmap_options.geom_consistency) CheckSourcesAreReferences(workspace, cfg, listed, colmap_options, &problems);
  return problems;
}

}  // namespace mpmvs
