#include "colmap_ext/cli/patch_match_flags.h"

#include <memory>
#include <string>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

// "help (range)": the range from the declaration, shown in -h.
std::string HelpText(const OptionSpec& spec) {
  const std::string range = spec.range.Text();
  return range.empty() ? spec.help : std::string(spec.help) + " [" + range + "]";
}

}  // namespace

void AddPatchMatchOptions(OptionParser* parser, PatchMatchStereoOptions* c, MpMvsOptions* m) {
  const std::string p = "PatchMatchStereo.";
  c->Visit([&](const OptionSpec& spec, auto& field) { parser->Add(p + spec.name, &field, HelpText(spec)); });
#define MPMVS_ADD_IGNORED(NAME, HINT) parser->AddIgnored(p + #NAME, HINT);
  MPMVS_COLMAP_IGNORED_OPTIONS(MPMVS_ADD_IGNORED)
#undef MPMVS_ADD_IGNORED

  const std::string q = "MPMVS.";
  // The preset's values are set after parsing, for the options not given explicitly.
  auto preset = std::make_shared<std::string>("default");
  parser->Add(q + "preset", preset.get(),
              std::string("defaults of all --MPMVS options: default, fast (6 of the 21 iterations) or "
                          "paper (MP-MVS as published; docs/options.md); options given explicitly override it [" +
                  PresetNames() + "]"));
  m->Visit([&](const OptionSpec& spec, auto& field, const auto&) {
    parser->Add(q + spec.name, &field, HelpText(spec));
  });
  parser->OnParsed([preset, m, q](const OptionParser& parsed) {
    if (!ApplyPreset(*preset, [&](const std::string& name) { return parsed.Given(q + name); }, m)) {
      throw Error("--MPMVS.preset = " + *preset + " is invalid: must be one of " + PresetNames());
    }
  });
}

void AddGeneralOptions(OptionParser* parser, MpMvsOptions* m) {
  auto general = std::make_shared<GeneralOptions>();
  general->Visit([&](const OptionSpec& spec, auto& field) {
    if (std::string(spec.name) == "project_path") {
      parser->AddProjectFile(spec.name, &general->project_path, HelpText(spec));
    } else {
      parser->Add(spec.name, &field, HelpText(spec));
    }
  });
  // After the preset's callback (AddPatchMatchOptions), which sets the seed it was not given.
  parser->OnParsed([general, m](const OptionParser& parsed) {
    std::string error;
    if (!general->Check(&error)) throw Error(error);
    SetLogToStderr(general->log_to_stderr);
    SetLogLevel(general->log_level);
    if (!parsed.Given("random_seed") || parsed.Given("MPMVS.seed")) return;
    const int seed = SeedForRandomSeed(general->random_seed);
    if (seed < 0) {
      LogWarning("--random_seed -1 (a seed from the clock) is not used: resumed runs and shards must draw the same "
                 "random streams; running with --MPMVS.seed " + std::to_string(m->seed));
    } else {
      m->seed = seed;
    }
  });
}

void AddMpPatchMatchRunOptions(OptionParser* parser, MpPatchMatchRun* run, std::string* pmvs_option_name) {
  parser->AddRequired("workspace_path", &run->workspace_path, "COLMAP dense workspace (image_undistorter output)");
  parser->Add("workspace_format", &run->workspace_format, "COLMAP (PMVS is not supported)");
  parser->Add("pmvs_option_name", pmvs_option_name, "accepted for COLMAP compatibility (PMVS only)");
  parser->Add("config_path", &run->config_path, "patch-match.cfg to use instead of stereo/patch-match.cfg");
  AddPatchMatchOptions(parser, &run->colmap_options, &run->options);
  AddGeneralOptions(parser, &run->options);
}

}  // namespace mpmvs
