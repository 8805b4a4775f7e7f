#include "colmap_ext/evaluation/evaluation_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "colmap_ext/io/gt_files.h"
#include "colmap_ext/io/image_io.h"
#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/io/sparse_model.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/visualization/visualization.h"

namespace mpmvs {
namespace {

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

std::string Percent(double share) { return Fmt("%.1f", 100.0 * share); }

std::string TolName(double tolerance) { return Fmt("%g%%", 100.0 * tolerance); }

std::string PadRight(std::string s, size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

std::string PadLeft(const std::string& s, size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}

std::string Shorten(const std::string& s, size_t width) {
  return s.size() <= width ? s : "..." + s.substr(s.size() - (width - 3));
}

// "+5.54" (a share in percent, signed, two decimals).
std::string SignedPercent(double share) { return Fmt("%+.2f", 100.0 * share); }

// The line under the depth tables on the GT against the poses (CompareSparsePointsWithGt);
// "" without observations.
std::string SparseGtLine(const SparseGtAgreement& a) {
  if (a.num_observations == 0) return "";
  return "Sparse points against the GT depth: " + std::to_string(a.num_observations) +
         " observations, median relative difference " + SignedPercent(a.median_rel_difference) + " % (absolute " +
         Fmt("%.2f %%", 100.0 * a.median_abs_rel_difference) + ")\n";
}

// The warning beside it where the GT disagrees with the poses by half the tolerance or more; "" otherwise.
std::string SparseGtWarning(const SparseGtAgreement& a, double tolerance) {
  if (!GtDisagreesWithPoses(a, tolerance)) return "";
  return "warning: the GT depth and the model's poses disagree by at least half of the " + TolName(tolerance) +
         " tolerance: scores at " + TolName(tolerance) + " judge the GT as much as the depth maps\n";
}

// Width of each of a tolerance's three columns: 8, wider where its name needs it ("comp@0.5%").
size_t ScoreColumnWidth(double tolerance) {
  return std::max<size_t>(8, ("comp@" + TolName(tolerance)).size() + 1);
}

// "12.3 45.6 51.2" for acc, comp, F1 at each tolerance.
std::string ScoreCells(const DepthPixelScore& s) {
  std::string out;
  for (const DepthScoreAtTolerance& t : s.at) {
    const size_t w = ScoreColumnWidth(t.tolerance);
    out += PadLeft(Percent(t.accuracy), w) + PadLeft(Percent(t.completeness), w) + PadLeft(Percent(t.f1), w);
  }
  return out;
}

std::string DepthRow(const std::string& name, const DepthPixelScore& s, bool has_estimate) {
  std::string row = PadRight(Shorten(name, 22), 23) + PadLeft(std::to_string(s.num_gt), 9) +
                    PadLeft(s.num_gt ? Percent(static_cast<double>(s.num_estimated) / s.num_gt) : "-", 7);
  row += ScoreCells(s);
  row += PadLeft(std::isfinite(s.median_rel_error) ? Fmt("%.2f", 100 * s.median_rel_error) : "-", 9);
  if (!has_estimate) row += "  (no depth map)";
  return row;
}

// nlohmann's ordered_json keeps the keys in the order written (the schema's order);
// non-finite numbers are written as null.
using Json = nlohmann::ordered_json;

Json DepthScoreJson(const DepthPixelScore& s) {
  Json tolerances = Json::array();
  for (const DepthScoreAtTolerance& t : s.at) {
    tolerances.push_back({{"tolerance", t.tolerance}, {"num_good", t.num_good},
                          {"accuracy", t.accuracy}, {"completeness", t.completeness},
                          {"f1", t.f1}});
  }
  return {{"num_gt_pixels", s.num_gt},
          {"num_estimated_pixels", s.num_estimated},
          {"median_relative_error", s.median_rel_error},
          {"num_too_near", s.num_too_near},
          {"num_too_far", s.num_too_far},
          {"tolerances", tolerances}};
}

Json ContextJson(const ReportContext& context) {
  return {{"command", context.command},
          {"commit", context.commit.empty() ? std::string("unknown") : context.commit},
          {"protocol", "docs/evaluation.md (depth: relative tolerances; cloud: ETH3D-style)"}};
}

std::string Dump(const Json& j) { return j.dump(2) + "\n"; }

FloatMap SampleOnto(const FloatMap& map, int width, int height, int channel) {
  FloatMap out(width, height, 1);
  if (map.Empty()) return out;
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const int mr = std::min(map.height - 1, static_cast<int>(std::lround(static_cast<double>(r) * map.height / height)));
      const int mc = std::min(map.width - 1, static_cast<int>(std::lround(static_cast<double>(c) * map.width / width)));
      out.At(r, c) = map.At(mr, mc, channel);
    }
  }
  return out;
}

}  // namespace

std::string FormatScoreTable(const WorkspaceEvaluation& e) {
  const DepthEvaluation& d = e.depth;
  std::string out;
  out += "Depth maps (" + d.input_type + ") of " + e.workspace_path + " against " + e.gt_dir +
         ": " + std::to_string(d.images.size()) + " images with GT\n";
  std::string header = PadRight("image", 23) + PadLeft("GT px", 9) + PadLeft("est%", 7);
  for (double t : d.tolerances) {
    const size_t w = ScoreColumnWidth(t);
    header += PadLeft("acc@" + TolName(t), w) + PadLeft("comp@" + TolName(t), w) + PadLeft("F1@" + TolName(t), w);
  }
  header += PadLeft("med.err%", 9);
  out += header + "\n" + std::string(header.size(), '-') + "\n";
  for (const DepthImageScore& s : d.images) out += DepthRow(s.name, s.all, s.has_estimate) + "\n";
  out += std::string(header.size(), '-') + "\n";
  out += DepthRow("all pixels (pooled)", d.pooled, true) + "\n";
  if (d.has_masks) {
    out += DepthRow("untextured (pooled)", d.pooled_untextured, true) + "\n";
    for (const DepthImageScore& s : d.images) {
      if (s.has_mask) out += DepthRow("  untex. " + s.name, s.untextured, s.has_estimate) + "\n";
    }
  }
  // Named surfaces no image shows (a wall behind every camera) are left out of the tables.
  for (size_t k = 0; k < d.surface_names.size(); ++k) {
    if (d.pooled_surfaces[k].num_gt > 0) out += DepthRow("surface " + d.surface_names[k], d.pooled_surfaces[k], true) + "\n";
  }
  out += "(percentages; acc = good / estimated GT pixels, comp = good / GT pixels, good = "
         "relative depth error below the tolerance)\n";
  if (!d.surface_names.empty() && !d.tolerances.empty()) {
    // Where each surface's GT pixels end: the sign of the error says what went wrong.
    const std::string tol = TolName(d.tolerances[0]);
    const size_t within_width = std::max<size_t>(11, tol.size() + 8);
    out += "\n" + PadRight("surface (pooled)", 23) + PadLeft("GT px", 9) + PadLeft("within " + tol, within_width) +
           PadLeft("too near", 10) + PadLeft("too far", 9) + PadLeft("no depth", 10) + "\n";
    for (size_t k = 0; k < d.surface_names.size(); ++k) {
      const DepthPixelScore& s = d.pooled_surfaces[k];
      if (s.num_gt == 0) continue;
      auto share = [&](int64_t n) { return Percent(static_cast<double>(n) / s.num_gt); };
      out += PadRight(Shorten(d.surface_names[k], 22), 23) + PadLeft(std::to_string(s.num_gt), 9) +
             PadLeft(share(s.at.empty() ? 0 : s.at[0].num_good), within_width) + PadLeft(share(s.num_too_near), 10) +
             PadLeft(share(s.num_too_far), 9) + PadLeft(share(s.num_gt - s.num_estimated), 10) + "\n";
    }
    out += "(percent of the surface's GT pixels; too near / too far: off by " + tol + " or more)\n";
  }
  const std::string sparse_line = SparseGtLine(e.sparse_vs_gt);
  if (!sparse_line.empty()) {
    out += "\n" + sparse_line;
    if (!d.tolerances.empty()) out += SparseGtWarning(e.sparse_vs_gt, d.tolerances[0]);
  }
  if (e.has_cloud) {
    const PointCloudEvaluation& c = e.cloud;
    out += "\nPoint cloud " + c.fused_path + ": " + std::to_string(c.num_points) + " points (" +
           std::to_string(c.num_observed) + " over observed GT); GT cloud " +
           std::to_string(c.num_gt_points) + " points, median GT depth " +
           Fmt("%.3f", c.median_gt_depth) + "\n";
    for (const CloudScoreAtTolerance& t : c.at) {
      out += "  tolerance " + PadLeft(TolName(t.relative_tolerance), 5) + " (" +
             Fmt("%.4g", t.tolerance) + "): accuracy " + PadLeft(Percent(t.accuracy), 5) +
             "%  completeness " + PadLeft(Percent(t.completeness), 5) + "%  F1 " +
             PadLeft(Percent(t.f1), 5) + "%\n";
    }
  }
  return out;
}

void PrintScoreTable(const WorkspaceEvaluation& evaluation) {
  std::cout << FormatScoreTable(evaluation) << std::flush;
}

std::string FormatComparisonTable(const std::vector<WorkspaceEvaluation>& evals) {
  if (evals.empty()) return "";
  const size_t name_w = 30;
  size_t col_w = 10;
  for (const WorkspaceEvaluation& e : evals) col_w = std::max(col_w, std::min<size_t>(24, e.label.size() + 2));
  std::string out = PadRight("scores in % (" + evals[0].depth.input_type + ")", name_w);
  for (const WorkspaceEvaluation& e : evals) out += PadLeft(Shorten(e.label, col_w - 2), col_w);
  out += "\n" + std::string(name_w + col_w * evals.size(), '-') + "\n";
  auto row = [&](const std::string& name, auto value_of) {
    out += PadRight(name, name_w);
    for (const WorkspaceEvaluation& e : evals) out += PadLeft(value_of(e), col_w);
    out += "\n";
  };
  const std::vector<double>& tols = evals[0].depth.tolerances;
  for (size_t k = 0; k < tols.size(); ++k) {
    const std::string t = TolName(tols[k]);
    row("depth F1@" + t, [&](const WorkspaceEvaluation& e) { return k < e.depth.pooled.at.size() ? Percent(e.depth.pooled.at[k].f1) : "-"; });
    row("depth accuracy@" + t, [&](const WorkspaceEvaluation& e) { return k < e.depth.pooled.at.size() ? Percent(e.depth.pooled.at[k].accuracy) : "-"; });
    row("depth completeness@" + t, [&](const WorkspaceEvaluation& e) { return k < e.depth.pooled.at.size() ? Percent(e.depth.pooled.at[k].completeness) : "-"; });
  }
  const bool any_masks = std::any_of(evals.begin(), evals.end(), [](const WorkspaceEvaluation& e) { return e.depth.has_masks; });
  if (any_masks) {
    for (size_t k = 0; k < tols.size(); ++k) {
      row("untextured F1@" + TolName(tols[k]), [&](const WorkspaceEvaluation& e) {
        return e.depth.has_masks && k < e.depth.pooled_untextured.at.size() ? Percent(e.depth.pooled_untextured.at[k].f1) : "-";
      });
    }
  }
  row("median rel. depth error", [](const WorkspaceEvaluation& e) {
    return std::isfinite(e.depth.pooled.median_rel_error) ? Fmt("%.2f", 100 * e.depth.pooled.median_rel_error) : "-";
  });
  row("sparse points vs GT (median)", [](const WorkspaceEvaluation& e) {
    return e.sparse_vs_gt.num_observations ? SignedPercent(e.sparse_vs_gt.median_rel_difference) : "-";
  });
  const bool any_cloud = std::any_of(evals.begin(), evals.end(), [](const WorkspaceEvaluation& e) { return e.has_cloud; });
  if (any_cloud) {
    const WorkspaceEvaluation* first = nullptr;
    for (const WorkspaceEvaluation& e : evals) {
      if (e.has_cloud && !first) first = &e;
    }
    for (size_t k = 0; k < first->cloud.at.size(); ++k) {
      const std::string t = TolName(first->cloud.at[k].relative_tolerance);
      row("cloud F1@" + t, [&](const WorkspaceEvaluation& e) { return e.has_cloud && k < e.cloud.at.size() ? Percent(e.cloud.at[k].f1) : "-"; });
      row("cloud accuracy@" + t, [&](const WorkspaceEvaluation& e) { return e.has_cloud && k < e.cloud.at.size() ? Percent(e.cloud.at[k].accuracy) : "-"; });
      row("cloud completeness@" + t, [&](const WorkspaceEvaluation& e) { return e.has_cloud && k < e.cloud.at.size() ? Percent(e.cloud.at[k].completeness) : "-"; });
    }
    row("fused points", [](const WorkspaceEvaluation& e) { return e.has_cloud ? std::to_string(e.cloud.num_points) : "-"; });
  }
  if (!tols.empty()) {
    // The workspaces usually share one model and GT: the warning once, from the first that disagrees.
    for (const WorkspaceEvaluation& e : evals) {
      const std::string warning = SparseGtWarning(e.sparse_vs_gt, tols[0]);
      if (!warning.empty()) {
        out += warning;
        break;
      }
    }
    out += "per image F1@" + TolName(tols[0]) + ":\n";
    for (size_t i = 0; i < evals[0].depth.images.size(); ++i) {
      const std::string& name = evals[0].depth.images[i].name;
      row("  " + Shorten(name, name_w - 3), [&](const WorkspaceEvaluation& e) -> std::string {
        for (const DepthImageScore& s : e.depth.images) {
          if (s.name == name) return s.has_estimate ? Percent(s.all.at[0].f1) : "missing";
        }
        return "-";
      });
    }
  }
  return out;
}

std::string FormatAgreementTable(const std::vector<std::string>& labels,
                                 const std::vector<PairAgreement>& pairs, double tolerance) {
  std::string out = "Agreement without GT: share (%) of pixels estimated by both whose depths "
                    "agree within " + TolName(tolerance) + " (both% = pixels estimated by both)\n";
  const size_t name_w = 24, col_w = 22;
  out += PadRight("image", name_w);
  for (const PairAgreement& p : pairs) {
    out += PadLeft(Shorten(labels[p.a], 9) + " vs " + Shorten(labels[p.b], 9), col_w);
  }
  out += "\n" + std::string(name_w + col_w * pairs.size(), '-') + "\n";
  auto cell = [](const AgreementCounts& c, bool present) -> std::string {
    if (!present) return "missing";
    return Percent(c.AgreeShare()) + " (both " +
           (c.num_pixels ? Percent(static_cast<double>(c.num_both) / c.num_pixels) : std::string("-")) + ")";
  };
  if (!pairs.empty()) {
    for (size_t i = 0; i < pairs[0].images.size(); ++i) {
      out += PadRight(Shorten(pairs[0].images[i].name, name_w - 1), name_w);
      for (const PairAgreement& p : pairs) {
        const ImageAgreement& ia = p.images[i];
        out += PadLeft(cell(ia.counts, ia.present_a && ia.present_b), col_w);
      }
      out += "\n";
    }
  }
  out += std::string(name_w + col_w * pairs.size(), '-') + "\n" + PadRight("all (pooled)", name_w);
  for (const PairAgreement& p : pairs) out += PadLeft(cell(p.pooled, true), col_w);
  return out + "\n";
}

std::string EvaluationJson(const std::vector<WorkspaceEvaluation>& evaluations,
                           const ReportContext& context) {
  Json j = ContextJson(context);
  Json& workspaces = j["workspaces"] = Json::array();
  for (const WorkspaceEvaluation& e : evaluations) {
    Json depth = {{"input_type", e.depth.input_type},
                  {"tolerances", e.depth.tolerances},
                  {"pooled", DepthScoreJson(e.depth.pooled)}};
    if (e.depth.has_masks) depth["pooled_untextured"] = DepthScoreJson(e.depth.pooled_untextured);
    if (!e.depth.surface_names.empty()) {
      Json& surfaces = depth["pooled_surfaces"] = Json::array();
      for (size_t k = 0; k < e.depth.surface_names.size(); ++k) {
        surfaces.push_back({{"name", e.depth.surface_names[k]}, {"all", DepthScoreJson(e.depth.pooled_surfaces[k])}});
      }
    }
    Json& images = depth["images"] = Json::array();
    for (const DepthImageScore& s : e.depth.images) {
      Json image = {{"name", s.name}, {"has_estimate", s.has_estimate}, {"all", DepthScoreJson(s.all)}};
      if (s.has_mask) image["untextured"] = DepthScoreJson(s.untextured);
      images.push_back(std::move(image));
    }
    Json w = {{"label", e.label}, {"workspace_path", e.workspace_path}, {"gt_dir", e.gt_dir},
              {"depth", std::move(depth)}};
    if (e.sparse_vs_gt.num_observations > 0) {
      w["sparse_points_vs_gt"] = {{"num_observations", e.sparse_vs_gt.num_observations},
                                  {"median_relative_difference", e.sparse_vs_gt.median_rel_difference},
                                  {"median_absolute_relative_difference", e.sparse_vs_gt.median_abs_rel_difference}};
    }
    if (e.has_cloud) {
      const PointCloudEvaluation& c = e.cloud;
      Json tolerances = Json::array();
      for (const CloudScoreAtTolerance& t : c.at) {
        tolerances.push_back({{"relative_tolerance", t.relative_tolerance}, {"tolerance", t.tolerance},
                              {"accuracy", t.accuracy}, {"completeness", t.completeness},
                              {"f1", t.f1}});
      }
      w["point_cloud"] = {{"fused_path", c.fused_path},
                          {"num_points", c.num_points},
                          {"num_observed_points", c.num_observed},
                          {"num_gt_points", c.num_gt_points},
                          {"median_gt_depth", c.median_gt_depth},
                          {"tolerances", std::move(tolerances)}};
    }
    workspaces.push_back(std::move(w));
  }
  return Dump(j);
}

std::string AgreementJson(const std::vector<std::string>& labels,
                          const std::vector<PairAgreement>& pairs, double tolerance,
                          const std::string& input_type, const ReportContext& context) {
  auto counts = [](const AgreementCounts& c) -> Json {
    return {{"num_pixels", c.num_pixels}, {"num_a", c.num_a},         {"num_b", c.num_b},
            {"num_both", c.num_both},     {"num_agree", c.num_agree}, {"agree_share", c.AgreeShare()}};
  };
  Json j = ContextJson(context);
  j["input_type"] = input_type;
  j["tolerance"] = tolerance;
  j["labels"] = labels;
  Json& pairs_json = j["pairs"] = Json::array();
  for (const PairAgreement& p : pairs) {
    Json images = Json::array();
    for (const ImageAgreement& ia : p.images) {
      images.push_back({{"name", ia.name}, {"present_a", ia.present_a},
                        {"present_b", ia.present_b}, {"counts", counts(ia.counts)}});
    }
    pairs_json.push_back({{"a", labels[p.a]}, {"b", labels[p.b]}, {"pooled", counts(p.pooled)},
                          {"images", std::move(images)}});
  }
  return Dump(j);
}

void WriteJsonFile(const std::string& path, const std::string& json) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << json; });
}

std::vector<std::string> WriteEvaluationPictures(const WorkspaceEvaluation& evaluation,
                                                 const std::string& out_dir) {
  CreateDirectories(out_dir);
  const SparseModel model = ReadSparseModel(JoinPaths(evaluation.workspace_path, "sparse"));
  const std::vector<GtView> gt = LoadGtViews(model, evaluation.gt_dir);
  const std::string& type = evaluation.depth.input_type;
  const double max_error = 2.0 * *std::max_element(evaluation.depth.tolerances.begin(),
                                                   evaluation.depth.tolerances.end());
  std::vector<std::string> written;
  for (const GtView& v : gt) {
    const int W = v.depth.width, H = v.depth.height;
    FloatMap gt_map(W, H, 1);
    gt_map.data = v.depth.data;
    double dmin = 0, dmax = 1;
    RobustRange(gt_map.data, 0.01, 0.99, &dmin, &dmax);

    const std::string depth_path = JoinPaths(evaluation.workspace_path,
                                             "stereo/depth_maps/" + v.name + "." + type + ".bin");
    const std::string normal_path = JoinPaths(evaluation.workspace_path,
                                              "stereo/normal_maps/" + v.name + "." + type + ".bin");
    const bool has_estimate = FileExists(depth_path);
    const FloatMap estimate = has_estimate ? ReadFloatMap(depth_path, 1) : FloatMap();
    const FloatMap est_on_gt = SampleOnto(estimate, W, H, 0);

    std::vector<RgbImage> tiles;
    const std::string image_path = JoinPaths(evaluation.workspace_path, "images/" + v.name);
    if (FileExists(image_path)) {
      RgbImage image = ReadRgbImage(image_path);
      tiles.push_back(TitledPicture(image, "input " + v.name));
    }
    tiles.push_back(DepthPicture(gt_map, dmin, dmax, "GT depth"));
    tiles.push_back(DepthPicture(est_on_gt, dmin, dmax,
                                 has_estimate ? "estimated depth (" + type + ")" : "no depth map"));
    std::vector<float> error(static_cast<size_t>(W) * H, std::nanf(""));
    for (size_t i = 0; i < error.size(); ++i) {
      const float g = v.depth.data[i];
      if (!(std::isfinite(g) && g > 0)) continue;
      const float z = est_on_gt.data[i];
      error[i] = (std::isfinite(z) && z > 0) ? std::abs(z - g) / g : -std::numeric_limits<float>::infinity();
    }
    ScalarPictureOptions eo;
    eo.value_min = 0;
    eo.value_max = max_error;
    eo.title = "rel. depth error (grey: none)";
    eo.unit = "%";
    eo.label_factor = 100;
    tiles.push_back(ScalarPicture(error, W, H, eo));
    if (FileExists(normal_path)) {
      const FloatMap normal = ReadFloatMap(normal_path, 3);
      FloatMap normal_on_gt(W, H, 3);
      for (int ch = 0; ch < 3; ++ch) {
        const FloatMap plane = SampleOnto(normal, W, H, ch);
        std::copy(plane.data.begin(), plane.data.end(), normal_on_gt.data.begin() + static_cast<size_t>(ch) * W * H);
      }
      tiles.push_back(NormalPicture(normal_on_gt, "estimated normals"));
    }
    if (!v.untextured.empty()) {
      // Where walls go wrong: the same errors on untextured pixels only, and the planar
      // prior's own error there (is the prior right?) when the run kept its model.
      std::vector<float> untextured_error(error.size(), std::nanf(""));
      for (size_t i = 0; i < error.size(); ++i) {
        if (v.untextured[i]) untextured_error[i] = error[i];
      }
      eo.title = "error on untextured pixels";
      tiles.push_back(ScalarPicture(untextured_error, W, H, eo));
      const std::string prior_path =
          JoinPaths(evaluation.workspace_path, "stereo/mpmvs/pictures/" + v.name + ".prior.prior_model.bin");
      if (FileExists(prior_path)) {
        const FloatMap prior = SampleOnto(ReadFloatMap(prior_path, 1), W, H, 0);
        std::vector<float> prior_error(error.size(), std::nanf(""));
        for (size_t i = 0; i < error.size(); ++i) {
          const float g = v.depth.data[i], z = prior.data[i];
          if (!v.untextured[i] || !(std::isfinite(g) && g > 0)) continue;
          prior_error[i] = z > 0 ? std::abs(z - g) / g : -std::numeric_limits<float>::infinity();
        }
        eo.title = "planar prior error, untextured";
        tiles.push_back(ScalarPicture(prior_error, W, H, eo));
      }
      RgbImage mask = MakeRgbImage(W, H, RgbColor{0, 0, 0});
      for (size_t i = 0; i < v.untextured.size(); ++i) {
        const uint8_t m = v.untextured[i] ? 255 : 0;
        mask.data[3 * i] = mask.data[3 * i + 1] = mask.data[3 * i + 2] = m;
      }
      tiles.push_back(TitledPicture(mask, "untextured (white)"));
    }
    const std::string path = JoinPaths(out_dir, ImageStem(v.name) + "_eval.png");
    WriteRgbPng(path, TilePictures(tiles, 3));
    written.push_back(path);
  }
  return written;
}

}  // namespace mpmvs
