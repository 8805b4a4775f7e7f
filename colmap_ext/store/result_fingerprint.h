#pragma once
// What a run's results depend on, besides each image's own pictures and cameras: every
// option that changes a result (the --MPMVS.* ones with the math revision, and COLMAP's
// --PatchMatchStereo.* ones) and which reference images run with which sources and depth
// ranges (patch-match.cfg or --config_path, after max_image_size). Runs that work on one
// workspace at the same time must agree on it (schedule/work_claims.h, RegisterRun): their
// intermediate results and maps would mix.
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/options/patch_match_options.h"
#include "colmap_ext/plan/reference_problems.h"

namespace mpmvs {

struct ResultFingerprint {
  std::string state_options;  // StateOptionsText: the options part of each state's fingerprint
  std::string options;   // "NAME VALUE" lines: math_revision, MPMVS.*, PatchMatchStereo.*
  // The options without those that act through the inputs (kInput: image size, depth range,
  // sources), which each image's inputs hash holds: a change of it recomputes every map.
  std::string maps_options;
  std::string problems;  // one line per runnable reference: name, depth range, sources
  // The tag runs sharing a workspace must have in common (a hash of both texts).
  std::string RunTag() const;
};

ResultFingerprint MakeResultFingerprint(const PatchMatchStereoOptions& colmap_options, const MpMvsOptions& options,
                                        const DenseWorkspace& workspace,
                                        const std::vector<ReferenceProblem>& problems);

}  // namespace mpmvs
