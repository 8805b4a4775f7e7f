#pragma once
// The record beside a reference image's final maps of one type
// (stereo/mpmvs/NAME.TYPE.maps.json): the options and inputs the maps were made from and,
// per file, its size, modification time and checksum. With it a rerun tells a change of
// options (the maps are recomputed: no damage, nothing moved aside) from damage (bytes other
// than those written: moved aside and recomputed). Maps without a record (made by COLMAP,
// by an older mp-mvs, or stereo/mpmvs deleted) are judged by their values alone.
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {

struct MapsRecord {
  static constexpr int kVersion = 1;
  std::string type;             // photometric or geometric
  std::string options;          // ResultFingerprint::options when written (to name changes)
  uint64_t maps_options = 0;    // hash of ResultFingerprint::maps_options
  uint64_t inputs = 0;          // the reference's and its sources' images, cameras, depth range
  struct File {
    std::string role;           // depth, normal or consistency_graph
    uint64_t size = 0;
    int64_t mtime_ns = 0;
    uint64_t checksum = 0;      // HashBytes of the whole file
  };
  std::vector<File> files;
  const File* Find(const std::string& role) const;
};

// False with *why when absent or unreadable.
bool ReadMapsRecord(const std::string& path, MapsRecord* record, std::string* why);
// Atomic write.
void WriteMapsRecord(const std::string& path, const MapsRecord& record);

// The file as it is now: size, modification time and checksum of its bytes.
MapsRecord::File DescribeFile(const std::string& path, const std::string& role);
// Whether path holds the bytes `file` describes: same size and modification time (nobody
// wrote it since), or else the same checksum.
bool FileMatches(const std::string& path, const MapsRecord::File& file);

// "PatchMatchStereo.max_image_size 48 -> -1, MPMVS.seed 1 -> 7": the options whose values
// differ between two ResultFingerprint::options texts ("" when none).
std::string ChangedOptions(const std::string& before, const std::string& now);

}  // namespace mpmvs
