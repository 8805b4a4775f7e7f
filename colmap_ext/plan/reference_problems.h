#pragma once
// The reference images of a run: patch-match.cfg's problems with their depth ranges, and
// which of them cannot run (no sources, no depth range), as COLMAP reports them.
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/options/patch_match_options.h"
#include "colmap_ext/plan/depth_check_tolerance.h"

namespace mpmvs {

struct ReferenceProblem {
  int ref = -1;
  std::vector<int> src;
  float depth_min = 0, depth_max = 0;
  // The depth check's tolerance relative to depth (depth_check_tolerance.h): one value for
  // the model.
  float depth_check_tolerance = kDepthCheckBaseTolerance;
};

struct ReferenceProblems {
  std::vector<ReferenceProblem> runnable;
  int num_skipped_no_sources = 0;
  int num_skipped_no_depth_range = 0;
  int num_skipped_missing_files = 0;  // --PatchMatchStereo.allow_missing_files
  DepthCheckTolerance depth_check;    // of the workspace's model, in every problem
};

// Reads config_path ("" = WS/stereo/patch-match.cfg), caps the sources at
// max_sources, takes the depth range from the options or the sparse points, and
// warns about each reference that cannot run. A reference listed again is ignored (with a
// warning). A missing image file is an Error naming it, or, with allow_missing_files, a
// reference skipped or a source dropped with a warning (as COLMAP). Every problem carries the
// depth check's tolerance of the workspace's model.
ReferenceProblems LoadReferenceProblems(const DenseWorkspace& workspace, const std::string& config_path,
                                        const PatchMatchStereoOptions& colmap_options,
                                        int max_sources);

}  // namespace mpmvs
