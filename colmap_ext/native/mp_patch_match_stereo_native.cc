#include "colmap_ext/native/mp_patch_match_stereo_native.h"

#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "colmap_ext/cli/commands.h"
#include "colmap_ext/native/colmap_workspace_io.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {

int RunColmapMpPatchMatchStereo(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
    const std::unique_ptr<WorkspaceIo> io = MakeColmapWorkspaceIo();
    return RunMpPatchMatchStereoCommandWithIo(args, io.get(), "colmap") == 0 ? EXIT_SUCCESS
                                                                             : EXIT_FAILURE;
  } catch (const Error& e) {
    LogError(e.what());
  } catch (const std::exception& e) {
    LogError(std::string("unexpected failure: ") + e.what());
  }
  return EXIT_FAILURE;
}

}  // namespace mpmvs
