// The flags of mp_patch_match_stereo (cli/patch_match_flags.h): COLMAP's general options
// and what they set.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "colmap_ext/cli/option_parser.h"
#include "colmap_ext/cli/patch_match_flags.h"
#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// The --MPMVS.seed a parse of args leaves (after --workspace_path w).
int SeedAfter(std::vector<std::string> args) {
  MpPatchMatchRun run;
  std::string pmvs;
  OptionParser parser;
  AddMpPatchMatchRunOptions(&parser, &run, &pmvs);
  args.insert(args.begin(), {"--workspace_path", "w"});
  EXPECT_TRUE(parser.Parse(args));
  SetLogLevel(2);  // what the parse set, back to the default for the other tests
  SetLogToStderr(false);
  return run.options.seed;
}

// COLMAP's random_seed counts from its default 0, --MPMVS.seed from its default 1: COLMAP's
// default gives ours, other seeds other streams; an explicit --MPMVS.seed or a preset keeps
// its own; -1 (COLMAP: from the clock) cannot be honoured by resumed runs and shards.
TEST(PatchMatchFlags, RandomSeedMapsOntoTheSeedFromColmapsDefault) {
  EXPECT_EQ(SeedAfter({}), 1);
  EXPECT_EQ(SeedAfter({"--random_seed", "0"}), 1);
  EXPECT_EQ(SeedAfter({"--random_seed", "7"}), 8);
  EXPECT_EQ(SeedAfter({"--random_seed", "7", "--MPMVS.preset", "fast"}), 8);
  EXPECT_EQ(SeedAfter({"--random_seed", "7", "--MPMVS.seed", "3"}), 3);
  EXPECT_EQ(SeedAfter({"--MPMVS.seed", "3", "--random_seed", "7"}), 3);
  EXPECT_EQ(SeedAfter({"--random_seed", "-1"}), 1);
  EXPECT_EQ(SeedAfter({"--random_seed", "2147483646"}), 2147483647);
  EXPECT_EQ(SeedAfter({"--random_seed", "2147483647"}), 2147483647);
  EXPECT_THROW(SeedAfter({"--random_seed", "-2"}), Error);
  EXPECT_EQ(SeedAfter({"--log_level", "0", "--log_to_stderr", "yes"}), 1);
}

}  // namespace
}  // namespace mpmvs
