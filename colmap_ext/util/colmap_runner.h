#pragma once
// Runs the `colmap` executable for the steps mp-mvs leaves to COLMAP (stereo_fusion).
#include <string>
#include <vector>

namespace mpmvs {

// The `colmap` executable to hand other commands to: --colmap_path is handled by main;
// else $MPMVS_COLMAP_EXE, else "colmap" on PATH.
std::string ColmapExecutableName();

// Whether the colmap executable (ColmapExecutableName()) can be found on PATH or as a path.
bool ColmapAvailable();

// Runs colmap with args, its output appended to log_path; returns the exit code
// (127 when it cannot be started).
int RunColmap(const std::vector<std::string>& args, const std::string& log_path);

// colmap stereo_fusion on a COLMAP workspace with deterministic settings (one thread) and
// min_num_pixels = min(5, num_images - 1) as docs/evaluation.md §3 prescribes. Throws Error naming
// the log file when fusion fails.
void RunStereoFusion(const std::string& workspace_path, const std::string& input_type,
                     const std::string& output_path, int num_images, const std::string& log_path);

}  // namespace mpmvs
