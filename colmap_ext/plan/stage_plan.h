#pragma once
// The order of PatchMatch stages of mp_patch_match_stereo (docs/algorithm.md §0, §1):
//   gp (default): photometric mPM -> geometric pass 1 -> planar prior (from pass 1) -> geometric pass 2
//                 [-> prior2 (from pass 2) -> geometric pass 3 ...: --MPMVS.prior_rounds]
//   pp (ACMP):    photometric mPM -> planar prior (photometric selection) -> geometric x2
//   none:         photometric mPM -> geometric x2
// then, with geometric stages, a depth check of the last one's
// results against its sources' results, which writes the geometric maps.
// Each stage reads the previous stage's results of all images (Jacobi), never results of
// the same stage, so the output does not depend on the image order.
#include <string>
#include <vector>

#include "colmap_ext/options/patch_match_options.h"
#include "kernels/patch_match.h"

namespace mpmvs {

enum class StageKind { kPhotometric, kGeometric, kPlanarPrior, kDepthCheck };

struct StagePlan {
  std::string name;        // file tag in stereo/mpmvs: "photometric", "geometric1", ...
  StageKind kind = StageKind::kPhotometric;
  int input = -1;          // stage whose results initialise this one (and feed sources)
  bool prior_geometric_selection = false;  // kPlanarPrior: MP-MVS (true) or ACMP (false)
  int confirming_views = 0;                // kDepthCheck: source views that must confirm a depth
  kernels::PatchMatchSchedule schedule;
};

struct PipelinePlan {
  std::vector<StagePlan> stages;
  int photometric_output = -1;  // stage written as NAME.photometric.bin
  int geometric_output = -1;    // stage written as NAME.geometric.bin (-1: none)
};

PipelinePlan MakePipelinePlan(const PatchMatchStereoOptions& colmap_options,
                              const MpMvsOptions& options);

std::string StageKindName(StageKind kind);

// Whether stage k (-1: none) is a prior run or builds on one: its estimate then follows that
// prior's triangles, whose edges are kinks of the prior, not of the scene.
bool BuildsOnPrior(const PipelinePlan& pipeline, int k);

}  // namespace mpmvs
