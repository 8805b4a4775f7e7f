#include "colmap_ext/store/state_record.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "colmap_ext/util/file_util.h"

namespace mpmvs {
namespace {

constexpr uint64_t kMul = 0x9E3779B97F4A7C15ull;

uint64_t Mix(uint64_t h) {
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return h;
}

std::string Hex(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016" PRIx64, value);
  return text;
}

bool ParseHex(const nlohmann::json& j, uint64_t* value) {
  if (!j.is_string() || j.get<std::string>().size() != 16) return false;
  const std::string text = j.get<std::string>();
  char* end = nullptr;
  *value = std::strtoull(text.c_str(), &end, 16);
  return end == text.c_str() + text.size();
}

}  // namespace

uint64_t HashBytes(const void* data, size_t size, uint64_t seed) {
  // Four independent 64-bit lanes (fast on long payloads), folded together at the end.
  const auto* bytes = static_cast<const uint8_t*>(data);
  uint64_t lanes[4] = {seed ^ 1, seed ^ 2, seed ^ 3, seed ^ 4};
  size_t i = 0;
  for (; i + 32 <= size; i += 32) {
    for (int k = 0; k < 4; ++k) {
      uint64_t w;
      std::memcpy(&w, bytes + i + 8 * k, 8);
      lanes[k] = (lanes[k] ^ w) * kMul;
      lanes[k] ^= lanes[k] >> 32;
    }
  }
  uint64_t h = Mix(size * kMul);
  for (uint64_t lane : lanes) h = Mix(h ^ lane) * kMul;
  for (; i < size; ++i) h = (h ^ bytes[i]) * kMul;
  return Mix(h);
}

uint64_t StateChecksum(const FloatMap& state) {
  const int32_t sizes[3] = {state.width, state.height, state.channels};
  return HashBytes(state.data.data(), state.data.size() * sizeof(float), HashBytes(sizes, sizeof(sizes)));
}

std::string StateOptionsText(const MpMvsOptions& options) {
  return "math_revision " + std::to_string(kStateMathRevision) + "\n" + ResultOptionsText(options);
}

bool ReadStateRecord(const std::string& path, StateRecord* record, std::string* why) {
  if (!FileExists(path)) {
    *why = "its record " + path + " is missing (made by an older mp-mvs or interrupted)";
    return false;
  }
  try {
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.value("format", "") != "mpmvs-state") throw std::runtime_error("not an mp-mvs state record");
    record->version = j.at("version").get<int>();
    if (record->version != StateRecord::kVersion) {
      *why = "its record " + path + " has version " + std::to_string(record->version) + ", this mp-mvs writes " +
             std::to_string(StateRecord::kVersion);
      return false;
    }
    record->stage = j.at("stage").get<std::string>();
    record->width = j.at("width").get<int>();
    record->height = j.at("height").get<int>();
    if (!ParseHex(j.at("options"), &record->options) || !ParseHex(j.at("inputs"), &record->inputs) ||
        !ParseHex(j.at("checksum"), &record->checksum)) {
      throw std::runtime_error("bad hash field");
    }
  } catch (const std::exception& e) {
    *why = "its record " + path + " is unreadable (" + e.what() + ")";
    return false;
  }
  return true;
}

void WriteStateRecord(const std::string& path, const StateRecord& record) {
  nlohmann::ordered_json j;
  j["format"] = "mpmvs-state";
  j["version"] = record.version;
  j["stage"] = record.stage;
  j["width"] = record.width;
  j["height"] = record.height;
  j["options"] = Hex(record.options);
  j["inputs"] = Hex(record.inputs);
  j["checksum"] = Hex(record.checksum);
  WriteFileAtomically(path, [&](std::ostream& out) { out << j.dump(1) << "\n"; });
}

}  // namespace mpmvs
