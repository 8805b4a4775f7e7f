#pragma once
// The paper's ablation (its Table 1): ACMH, mPM+ACMH, mPM+rs, mPM+ACMH+pp, mPM+rs+pp,
// mPM+rs+gp, each run as mp_patch_match_stereo with the matching --MPMVS options on a copy
// of one workspace, fused by `colmap stereo_fusion` and scored against ground truth
// (docs/evaluation.md).
#include <string>
#include <vector>

#include "colmap_ext/evaluation/evaluation.h"
#include "colmap_ext/evaluation/evaluation_report.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"

namespace mpmvs {

struct AblationRow {
  std::string name;  // e.g. "mPM+rs+gp"
  MpMvsOptions options;
};

// The six rows, built on top of `base` (seed, iterations, ...).
std::vector<AblationRow> PaperAblationRows(const MpMvsOptions& base);

struct AblationRowResult {
  std::string name;
  MpMvsOptions options;  // the row's --MPMVS options
  MpPatchMatchSummary summary;
  WorkspaceEvaluation evaluation;
  std::string workspace_path;
};

struct AblationOptions {
  std::string workspace_path;  // a COLMAP dense workspace (images/, sparse/, stereo/*.cfg)
  std::string gt_path;         // folder with depth_<stem>.pfm
  std::string output_path;     // one sub-folder per row
  std::vector<std::string> rows;  // names to run; empty = all six
  bool fuse = true;            // run colmap stereo_fusion and score the point cloud
  PatchMatchStereoOptions colmap_options;
  MpMvsOptions options;
};

std::vector<AblationRowResult> RunAblation(const AblationOptions& options);

// Table: per row depth-map and point-cloud accuracy / completeness / F1 at both tolerances,
// run time, and the window sides and propagation pattern the photometric stage used.
std::string FormatAblationTable(const std::vector<AblationRowResult>& rows);

// ablation.json: EvaluationJson of the rows' workspaces, each with its row name, the values of
// its options that change results and its run time.
std::string AblationJson(const std::vector<AblationRowResult>& rows, const ReportContext& context);

}  // namespace mpmvs
