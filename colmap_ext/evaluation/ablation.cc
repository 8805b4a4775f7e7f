#include "colmap_ext/evaluation/ablation.h"

#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "colmap_ext/util/colmap_runner.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"
#include "kernels/half_resolution.h"
#include "kernels/ncc.h"

namespace mpmvs {

namespace fs = std::filesystem;

std::vector<AblationRow> PaperAblationRows(const MpMvsOptions& base) {
  auto row = [&](const std::string& name, int max_scale, bool distant, const std::string& prior) {
    AblationRow r;
    r.name = name;
    r.options = base;
    r.options.max_window_scale = max_scale;
    r.options.distant_sampling = distant;
    r.options.planar_prior = prior;
    return r;
  };
  return {row("ACMH", 0, false, "none"),          row("mPM+ACMH", base.max_window_scale, false, "none"),
          row("mPM+rs", base.max_window_scale, true, "none"),
          row("mPM+ACMH+pp", base.max_window_scale, false, "photometric"),
          row("mPM+rs+pp", base.max_window_scale, true, "photometric"),
          row("mPM+rs+gp", base.max_window_scale, true, "geometric")};
}

namespace {

// A fresh copy of the workspace's inputs (images, sparse, configuration), no outputs.
void CopyWorkspaceInputs(const std::string& from, const std::string& to) {
  fs::create_directories(to);
  for (const char* dir : {"images", "sparse"}) {
    const fs::path dst = fs::path(to) / dir;
    if (!fs::exists(dst)) fs::copy(fs::path(from) / dir, dst, fs::copy_options::recursive);
  }
  for (const char* dir : {"stereo/depth_maps", "stereo/normal_maps", "stereo/consistency_graphs"}) {
    fs::create_directories(fs::path(to) / dir);
  }
  for (const char* cfg : {"stereo/patch-match.cfg", "stereo/fusion.cfg"}) {
    const fs::path src = fs::path(from) / cfg;
    if (!fs::exists(src)) ThrowFileError(src.string(), "missing; is this a dense workspace from image_undistorter?");
    fs::copy_file(src, fs::path(to) / cfg, fs::copy_options::overwrite_existing);
  }
}

std::string PatternName(kernels::PatternKind kind) {
  return kind == kernels::PatternKind::kDistant ? "distant" : "acmh";
}

}  // namespace

std::vector<AblationRowResult> RunAblation(const AblationOptions& options) {
  std::vector<AblationRow> rows = PaperAblationRows(options.options);
  if (!options.rows.empty()) {
    std::set<std::string> wanted(options.rows.begin(), options.rows.end());
    std::vector<AblationRow> kept;
    for (const AblationRow& r : rows) {
      if (wanted.erase(r.name)) kept.push_back(r);
    }
    if (!wanted.empty()) {
      throw Error("unknown ablation row '" + *wanted.begin() +
                  "' (rows: ACMH, mPM+ACMH, mPM+rs, mPM+ACMH+pp, mPM+rs+pp, mPM+rs+gp)");
    }
    rows = kept;
  }
  const bool fuse = options.fuse && ColmapAvailable();
  if (options.fuse && !fuse) LogWarning("colmap not found: rows are scored on depth maps only");
  std::vector<AblationRowResult> results;
  for (const AblationRow& row : rows) {
    LogHeading("ablation row " + row.name);
    AblationRowResult result;
    result.name = row.name;
    result.options = row.options;
    std::string dir_name = row.name;
    for (char& c : dir_name) {
      if (c == '+') c = '_';
    }
    result.workspace_path = JoinPaths(options.output_path, dir_name);
    CopyWorkspaceInputs(options.workspace_path, result.workspace_path);
    MpPatchMatchRun run;
    run.workspace_path = result.workspace_path;
    run.colmap_options = options.colmap_options;
    run.options = row.options;
    result.summary = RunMpPatchMatchStereo(run);
    std::string fused = "none";
    if (fuse) {
      fused = JoinPaths(result.workspace_path, "fused.ply");
      const int num_images = static_cast<int>(std::distance(
          fs::directory_iterator(JoinPaths(result.workspace_path, "images")), fs::directory_iterator{}));
      RunStereoFusion(result.workspace_path, "geometric", fused, num_images,
                      JoinPaths(result.workspace_path, "stereo_fusion.log"));
    }
    EvaluationOptions eval;
    eval.input_type = run.colmap_options.geom_consistency ? "geometric" : "photometric";
    result.evaluation = EvaluateWorkspace(result.workspace_path, options.gt_path, fused, eval);
    result.evaluation.label = row.name;
    results.push_back(std::move(result));
  }
  return results;
}

std::string FormatAblationTable(const std::vector<AblationRowResult>& rows) {
  std::ostringstream ss;
  char line[512];
  std::snprintf(line, sizeof(line), "%-12s | %-23s | %-23s | %-23s | %-23s | %-23s | %8s | %s\n", "row",
                "depth 1%: acc comp F1", "depth 2%: acc comp F1", "untextured 1%: acc comp F1",
                "cloud 0.5%: acc comp F1", "cloud 1%: acc comp F1", "time s", "photometric stage");
  ss << line << std::string(176, '-') << "\n";
  for (const AblationRowResult& r : rows) {
    auto depth_at = [&](size_t i, bool untextured = false) {
      // Untextured: the GT's untextured mask (synthetic scenes); "-" without one.
      const DepthPixelScore& d = untextured ? r.evaluation.depth.pooled_untextured : r.evaluation.depth.pooled;
      char buf[64];
      if (i < d.at.size() && d.num_gt > 0) {
        std::snprintf(buf, sizeof(buf), "%6.1f %6.1f %6.1f", 100 * d.at[i].accuracy, 100 * d.at[i].completeness,
                      100 * d.at[i].f1);
      } else {
        std::snprintf(buf, sizeof(buf), "%20s", "-");
      }
      return std::string(buf);
    };
    auto cloud_at = [&](size_t i) {
      char buf[64];
      if (r.evaluation.has_cloud && i < r.evaluation.cloud.at.size()) {
        const CloudScoreAtTolerance& c = r.evaluation.cloud.at[i];
        std::snprintf(buf, sizeof(buf), "%6.1f %6.1f %6.1f", 100 * c.accuracy, 100 * c.completeness, 100 * c.f1);
      } else {
        std::snprintf(buf, sizeof(buf), "%20s", "-");
      }
      return std::string(buf);
    };
    // The windows' sides in full-resolution pixels (a half-resolution window covers the one of
    // the next scale), "h" where the images ran at half resolution.
    std::string windows, pattern;
    if (!r.summary.stages.empty()) {
      std::string last;
      for (const kernels::IterationStats& it : r.summary.stages.front().iterations) {
        const int scale = kernels::FullResolutionScale(it.window_scale, it.half_resolution);
        const std::string side =
            std::to_string(kernels::WindowSide(kernels::WindowForScale(scale))) + (it.half_resolution ? "h" : "");
        if (side != last) windows += (windows.empty() ? "" : "/") + side;
        last = side;
        pattern = PatternName(it.pattern);
      }
    }
    std::snprintf(line, sizeof(line), "%-12s | %-23s | %-23s | %-23s | %-23s | %-23s | %8.1f | windows %s px, %s\n",
                  r.name.c_str(), depth_at(0).c_str(), depth_at(1).c_str(), depth_at(0, true).c_str(),
                  cloud_at(0).c_str(), cloud_at(1).c_str(), r.summary.seconds, windows.c_str(), pattern.c_str());
    ss << line;
  }
  return ss.str();
}

std::string AblationJson(const std::vector<AblationRowResult>& rows, const ReportContext& context) {
  std::vector<WorkspaceEvaluation> evaluations;
  for (const AblationRowResult& r : rows) evaluations.push_back(r.evaluation);
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(EvaluationJson(evaluations, context));
  for (size_t k = 0; k < rows.size(); ++k) {
    nlohmann::ordered_json options = nlohmann::ordered_json::object();
    std::istringstream lines(ResultOptionsText(rows[k].options));
    for (std::string name, value; lines >> name >> value;) options[name] = value;
    nlohmann::ordered_json& w = j["workspaces"][k];
    w["row"] = rows[k].name;
    w["seconds"] = rows[k].summary.seconds;
    w["options"] = std::move(options);
  }
  return j.dump(2) + "\n";
}

}  // namespace mpmvs
