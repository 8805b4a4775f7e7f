#pragma once
// What the stages hand each other and share, like COLMAP's CachedWorkspace: every stage's
// result per image in stereo/mpmvs/NAME.STAGE.state.bin (the only way a stage reads another
// stage's work) with its record NAME.STAGE.state.json (state_record.h), and the grey images, colour guides and source depth maps that several
// reference images use, in LRU caches bounded by --PatchMatchStereo.cache_size (5/16 each),
// with the images' plain-window masks of the planar prior (the last 1/16: a byte per pixel
// and window scale).
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/plan/run_plan.h"
#include "colmap_ext/store/maps_record.h"
#include "colmap_ext/store/result_fingerprint.h"
#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/lru_cache.h"
#include "kernels/patch_match.h"

namespace mpmvs {

// Depth of each pixel's plane (0 where invalid or outside [depth_min, depth_max]).
std::vector<float> ResultDepth(const kernels::PatchMatchResult& result, const kernels::Camera& camera,
                               float depth_min, float depth_max);

// What a rerun finds of a reference image's final maps of one type.
struct FinalMapsCheck {
  bool complete = false;  // every file there, whole, made with this run's options and inputs
  // Not empty: the maps were made with other options or inputs (what differs); they are
  // recomputed and replaced, as a change of options is no damage.
  std::string other_options;
  // Files that exist but are damaged: (file, why).
  std::vector<std::pair<std::string, std::string>> damaged;
};

class StageStore {
 public:
  // workspace, io and plan must outlive the store. problems: every view that runs (a source
  // outside them has no stage results). fingerprint: the run's (result_fingerprint.h).
  StageStore(const DenseWorkspace& workspace, WorkspaceIo* io, const RunPlan& plan,
             const std::vector<ReferenceProblem>& problems, const ResultFingerprint& fingerprint);

  // Whether the view runs (has stage results at all); a source that does not was reported
  // when the run was planned.
  bool Runs(int view) const { return problems_.count(view) > 0; }
  std::string StatePath(int view, const std::string& stage) const;
  std::string StateRecordPath(int view, const std::string& stage) const;
  // Whether the stage's result of the view can be used: the view runs, and its state file
  // is whole and was made with this run's options and inputs (its record says so). A state
  // that exists but fails is reported once, with the reason, and counts as absent (the
  // stage recomputes it).
  bool HasState(int view, const std::string& stage);
  // Throws Error naming the file when it is damaged or of another size than the view.
  kernels::PatchMatchResult ReadState(int view, const std::string& stage) const;
  // Whether the state file or its record is on the disk, usable or not (no read).
  bool StateFilesExist(int view, const std::string& stage) const;
  // Removes the state file and its record, record first (a state without its record is not
  // resumed); whether a state was there.
  bool RemoveState(int view, const std::string& stage);
  // Writes the state file, then its record.
  void WriteState(int view, const std::string& stage, const kernels::PatchMatchResult& result);
  std::string MapsRecordPath(int view, const std::string& type) const;
  // The final COLMAP maps of this type (and the consistency graph if asked): whether they
  // are there, whole and of this run's options and inputs. With their record (maps_record.h)
  // a file whose bytes are not those written is damaged; without one (maps of COLMAP or an
  // older mp-mvs) the values are checked: finite, depths 0 or inside the depth range, normals
  // of length 1 or 0; a whole map of another size was made with another max_image_size.
  FinalMapsCheck CheckFinalOutputs(int view, const std::string& type) const;
  bool FinalOutputsExist(int view, const std::string& type) const { return CheckFinalOutputs(view, type).complete; }
  // Whether every final map the run writes for the view (photometric and, with geometric
  // consistency, geometric) is there and whole.
  bool AllFinalOutputsExist(int view) const;
  // Moves every final map of the view that exists but is not a whole map of the view's size
  // aside to FILE.damaged-N, with a warning, so that it is recomputed. Returns how many.
  int MoveAsideDamagedFinalOutputs(int view) const;
  // Around writing the final maps of a type: the old record goes first (a run killed in
  // between leaves maps without a record, judged by their values), the new one last.
  void RemoveMapsRecord(int view, const std::string& type) const;
  void WriteMapsRecord(int view, const std::string& type) const;
  // Once a run has said that it recomputes what other options or inputs made, states of
  // other options are recomputed without a line each.
  void SetOptionsChangeReported() { options_change_reported_ = true; }

  std::shared_ptr<const GrayImage> Image(int view) { return images_.Get(view); }
  // Empty for a grey picture: nothing to read or upload.
  std::shared_ptr<const std::vector<float>> ChromaGuide(int view) { return chroma_guides_.Get(view); }
  // The depth map of stage_index's result of a view, for the geometric term of its neighbours.
  std::shared_ptr<const std::vector<float>> SourceDepth(int stage_index, int view) {
    return depths_.Get({stage_index, view});
  }
  // The noise variance of a view's grey image (EstimateNoiseVariance), estimated once.
  float NoiseVariance(int view);
  // 1 where the view's grey window of this mPM scale is plain at the image's noise
  // (kernels::PlainWindowMaskCpu): every reference whose prior takes vertices from this
  // view asks for it, in every prior round, and each costs a textured reference window per
  // pixel.
  std::shared_ptr<const std::vector<uint8_t>> PlainWindows(int view, int window_scale) {
    return plain_windows_.Get({view, window_scale});
  }

 private:
  std::vector<float> ReadChromaGuide(int view) const;
  // The record a state of this view and stage made now would carry (checksum 0).
  StateRecord ExpectedRecord(int view, const std::string& stage);
  // "" when the existing state file is usable, else why not; *changed: why not is that it
  // was made with other options or inputs (not damage).
  std::string CheckState(int view, const std::string& stage, bool* changed);
  // Identity of a view's picture and camera: name, size, K, R, T and the image file's hash.
  std::string ViewIdentity(int view) const;
  // Hash of what a view's results are made from: its and its sources' identities, its
  // depth range and sources, and for the depth check's results (depth_check) its tolerance.
  uint64_t InputsHash(int view, bool depth_check) const;
  // Whether the results of this stage, or the final maps of this type, are the depth check's.
  bool IsDepthCheckStage(const std::string& stage) const;
  bool MapsFromDepthCheck(const std::string& type) const;

  const DenseWorkspace& workspace_;
  WorkspaceIo* io_;
  const RunPlan& plan_;
  std::map<int, ReferenceProblem> problems_;
  ResultFingerprint fingerprint_;
  mutable std::map<int, std::string> view_identities_;
  bool options_change_reported_ = false;
  struct StateVerdict {
    bool usable = false;
    std::string why;    // why not
    std::string stamp;  // StateStamp when judged
  };
  // Modification times and sizes of the state file and its record.
  std::string StateStamp(int view, const std::string& stage) const;
  std::map<std::pair<int, std::string>, StateVerdict> state_usable_;  // HasState's verdicts
  LruCache<int, GrayImage> images_;
  LruCache<int, std::vector<float>> chroma_guides_;
  LruCache<std::pair<int, int>, std::vector<float>> depths_;
  std::map<int, float> noise_variances_;
  LruCache<std::pair<int, int>, std::vector<uint8_t>> plain_windows_;  // (view, window scale)
};

}  // namespace mpmvs
