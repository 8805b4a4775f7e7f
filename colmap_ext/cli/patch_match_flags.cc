#include "colmap_ext/cli/patch_match_flags.h"

#include <memory>
#include <string>

#include "colmap_ext/util/error.h"

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
              std::string("defaults of all --MPMVS options: default, fast (about half the iterations) or "
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

void AddMpPatchMatchRunOptions(OptionParser* parser, MpPatchMatchRun* run, std::string* pmvs_option_name) {
  parser->AddRequired("workspace_path", &run->workspace_path, "COLMAP dense workspace (image_undistorter output)");
  parser->Add("workspace_format", &run->workspace_format, "COLMAP (PMVS is not supported)");
  parser->Add("pmvs_option_name", pmvs_option_name, "accepted for COLMAP compatibility (PMVS only)");
  parser->Add("config_path", &run->config_path, "patch-match.cfg to use instead of stereo/patch-match.cfg");
  AddPatchMatchOptions(parser, &run->colmap_options, &run->options);
}

}  // namespace mpmvs
