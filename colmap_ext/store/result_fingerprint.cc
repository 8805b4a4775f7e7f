#include "colmap_ext/store/result_fingerprint.h"

#include <cstdio>
#include <sstream>

#include "colmap_ext/store/state_record.h"

namespace mpmvs {

std::string ResultFingerprint::RunTag() const { return std::to_string(HashText(options + "\n" + problems)); }

ResultFingerprint MakeResultFingerprint(const PatchMatchStereoOptions& colmap_options, const MpMvsOptions& options,
                                        const DenseWorkspace& workspace,
                                        const std::vector<ReferenceProblem>& problems) {
  ResultFingerprint fingerprint;
  // StateOptionsText: its first line is the math revision, the others --MPMVS options.
  fingerprint.state_options = StateOptionsText(options);
  std::istringstream state(fingerprint.state_options);
  std::string method;
  std::string line;
  for (bool first = true; std::getline(state, line); first = false) method += (first ? "" : "MPMVS.") + line + "\n";
  fingerprint.options = method + ResultOptionsText(colmap_options);
  fingerprint.maps_options = method + ResultOptionsText(colmap_options, false);
  for (const ReferenceProblem& p : problems) {
    char range[64];
    std::snprintf(range, sizeof(range), " %.9g %.9g", p.depth_min, p.depth_max);
    fingerprint.problems += workspace.views[p.ref].name + range;
    // A widened depth check tolerance (exactly posed models keep the tags of earlier builds).
    if (p.depth_check_tolerance != kDepthCheckBaseTolerance) {
      std::snprintf(range, sizeof(range), " tolerance %.9g", p.depth_check_tolerance);
      fingerprint.problems += range;
    }
    fingerprint.problems += " :";
    for (int src : p.src) fingerprint.problems += " " + workspace.views[src].name;
    fingerprint.problems += "\n";
  }
  return fingerprint;
}

}  // namespace mpmvs
