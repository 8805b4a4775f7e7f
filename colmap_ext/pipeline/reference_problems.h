#pragma once
// The reference images of a run: patch-match.cfg's problems with their depth ranges, and
// which of them cannot run (no sources, no depth range), as COLMAP reports them.
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/pipeline/patch_match_options.h"

namespace mpmvs {

struct ReferenceProblem {
  int ref = -1;
  std::vector<int> src;
  float depth_min = 0, depth_max = 0;
};

struct ReferenceProblems {
  std::vector<ReferenceProblem> runnable;
  int num_skipped_no_sources = 0;
  int num_skipped_no_depth_range = 0;
};

// Reads config_path ("" = WS/stereo/patch-match.cfg), caps the sources at
// max_source_images, takes the depth range from the options or the sparse points, and
// warns about each reference that cannot run.
ReferenceProblems LoadReferenceProblems(const DenseWorkspace& workspace, const std::string& config_path,
                                        const PatchMatchStereoOptions& colmap_options,
                                        int max_source_images);

}  // namespace mpmvs
