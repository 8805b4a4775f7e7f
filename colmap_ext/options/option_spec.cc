#include "colmap_ext/options/option_spec.h"

#include <sstream>
#include <vector>

#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

std::vector<std::string> Words(const char* text) {
  std::vector<std::string> words;
  std::stringstream ss(text);
  std::string word;
  while (std::getline(ss, word, '|')) words.push_back(word);
  return words;
}

}  // namespace

bool OptionRange::Allows(double v) const {
  if (or_minus_one && v == -1) return true;
  switch (kind) {
    case Kind::kAny: return true;
    case Kind::kClosed: return v >= lo && v <= hi;
    case Kind::kOpen: return v > lo && v < hi;
    case Kind::kClosedOpen: return v >= lo && v < hi;
    case Kind::kOpenClosed: return v > lo && v <= hi;
    case Kind::kAtLeast: return v >= lo;
    case Kind::kAbove: return v > lo;
    case Kind::kMinusOneOrAbove: return v == -1 || v > lo;
    case Kind::kText: return false;
  }
  return false;
}

bool OptionRange::Allows(const std::string& value) const {
  if (kind == Kind::kAny) return true;
  if (kind != Kind::kText) return false;
  if (!choices) return !value.empty();
  for (const std::string& word : Words(text)) {
    if (value == word) return true;
  }
  return false;
}

std::string OptionRange::Text() const {
  if (or_minus_one) {
    OptionRange base = *this;
    base.or_minus_one = false;
    return "-1 or " + base.Text();
  }
  switch (kind) {
    case Kind::kAny: return "";
    case Kind::kClosed: return "in [" + FormatNumber(lo) + ", " + FormatNumber(hi) + "]";
    case Kind::kOpen: return "in (" + FormatNumber(lo) + ", " + FormatNumber(hi) + ")";
    case Kind::kClosedOpen: return "in [" + FormatNumber(lo) + ", " + FormatNumber(hi) + ")";
    case Kind::kOpenClosed: return "in (" + FormatNumber(lo) + ", " + FormatNumber(hi) + "]";
    case Kind::kAtLeast: return ">= " + FormatNumber(lo);
    case Kind::kAbove: return "> " + FormatNumber(lo);
    case Kind::kMinusOneOrAbove: return "-1 or > " + FormatNumber(lo);
    case Kind::kText: {
      if (!choices) return text;
      const std::vector<std::string> words = Words(text);
      std::string out;
      for (size_t i = 0; i < words.size(); ++i) {
        out += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
      }
      return out;
    }
  }
  return "";
}

}  // namespace mpmvs
