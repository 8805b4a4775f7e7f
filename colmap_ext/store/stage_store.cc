#include "colmap_ext/store/stage_store.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/plan/kernel_camera.h"
#include "colmap_ext/prior/chroma_guide.h"
#include "colmap_ext/prior/image_noise.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// Channels of a stage result file: plane (4), cost, photometric cost, geometric error.
constexpr int kStateChannels = 7;

FloatMap ResultToState(const kernels::PatchMatchResult& r) {
  FloatMap state(r.width, r.height, kStateChannels);
  const size_t n = static_cast<size_t>(r.width) * r.height;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) state.data[c * n + i] = r.plane[4 * i + c];
    state.data[4 * n + i] = r.cost[i];
    state.data[5 * n + i] = r.photo_cost[i];
    state.data[6 * n + i] = r.geo_error[i];
  }
  return state;
}

kernels::PatchMatchResult StateToResult(const FloatMap& state) {
  kernels::PatchMatchResult r;
  const size_t n = static_cast<size_t>(state.width) * state.height;
  r.width = state.width;
  r.height = state.height;
  r.plane.resize(4 * n);
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 4; ++c) r.plane[4 * i + c] = state.data[c * n + i];
  }
  r.cost.assign(state.data.begin() + 4 * n, state.data.begin() + 5 * n);
  r.photo_cost.assign(state.data.begin() + 5 * n, state.data.begin() + 6 * n);
  r.geo_error.assign(state.data.begin() + 6 * n, state.data.begin() + 7 * n);
  r.view_mask.assign(n, 0u);
  return r;
}

size_t CacheBytes(const std::vector<float>& values) { return values.size() * sizeof(float); }

}  // namespace

std::vector<float> ResultDepth(const kernels::PatchMatchResult& result, const kernels::Camera& camera,
                               float depth_min, float depth_max) {
  const int W = result.width, H = result.height;
  std::vector<float> depth(static_cast<size_t>(W) * H, 0.f);
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const size_t i = static_cast<size_t>(v) * W + u;
      if (!(result.photo_cost[i] < kernels::kInvalidCost)) continue;
      const float* p = &result.plane[4 * i];
      const kernels::Plane plane{{p[0], p[1], p[2]}, p[3]};
      const float z = kernels::PlaneDepth(plane, kernels::PixelRay(camera, float(u), float(v)));
      if (z >= depth_min && z <= depth_max) depth[i] = z;
    }
  }
  return depth;
}

StageStore::StageStore(const DenseWorkspace& workspace, WorkspaceIo* io, const RunPlan& plan,
                       const std::vector<ReferenceProblem>& problems, const ResultFingerprint& fingerprint)
    : workspace_(workspace),
      io_(io),
      plan_(plan),
      fingerprint_(fingerprint),
      images_(plan.cache_bytes / 16 * 5, [this](const int& view) { return io_->ReadGray(workspace_, view); },
              [](const GrayImage& img) { return CacheBytes(img.data); }),
      chroma_guides_(plan.cache_bytes / 16 * 5, [this](const int& view) { return ReadChromaGuide(view); },
                     CacheBytes),
      depths_(plan.cache_bytes / 16 * 5,
              [this](const std::pair<int, int>& key) {
                const int view = key.second;
                const ReferenceProblem& p = problems_.at(view);
                return ResultDepth(ReadState(view, plan_.pipeline.stages[key.first].name),
                                   ToKernelCamera(workspace_.views[view]), p.depth_min, p.depth_max);
              },
              CacheBytes),
      plain_windows_(plan.cache_bytes / 16,
                     [this](const std::pair<int, int>& key) {
                       const std::shared_ptr<const GrayImage> image = Image(key.first);
                       return kernels::PlainWindowMaskCpu(
                           kernels::ImageView{image->data.data(), image->width, image->height},
                           kernels::WindowForScale(key.second), NoiseVariance(key.first), plan_.num_threads);
                     },
                     [](const std::vector<uint8_t>& mask) { return mask.size(); }) {
  for (const ReferenceProblem& p : problems) problems_.emplace(p.ref, p);
}

float StageStore::NoiseVariance(int view) {
  auto it = noise_variances_.find(view);
  if (it == noise_variances_.end()) it = noise_variances_.emplace(view, EstimateNoiseVariance(*Image(view))).first;
  return it->second;
}

std::string StageStore::StatePath(int view, const std::string& stage) const {
  return JoinPaths(workspace_.IntermediateDir(), workspace_.views[view].name + "." + stage + ".state.bin");
}

std::string StageStore::StateRecordPath(int view, const std::string& stage) const {
  return JoinPaths(workspace_.IntermediateDir(), workspace_.views[view].name + "." + stage + ".state.json");
}

bool StageStore::HasState(int view, const std::string& stage) {
  if (!problems_.count(view) || !FileExists(StatePath(view, stage))) return false;
  // Judged again when the files change: another process may write or replace them while
  // this one waits (the state first, then its record).
  const std::string stamp = StateStamp(view, stage);
  StateVerdict& verdict = state_usable_[{view, stage}];
  if (verdict.stamp != stamp) {
    bool changed = false;
    const std::string why = CheckState(view, stage, &changed);
    if (!why.empty() && why != verdict.why) {
      // Other options or inputs are no damage: said once, not once per state.
      if (!changed) {
        LogWarning(StatePath(view, stage) + ": not resumed, " + why + "; recomputing it");
      } else if (!options_change_reported_) {
        LogInfo(StatePath(view, stage) + ": not resumed, " + why +
                "; recomputing it and every intermediate result of other options or inputs");
        options_change_reported_ = true;
      }
    }
    verdict = {why.empty(), why, stamp};
  }
  return verdict.usable;
}

std::string StageStore::StateStamp(int view, const std::string& stage) const {
  std::string stamp;
  for (const std::string& path : {StatePath(view, stage), StateRecordPath(view, stage)}) {
    std::error_code ec;
    const auto time = std::filesystem::last_write_time(path, ec);
    const auto size = ec ? 0 : std::filesystem::file_size(path, ec);
    stamp += ec ? std::string("- ")
                : std::to_string(time.time_since_epoch().count()) + ":" + std::to_string(size) + " ";
  }
  return stamp;
}

std::string StageStore::CheckState(int view, const std::string& stage, bool* changed) {
  StateRecord record;
  std::string why;
  *changed = false;
  if (!ReadStateRecord(StateRecordPath(view, stage), &record, &why)) return why;
  const StateRecord expected = ExpectedRecord(view, stage);
  *changed = true;
  if (record.stage != stage || record.width != expected.width || record.height != expected.height) {
    return "its record is of stage " + record.stage + " at " + std::to_string(record.width) + "x" +
           std::to_string(record.height) + ", expected " + stage + " at " + std::to_string(expected.width) + "x" +
           std::to_string(expected.height);
  }
  if (record.options != expected.options) return "it was made with other --MPMVS options";
  if (record.inputs != expected.inputs) {
    return "it was made from other images, cameras, depth range, source images or depth check tolerance";
  }
  *changed = false;
  try {
    const FloatMap state = ReadFloatMap(StatePath(view, stage), kStateChannels);
    if (state.width != expected.width || state.height != expected.height) return "its size differs from the image";
    if (StateChecksum(state) != record.checksum) return "its values do not match its checksum (damaged)";
  } catch (const Error& e) {
    return std::string("it is damaged (") + e.what() + ")";
  }
  return "";
}

StateRecord StageStore::ExpectedRecord(int view, const std::string& stage) {
  StateRecord record;
  record.stage = stage;
  record.width = workspace_.views[view].width;
  record.height = workspace_.views[view].height;
  // The stage and the stages it builds on: their names and kinds follow from the options.
  std::string chain;
  for (int s = 0; s < static_cast<int>(plan_.pipeline.stages.size()); ++s) {
    if (plan_.pipeline.stages[s].name != stage) continue;
    for (int k = s; k >= 0; k = plan_.pipeline.stages[k].input) {
      chain += plan_.pipeline.stages[k].name + "/" + StageKindName(plan_.pipeline.stages[k].kind) + " ";
    }
  }
  record.options = HashText(fingerprint_.state_options + "stages " + chain + "\n");
  record.inputs = InputsHash(view, IsDepthCheckStage(stage));
  return record;
}

bool StageStore::IsDepthCheckStage(const std::string& stage) const {
  for (const StagePlan& s : plan_.pipeline.stages) {
    if (s.name == stage) return s.kind == StageKind::kDepthCheck;
  }
  return false;
}

bool StageStore::MapsFromDepthCheck(const std::string& type) const {
  const int k = type == "geometric" ? plan_.pipeline.geometric_output : plan_.pipeline.photometric_output;
  return k >= 0 && plan_.pipeline.stages[k].kind == StageKind::kDepthCheck;
}

uint64_t StageStore::InputsHash(int view, bool depth_check) const {
  const ReferenceProblem& p = problems_.at(view);
  char range[64];
  std::snprintf(range, sizeof(range), "%.9g %.9g", p.depth_min, p.depth_max);
  std::string inputs = "reference " + ViewIdentity(view) + "depth range " + range + "\n";
  // Only the depth check's results depend on its rule and tolerance, so only its records name
  // them: the rule's revision and a widened model tolerance.
  if (depth_check) {
    inputs += "depth check revision " + std::to_string(kDepthCheckRevision) + "\n";
    if (p.depth_check_tolerance != kDepthCheckBaseTolerance) {
      std::snprintf(range, sizeof(range), "%.9g", p.depth_check_tolerance);
      inputs += "depth check tolerance " + std::string(range) + "\n";
    }
  }
  for (int src : p.src) inputs += "source " + ViewIdentity(src);
  return HashText(inputs);
}

std::string StageStore::ViewIdentity(int view) const {
  auto it = view_identities_.find(view);
  if (it != view_identities_.end()) return it->second;
  const DenseView& v = workspace_.views[view];
  std::ostringstream s;
  s.precision(17);
  s << v.name << " " << v.width << "x" << v.height << " K";
  for (double x : v.K) s << " " << x;
  s << " R";
  for (double x : v.R) s << " " << x;
  s << " T";
  for (double x : v.T) s << " " << x;
  // The picture's bytes (a missing or unreadable picture fails later, where it is read).
  uint64_t image_hash = 0;
  try {
    const std::vector<uint8_t> bytes = ReadFileBytes(v.image_path);
    image_hash = HashBytes(bytes.data(), bytes.size());
  } catch (const Error&) {
  }
  s << " image " << image_hash << "\n";
  return view_identities_.emplace(view, s.str()).first->second;
}

kernels::PatchMatchResult StageStore::ReadState(int view, const std::string& stage) const {
  const std::string path = StatePath(view, stage);
  const FloatMap state = ReadFloatMap(path, kStateChannels);
  const DenseView& v = workspace_.views[view];
  if (state.width != v.width || state.height != v.height) {
    ThrowFileError(path, "size differs from the image; delete the folder stereo/mpmvs (intermediate results "
                         "only) or rerun with --MPMVS.overwrite 1");
  }
  return StateToResult(state);
}

void StageStore::WriteState(int view, const std::string& stage, const kernels::PatchMatchResult& result) {
  const FloatMap state = ResultToState(result);
  StateRecord record = ExpectedRecord(view, stage);
  record.checksum = StateChecksum(state);
  // A record left from an earlier state would not match the new values anyway (checksum);
  // removing it first keeps an interrupted write from looking like a known state.
  std::error_code ec;
  std::filesystem::remove(StateRecordPath(view, stage), ec);
  WriteFloatMap(StatePath(view, stage), state);
  WriteStateRecord(StateRecordPath(view, stage), record);
  state_usable_[{view, stage}] = {true, "", StateStamp(view, stage)};
}

bool StageStore::StateFilesExist(int view, const std::string& stage) const {
  return FileExists(StatePath(view, stage)) || FileExists(StateRecordPath(view, stage));
}

bool StageStore::RemoveState(int view, const std::string& stage) {
  std::error_code ec;
  std::filesystem::remove(StateRecordPath(view, stage), ec);
  const bool removed = std::filesystem::remove(StatePath(view, stage), ec);
  state_usable_.erase({view, stage});
  return removed;
}

namespace {

// The final map files of a view and type: (role, path, channels; 0 for the consistency graph).
struct FinalFile {
  std::string role;
  std::string path;
  int channels;
};

std::vector<FinalFile> FinalFiles(const DenseWorkspace& workspace, int view, const std::string& type,
                                  bool consistency_graph) {
  std::vector<FinalFile> files = {{"depth", workspace.DepthMapPath(view, type), 1},
                                  {"normal", workspace.NormalMapPath(view, type), 3}};
  if (consistency_graph) files.push_back({"consistency_graph", workspace.ConsistencyGraphPath(view, type), 0});
  return files;
}

// "" when the map's values are those of a depth (channels 1: finite, 0 or inside
// [depth_min, depth_max] with 1 % slack) or normal map (finite, length 1 or 0).
std::string MapValuesProblem(const FloatMap& map, float depth_min, float depth_max) {
  const size_t n = static_cast<size_t>(map.width) * map.height;
  for (size_t i = 0; i < n; ++i) {
    if (map.channels == 1) {
      const float d = map.data[i];
      if (!std::isfinite(d) || d < 0.f || (d > 0.f && (d < 0.99f * depth_min || d > 1.01f * depth_max))) {
        return "a depth of " + std::to_string(d) + " (pixel " + std::to_string(i) + ") is not 0 or inside the " +
               "depth range [" + std::to_string(depth_min) + ", " + std::to_string(depth_max) + "]";
      }
    } else {
      const float x = map.data[i], y = map.data[n + i], z = map.data[2 * n + i];
      const float length2 = x * x + y * y + z * z;
      if (!std::isfinite(length2) || (length2 != 0.f && std::abs(length2 - 1.f) > 0.01f)) {
        return "the normal of pixel " + std::to_string(i) + " is not of length 1 or 0";
      }
    }
  }
  return "";
}

}  // namespace

FinalMapsCheck StageStore::CheckFinalOutputs(int view, const std::string& type) const {
  FinalMapsCheck check;
  const DenseView& v = workspace_.views[view];
  const std::string size_text = std::to_string(v.width) + "x" + std::to_string(v.height);
  MapsRecord record;
  std::string no_record;
  const bool has_record = ReadMapsRecord(MapsRecordPath(view, type), &record, &no_record);
  bool all_there = true;
  for (const FinalFile& file : FinalFiles(workspace_, view, type, plan_.write_consistency_graph)) {
    if (!FileExists(file.path)) {
      all_there = false;
      continue;
    }
    if (has_record && (record.maps_options != HashText(fingerprint_.maps_options) ||
                       record.inputs != InputsHash(view, MapsFromDepthCheck(type)))) {
      const std::string changed = ChangedOptions(record.options, fingerprint_.options);
      check.other_options =
          changed.empty() ? "other images, cameras, depth range, sources or depth check tolerance" : changed;
      return check;
    }
    std::string why;
    FloatMap map;
    if (file.channels == 0) {
      try {
        const ConsistencyGraph graph = ReadConsistencyGraph(file.path);
        if (graph.width != v.width || graph.height != v.height) {
          why = "it is " + std::to_string(graph.width) + "x" + std::to_string(graph.height) + ", the image " + size_text;
        }
      } catch (const Error& e) {
        why = e.what();
      }
    } else {
      why = CheckFloatMapFile(file.path, v.width, v.height, file.channels);
      if (!why.empty() && !has_record) {
        // A whole map of another size: made with another max_image_size, no damage.
        try {
          map = ReadFloatMap(file.path, file.channels);
          check.other_options = "made at " + std::to_string(map.width) + "x" + std::to_string(map.height) +
                                ", the image is now " + size_text + " (PatchMatchStereo.max_image_size)";
          return check;
        } catch (const Error&) {
        }
      }
    }
    if (why.empty()) {
      const MapsRecord::File* written = has_record ? record.Find(file.role) : nullptr;
      if (written) {
        if (!FileMatches(file.path, *written)) {
          why = "its bytes are not those mp-mvs wrote (changed or copied over since; its record " +
                MapsRecordPath(view, type) + ")";
        }
      } else if (file.channels > 0) {
        try {
          const ReferenceProblem& p = problems_.at(view);
          why = MapValuesProblem(ReadFloatMap(file.path, file.channels), p.depth_min, p.depth_max);
        } catch (const Error& e) {
          why = e.what();
        }
      }
    }
    if (!why.empty()) check.damaged.emplace_back(file.path, why);
  }
  check.complete = all_there && check.damaged.empty();
  return check;
}

bool StageStore::AllFinalOutputsExist(int view) const {
  return FinalOutputsExist(view, plan_.final_type) && FinalOutputsExist(view, "photometric");
}

int StageStore::MoveAsideDamagedFinalOutputs(int view) const {
  int moved = 0;
  std::vector<std::string> types = {"photometric"};
  if (plan_.final_type != "photometric") types.push_back(plan_.final_type);
  for (const std::string& type : types) {
    for (const auto& damaged : CheckFinalOutputs(view, type).damaged) {
      std::string aside;
      for (int n = 1; aside.empty() || FileExists(aside); ++n) aside = damaged.first + ".damaged-" + std::to_string(n);
      std::error_code ec;
      std::filesystem::rename(damaged.first, aside, ec);
      if (ec) {
        ThrowFileError(damaged.first, "is damaged (" + damaged.second + ") and cannot be moved aside (" +
                                          ec.message() + "); remove it or rerun with --MPMVS.overwrite 1");
      }
      LogWarning(damaged.first + ": " + damaged.second + "; moved aside to " + aside + " and recomputed");
      ++moved;
    }
  }
  return moved;
}

std::string StageStore::MapsRecordPath(int view, const std::string& type) const {
  return JoinPaths(workspace_.IntermediateDir(), workspace_.views[view].name + "." + type + ".maps.json");
}

void StageStore::RemoveMapsRecord(int view, const std::string& type) const {
  std::error_code ec;
  std::filesystem::remove(MapsRecordPath(view, type), ec);
}

void StageStore::WriteMapsRecord(int view, const std::string& type) const {
  MapsRecord record;
  record.type = type;
  record.options = fingerprint_.options;
  record.maps_options = HashText(fingerprint_.maps_options);
  record.inputs = InputsHash(view, MapsFromDepthCheck(type));
  for (const FinalFile& file : FinalFiles(workspace_, view, type, plan_.write_consistency_graph)) {
    record.files.push_back(DescribeFile(file.path, file.role));
  }
  mpmvs::WriteMapsRecord(MapsRecordPath(view, type), record);
}

std::vector<float> StageStore::ReadChromaGuide(int view) const {
  const RgbImage rgb = io_->ReadRgb(workspace_, view);
  const DenseView& v = workspace_.views[view];
  if (rgb.width != v.width || rgb.height != v.height) {
    throw Error(v.image_path + ": colour image is " + std::to_string(rgb.width) + "x" +
                std::to_string(rgb.height) + " but the view is " + std::to_string(v.width) + "x" +
                std::to_string(v.height));
  }
  std::vector<float> guide = MakeChromaGuide(rgb, plan_.chroma_guide_weight);
  if (std::none_of(guide.begin(), guide.end(), [](float c) { return c != 0.f; })) guide.clear();
  return guide;
}

}  // namespace mpmvs
