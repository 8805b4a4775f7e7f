#include "colmap_ext/store/maps_record.h"

#include <sys/stat.h>

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "colmap_ext/store/state_record.h"
#include "colmap_ext/util/file_util.h"

namespace mpmvs {
namespace {

std::string Hex(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016" PRIx64, value);
  return text;
}

uint64_t ParseHex(const nlohmann::json& j) {
  const std::string text = j.get<std::string>();
  char* end = nullptr;
  const uint64_t value = std::strtoull(text.c_str(), &end, 16);
  if (text.size() != 16 || end != text.c_str() + text.size()) throw std::runtime_error("bad hash field");
  return value;
}

bool Stat(const std::string& path, uint64_t* size, int64_t* mtime_ns) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return false;
  *size = static_cast<uint64_t>(st.st_size);
  *mtime_ns = static_cast<int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  return true;
}

uint64_t FileChecksum(const std::string& path) {
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  return HashBytes(bytes.data(), bytes.size());
}

// "NAME VALUE" lines as a map.
std::map<std::string, std::string> OptionValues(const std::string& text) {
  std::map<std::string, std::string> values;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const size_t space = line.find(' ');
    if (space != std::string::npos) values[line.substr(0, space)] = line.substr(space + 1);
  }
  return values;
}

}  // namespace

const MapsRecord::File* MapsRecord::Find(const std::string& role) const {
  for (const File& file : files) {
    if (file.role == role) return &file;
  }
  return nullptr;
}

bool ReadMapsRecord(const std::string& path, MapsRecord* record, std::string* why) {
  if (!FileExists(path)) {
    *why = "it has no record " + path;
    return false;
  }
  try {
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.value("format", "") != "mpmvs-maps" || j.at("version").get<int>() != MapsRecord::kVersion) {
      throw std::runtime_error("not an mp-mvs maps record of version " + std::to_string(MapsRecord::kVersion));
    }
    record->type = j.at("type").get<std::string>();
    record->options = j.at("options").get<std::string>();
    record->maps_options = ParseHex(j.at("maps_options"));
    record->inputs = ParseHex(j.at("inputs"));
    record->files.clear();
    for (const auto& f : j.at("files")) {
      record->files.push_back({f.at("role").get<std::string>(), f.at("size").get<uint64_t>(),
                               f.at("mtime_ns").get<int64_t>(), ParseHex(f.at("checksum"))});
    }
  } catch (const std::exception& e) {
    *why = "its record " + path + " is unreadable (" + e.what() + ")";
    return false;
  }
  return true;
}

void WriteMapsRecord(const std::string& path, const MapsRecord& record) {
  nlohmann::ordered_json j;
  j["format"] = "mpmvs-maps";
  j["version"] = MapsRecord::kVersion;
  j["type"] = record.type;
  j["options"] = record.options;
  j["maps_options"] = Hex(record.maps_options);
  j["inputs"] = Hex(record.inputs);
  j["files"] = nlohmann::ordered_json::array();
  for (const MapsRecord::File& file : record.files) {
    nlohmann::ordered_json f;
    f["role"] = file.role;
    f["size"] = file.size;
    f["mtime_ns"] = file.mtime_ns;
    f["checksum"] = Hex(file.checksum);
    j["files"].push_back(f);
  }
  WriteFileAtomically(path, [&](std::ostream& out) { out << j.dump(1) << "\n"; });
}

MapsRecord::File DescribeFile(const std::string& path, const std::string& role) {
  MapsRecord::File file;
  file.role = role;
  Stat(path, &file.size, &file.mtime_ns);
  file.checksum = FileChecksum(path);
  return file;
}

bool FileMatches(const std::string& path, const MapsRecord::File& file) {
  uint64_t size = 0;
  int64_t mtime_ns = 0;
  if (!Stat(path, &size, &mtime_ns) || size != file.size) return false;
  return mtime_ns == file.mtime_ns || FileChecksum(path) == file.checksum;
}

std::string ChangedOptions(const std::string& before, const std::string& now) {
  const std::map<std::string, std::string> a = OptionValues(before), b = OptionValues(now);
  // An option missing from a text is a speed option at its paper value (options/option_spec.h).
  const std::string absent = "(the paper's value)";
  std::string changed;
  for (const auto& [name, value] : b) {
    const auto it = a.find(name);
    const std::string old_value = it == a.end() ? absent : it->second;
    if (old_value != value) changed += (changed.empty() ? "" : ", ") + name + " " + old_value + " -> " + value;
  }
  for (const auto& [name, value] : a) {
    if (!b.count(name)) changed += (changed.empty() ? "" : ", ") + name + " " + value + " -> " + absent;
  }
  return changed;
}

}  // namespace mpmvs
