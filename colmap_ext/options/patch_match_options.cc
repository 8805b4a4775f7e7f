#include "colmap_ext/options/patch_match_options.h"

#include <limits>
#include <sstream>
#include <type_traits>

namespace mpmvs {
namespace {

template <typename T>
bool Fail(std::string* error, const std::string& name, const T& value, const std::string& rule) {
  std::ostringstream ss;
  ss << "--" << name << " = " << value << " is invalid: must be " << rule;
  if (error) *error = ss.str();
  return false;
}

template <typename T>
bool Allowed(const OptionRange& range, const T& value) {
  if constexpr (std::is_same_v<T, std::string>) {
    return range.Allows(value);
  } else {
    return range.Allows(static_cast<double>(value));
  }
}

// The first value outside its declared range, as an error naming it.
template <typename Options>
bool CheckRanges(const Options& options, const std::string& section, std::string* error) {
  bool ok = true;
  options.Visit([&](const OptionSpec& spec, const auto& value, const auto&...) {
    if (ok && !Allowed(spec.range, value)) ok = Fail(error, section + spec.name, value, spec.range.Text());
  });
  return ok;
}

template <typename T>
std::string ValueText(const T& value) {
  std::ostringstream ss;
  ss << value;  // booleans as 1 or 0
  const std::string text = ss.str();
  return text.empty() ? "\"\"" : text;
}

std::string MarkdownCell(std::string text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

}  // namespace

bool PatchMatchStereoOptions::Check(std::string* error) const {
  const std::string p = "PatchMatchStereo.";
  if ((depth_min != -1 || depth_max != -1) && !(depth_min > 0 && depth_max > depth_min))
    return Fail(error, p + "depth_min/depth_max", std::to_string(depth_min) + "/" + std::to_string(depth_max),
                "both set with 0 < depth_min < depth_max (or both -1)");
  if (!CheckRanges(*this, p, error)) return false;
  std::stringstream ss(gpu_index);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t pos = 0;
      const int v = std::stoi(item, &pos);
      if (pos != item.size() || v < -1) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      return Fail(error, p + "gpu_index", gpu_index, "a comma-separated list of integers >= -1");
    }
  }
  return true;
}

bool GeneralOptions::Check(std::string* error) const { return CheckRanges(*this, "", error); }

int SeedForRandomSeed(int random_seed) {
  if (random_seed < 0) return -1;
  return random_seed == std::numeric_limits<int>::max() ? random_seed : random_seed + 1;
}

PlanarPriorMode MpMvsOptions::PriorMode() const {
  if (planar_prior == "photometric") return PlanarPriorMode::kPhotometric;
  if (planar_prior == "geometric") return PlanarPriorMode::kGeometric;
  return PlanarPriorMode::kNone;
}

bool MpMvsOptions::Check(std::string* error) const { return CheckRanges(*this, "MPMVS.", error); }

std::string PresetNames() {
  std::string names;
  for (const char* name : kPresetNames) names += (names.empty() ? "" : "|") + std::string(name);
  return names;
}

bool ApplyPreset(const std::string& preset, const std::function<bool(const std::string&)>& given,
                 MpMvsOptions* options) {
  int k = 0;
  while (k < kNumPresets && preset != kPresetNames[k]) ++k;
  if (k == kNumPresets) return false;
  options->Visit([&](const OptionSpec& spec, auto& value, const auto& presets) {
    if (spec.effect != OptionEffect::kRun && !given(spec.name)) value = presets.at(k);
  });
  return true;
}

std::string ResultOptionsText(const MpMvsOptions& options) {
  std::ostringstream s;
  s.precision(17);
  options.Visit([&](const OptionSpec& spec, const auto& value, const auto& presets) {
    if (spec.effect == OptionEffect::kRun) return;
    if (spec.effect == OptionEffect::kResultWhenSet && value == presets.paper_value()) return;
    s << spec.name << " " << value << "\n";
  });
  return s.str();
}

std::string ResultOptionsText(const PatchMatchStereoOptions& options, bool include_inputs) {
  std::ostringstream s;
  s.precision(17);
  options.Visit([&](const OptionSpec& spec, const auto& value) {
    if (spec.effect == OptionEffect::kRun || (spec.effect == OptionEffect::kInput && !include_inputs)) return;
    s << "PatchMatchStereo." << spec.name << " " << value << "\n";
  });
  return s.str();
}

std::string OptionsMarkdown() {
  std::ostringstream md;
  md << "# Options of mp_patch_match_stereo\n\n"
        "Generated from the declarations in `colmap_ext/options/patch_match_options.h` (a test keeps this file\n"
        "equal to them; `MPMVS_UPDATE_DOCS=1 build/mpmvs_tests --gtest_filter='OptionDocs.*'` rewrites it).\n"
        "`colmap-mp mp_patch_match_stereo -h` prints the same. Booleans take 1|0, true|false, yes|no or on|off.\n\n"
        "## COLMAP's general options\n\n"
        "The options every COLMAP command takes.\n\n"
        "| option | default | range | meaning |\n|---|---|---|---|\n";
  GeneralOptions general;
  general.Visit([&](const OptionSpec& spec, const auto& value) {
    md << "| `--" << spec.name << "` | " << MarkdownCell(ValueText(value)) << " | " << MarkdownCell(spec.range.Text())
       << " | " << MarkdownCell(spec.help) << " |\n";
  });
  md << "\n## COLMAP's PatchMatchStereo options\n\n"
        "Accepted under COLMAP's names and with COLMAP's meaning. \"result\": the option changes the maps\n"
        "(docs/colmap_interface.md §5: two runs on one workspace at once must agree on it; a later run with\n"
        "another value recomputes what it changes).\n\n"
        "| option | default | range | effect | meaning |\n|---|---|---|---|---|\n";
  PatchMatchStereoOptions colmap;
  colmap.Visit([&](const OptionSpec& spec, const auto& value) {
    md << "| `--PatchMatchStereo." << spec.name << "` | " << MarkdownCell(ValueText(value)) << " | "
       << MarkdownCell(spec.range.Text()) << " | " << (spec.effect == OptionEffect::kRun ? "run" : "result") << " | "
       << MarkdownCell(spec.help) << " |\n";
  });
  md << "\nAccepted for COLMAP compatibility and ignored with a warning (they describe COLMAP's own "
        "algorithm):\n\n";
#define MPMVS_IGNORED_ROW(NAME, HINT) md << "- `--PatchMatchStereo." #NAME "`: " HINT "\n";
  MPMVS_COLMAP_IGNORED_OPTIONS(MPMVS_IGNORED_ROW)
#undef MPMVS_IGNORED_ROW
  md << "\n## The method's options\n\n"
        "`--MPMVS.preset default|fast|paper` sets the defaults of all of them at once (the columns below:\n"
        "`fast` runs 6 of the default's 21 iterations; `paper` is MP-MVS as published, every window at full\n"
        "resolution; empty: as the default); options given explicitly override the preset.\n"
        "\"result\": the option changes the maps, so it enters the fingerprint of every stage's state (a\n"
        "change recomputes) and two runs on one workspace must agree on it.\n\n"
        "| option | default | fast | paper | range | effect | meaning |\n|---|---|---|---|---|---|---|\n";
  MpMvsOptions method;
  method.Visit([&](const OptionSpec& spec, const auto& value, const auto& presets) {
    md << "| `--MPMVS." << spec.name << "` | " << MarkdownCell(ValueText(value));
    for (int k = 1; k < kNumPresets; ++k) {
      const std::string text = ValueText(presets.at(k));
      md << " | " << (text == ValueText(value) ? "" : MarkdownCell(text));
    }
    md << " | " << MarkdownCell(spec.range.Text()) << " | " << (spec.effect == OptionEffect::kRun ? "run" : "result")
       << " | " << MarkdownCell(spec.help) << " |\n";
  });
  return md.str();
}

}  // namespace mpmvs
