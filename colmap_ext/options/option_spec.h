#pragma once
// What an option declaration says besides its name, type and default (patch_match_options.h):
// the values it accepts, whether it changes results, and its help.
#include <string>

namespace mpmvs {

// The values an option accepts. Bounds are checked NaN-safe: NaN is outside every bound.
struct OptionRange {
  enum class Kind {
    kAny,             // every value of the type
    kClosed,          // lo <= v <= hi
    kOpen,            // lo < v < hi
    kClosedOpen,      // lo <= v < hi
    kOpenClosed,      // lo < v <= hi
    kAtLeast,         // v >= lo
    kAbove,           // v > lo
    kMinusOneOrAbove, // v == -1 or v > lo
    kText,            // a text option: one of `text` ("a|b|c"), or any non-empty text when
                      // `choices` is false (then `text` says what it should be)
  };
  Kind kind = Kind::kAny;
  double lo = 0, hi = 0;
  const char* text = "";
  bool choices = false;
  bool or_minus_one = false;  // -1 ("automatic") is allowed too

  static constexpr OptionRange Any() { return {}; }
  static constexpr OptionRange Closed(double lo, double hi) { return {Kind::kClosed, lo, hi}; }
  static constexpr OptionRange Open(double lo, double hi) { return {Kind::kOpen, lo, hi}; }
  static constexpr OptionRange ClosedOpen(double lo, double hi) { return {Kind::kClosedOpen, lo, hi}; }
  static constexpr OptionRange OpenClosed(double lo, double hi) { return {Kind::kOpenClosed, lo, hi}; }
  static constexpr OptionRange AtLeast(double lo) { return {Kind::kAtLeast, lo, 0}; }
  static constexpr OptionRange Above(double lo) { return {Kind::kAbove, lo, 0}; }
  static constexpr OptionRange MinusOneOrAbove(double lo) { return {Kind::kMinusOneOrAbove, lo, 0}; }
  // This range, or -1.
  constexpr OptionRange OrMinusOne() const {
    OptionRange r = *this;
    r.or_minus_one = true;
    return r;
  }
  // "a|b|c": exactly one of these words.
  static constexpr OptionRange OneOf(const char* words) { return {Kind::kText, 0, 0, words, true}; }
  // Any non-empty text; `what` describes it in messages.
  static constexpr OptionRange NonEmpty(const char* what) { return {Kind::kText, 0, 0, what, false}; }

  bool Allows(double value) const;  // also booleans (0, 1), which take kAny
  bool Allows(const std::string& value) const;
  // "in [0, 4]", ">= 1", "none, photometric or geometric", ... ("" for kAny).
  std::string Text() const;
};

// What a value of the option affects.
enum class OptionEffect {
  kResult,         // the maps: enters the state fingerprint and the concurrent-run check
  kResultWhenSet,  // as kResult, but enters the fingerprint only away from its paper value
                   // (the method as it ran before the option existed), so states written
                   // before the option existed stay valid, whatever the default is now
  kInput,          // as kResult, through what it selects: the images' size, the depth range
                   // or the sources, which each state's and map's inputs hash holds already;
                   // it enters the run's fingerprint (store/result_fingerprint.h) only
  kRun,            // how the run goes (which images, resuming, pictures), not the maps
};

struct OptionSpec {
  const char* name;  // without its section ("MPMVS.", "PatchMatchStereo.")
  OptionRange range;
  OptionEffect effect;
  const char* help;
};

}  // namespace mpmvs
