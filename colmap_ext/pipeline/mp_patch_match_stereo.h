#pragma once
// The mp_patch_match_stereo controller: loads a COLMAP dense workspace, runs the stage plan
// (stage_plan.h) for every reference image of patch-match.cfg on the chosen backend, and
// writes COLMAP depth/normal maps that `colmap stereo_fusion` reads unchanged. Reading the
// workspace and writing the maps go through a WorkspaceIo (workspace_io.h), so the same
// stage loop serves `colmap-mp` (mp-mvs's own I/O) and the native `colmap` command
// (COLMAP's mvs::Workspace and writers, colmap_ext/native).
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/options/patch_match_options.h"
#include "colmap_ext/plan/kernel_camera.h"
#include "kernels/patch_match.h"

namespace mpmvs {

class WorkspaceIo;

struct StageSummary {
  std::string name;
  int images_computed = 0;
  int images_resumed = 0;  // results already on disk
  double seconds = 0;
  uint64_t ncc_evaluations = 0;
  uint64_t pixel_iterations = 0;  // pixels x iterations computed
  // Iterations of the first image computed in this stage (window sizes, pattern, tau).
  std::vector<kernels::IterationStats> iterations;
};

struct MpPatchMatchSummary {
  int num_references = 0;
  int num_written = 0;           // references whose final maps were written in this run (once each)
  int num_already_done = 0;      // final maps existed (rerun)
  int num_skipped_no_sources = 0;
  int num_skipped_no_depth_range = 0;
  int num_skipped_missing_files = 0;  // --PatchMatchStereo.allow_missing_files
  int num_not_references = 0;         // images of the model that patch-match.cfg does not list
  std::string backend;
  double seconds = 0;
  // stereo/mpmvs: the most it held (after a stage, before the states that stage made unneeded
  // were removed) and what it holds at the end.
  uint64_t intermediate_peak_bytes = 0;
  uint64_t intermediate_final_bytes = 0;
  // Wall time outside the parallel work (the backend's runs and the depth check): loading,
  // planning and what was left to do between images. cpu_seconds: the process's CPU time.
  double serial_seconds = 0;
  double cpu_seconds = 0;
  std::vector<StageSummary> stages;
};

struct MpPatchMatchRun {
  std::string workspace_path;
  std::string workspace_format = "COLMAP";
  std::string config_path;  // "" = workspace/stereo/patch-match.cfg
  PatchMatchStereoOptions colmap_options;
  MpMvsOptions options;
  // While the CPU backend runs a reference image, another thread writes the previous
  // image's outputs and assembles the next image (as the CUDA session does on its host
  // thread), so that no core waits for that serial work. Tests turn it off to compare with
  // the serial order: results and files are the same either way.
  bool cpu_side_work = true;
};

// Throws Error with a clear message on bad input; never leaves partial map files.
// Uses mp-mvs's own I/O (MpMvsWorkspaceIo).
MpPatchMatchSummary RunMpPatchMatchStereo(const MpPatchMatchRun& run);
// Same, reading the workspace and writing the maps through io (not owned, not null).
MpPatchMatchSummary RunMpPatchMatchStereo(const MpPatchMatchRun& run, WorkspaceIo* io);

}  // namespace mpmvs
