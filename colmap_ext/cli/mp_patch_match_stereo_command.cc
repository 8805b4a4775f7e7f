// `colmap-mp mp_patch_match_stereo` (and, through RunMpPatchMatchStereoCommandWithIo, the
// native `colmap mp_patch_match_stereo`): COLMAP's patch_match_stereo options plus --MPMVS.*.
#include <cstdio>
#include <iostream>

#include "colmap_ext/cli/commands.h"
#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/pipeline/mp_patch_match_stereo.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {

int RunMpPatchMatchStereoCommand(const std::vector<std::string>& args) {
  MpMvsWorkspaceIo io;
  return RunMpPatchMatchStereoCommandWithIo(args, &io, "colmap-mp");
}

int RunMpPatchMatchStereoCommandWithIo(const std::vector<std::string>& args, WorkspaceIo* io,
                                       const std::string& program) {
  MpPatchMatchRun run;
  OptionParser parser;
  std::string pmvs_option_name = "option-all";
  AddMpPatchMatchRunOptions(&parser, &run, &pmvs_option_name);
  if (!parser.Parse(args)) {
    std::cout << "Usage: " << program << " mp_patch_match_stereo --workspace_path DIR [options]\n\n"
              << "Computes depth and normal maps with MP-MVS and writes them where COLMAP's\n"
              << "patch_match_stereo does (stereo/depth_maps, stereo/normal_maps), for\n"
              << "`colmap stereo_fusion`.\n\nOptions:\n"
              << parser.Help();
    return 0;
  }
  for (const std::string& w : parser.Warnings()) LogWarning(w);
  const MpPatchMatchSummary s = RunMpPatchMatchStereo(run, io);
  LogHeading("mp_patch_match_stereo finished in " + FormatDuration(s.seconds));
  char line[512];
  if (s.seconds > 0) {
    std::snprintf(line, sizeof(line),
                  "%.1f s wall, %.1f s CPU (%.2f cores busy); %.2f s (%.1f %%) outside the parallel work "
                  "(loading, planning, writing between images)",
                  s.seconds, s.cpu_seconds, s.cpu_seconds / s.seconds, s.serial_seconds,
                  100 * s.serial_seconds / s.seconds);
    LogInfo(line);
  }
  for (const StageSummary& st : s.stages) {
    // A cost sample: one of a window's 36 points matched in one source view.
    const double samples = static_cast<double>(st.ncc_evaluations) * kernels::kWindowSamples;
    std::snprintf(line, sizeof(line),
                  "stage %-12s %3d computed, %3d resumed, %8.1f s, %.2f Mpix*iterations/s, %.0f cost samples "
                  "per pixel and iteration",
                  st.name.c_str(), st.images_computed, st.images_resumed, st.seconds,
                  st.seconds > 0 ? st.pixel_iterations / st.seconds / 1e6 : 0.0,
                  st.pixel_iterations > 0 ? samples / st.pixel_iterations : 0.0);
    LogInfo(line);
  }
  std::snprintf(line, sizeof(line),
                "%d reference images: %d written, %d already done, %d skipped without source images, "
                "%d skipped without depth range, %d skipped with missing files; %d images of the model are no "
                "reference (not in patch-match.cfg); backend %s",
                s.num_references, s.num_written, s.num_already_done, s.num_skipped_no_sources,
                s.num_skipped_no_depth_range, s.num_skipped_missing_files, s.num_not_references,
                s.backend.empty() ? "-" : s.backend.c_str());
  LogInfo(line);
  if (s.intermediate_peak_bytes > 0) {
    std::snprintf(line, sizeof(line), "stereo/mpmvs: peak %.1f MB, now %.1f MB (%s)", s.intermediate_peak_bytes / 1e6,
                  s.intermediate_final_bytes / 1e6,
                  run.options.keep_states ? "--MPMVS.keep_states 1 keeps every stage's state"
                                          : "a stage's state goes once no stage reads it; --MPMVS.keep_states 1 keeps all");
    LogInfo(line);
  }
  return 0;
}

}  // namespace mpmvs
