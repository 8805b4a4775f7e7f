#include <cstdlib>

#include "colmap_ext/commands.h"

namespace mpmvs {

std::string ColmapExecutableName() {
  const char* env = std::getenv("MPMVS_COLMAP_EXE");
  return env && *env ? env : "colmap";
}

}  // namespace mpmvs
