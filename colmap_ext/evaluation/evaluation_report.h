#pragma once
// Human-readable and machine-readable results of evaluation.h: a printed table per
// workspace, side-by-side tables for several workspaces (against GT, or their mutual
// agreement without GT), JSON files, and per-image PNG panels (input, GT depth, estimated
// depth, error map, normals, untextured mask).
#include <string>
#include <vector>

#include "colmap_ext/evaluation/evaluation.h"

namespace mpmvs {

// Recorded in JSON files so a number can be traced back to how it was made.
struct ReportContext {
  std::string command;  // the command line
  std::string commit;   // source revision ("unknown" when not known)
};

std::string FormatScoreTable(const WorkspaceEvaluation& evaluation);
void PrintScoreTable(const WorkspaceEvaluation& evaluation);  // to stdout

// Scores of several workspaces of one scene, one column per workspace (label).
std::string FormatComparisonTable(const std::vector<WorkspaceEvaluation>& evaluations);

// Mutual agreement (share of pixels estimated by both whose depths agree within the
// tolerance), per image and pooled, one column per pair.
std::string FormatAgreementTable(const std::vector<std::string>& labels,
                                 const std::vector<PairAgreement>& pairs, double tolerance);

// {"context": ..., "workspaces": [ {depth: {pooled, untextured, images[]}, cloud: ...} ]}
std::string EvaluationJson(const std::vector<WorkspaceEvaluation>& evaluations,
                           const ReportContext& context);
std::string AgreementJson(const std::vector<std::string>& labels,
                          const std::vector<PairAgreement>& pairs, double tolerance,
                          const std::string& input_type, const ReportContext& context);
// Atomic text write of a JSON document.
void WriteJsonFile(const std::string& path, const std::string& json);

// Writes out_dir/<stem>_eval.png for every evaluated image: input image, GT depth and
// estimated depth (same colour scale), relative depth error (0 .. 2 x largest tolerance;
// grey = GT but no estimate), estimated normals, untextured mask when present. Returns
// the written paths.
std::vector<std::string> WriteEvaluationPictures(const WorkspaceEvaluation& evaluation,
                                                 const std::string& out_dir);

}  // namespace mpmvs
