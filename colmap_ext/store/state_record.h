#pragma once
// The record beside each intermediate state file (stereo/mpmvs/NAME.STAGE.state.json): what
// produced the state (a hash of the result-changing options and stage chain, a hash of the
// reference's and its sources' images, cameras and depth range) and a checksum of its
// values, so that a rerun resumes only from states of the same options and inputs, whole.
// The state files themselves stay plain maps (mat_io.h); a state without its record is
// treated as unknown and recomputed.
#include <cstddef>
#include <cstdint>
#include <string>

#include "colmap_ext/io/mat_io.h"
#include "colmap_ext/options/patch_match_options.h"

namespace mpmvs {

struct StateRecord {
  static constexpr int kVersion = 1;
  int version = kVersion;
  std::string stage;
  int width = 0;
  int height = 0;
  uint64_t options = 0;   // StateOptionsText + the stage chain
  uint64_t inputs = 0;    // images, cameras, depth range and sources
  uint64_t checksum = 0;  // StateChecksum of the values
};

// 64-bit hash of bytes (not cryptographic: detects damage and changes, not tampering).
uint64_t HashBytes(const void* data, size_t size, uint64_t seed = 0);
inline uint64_t HashText(const std::string& text) { return HashBytes(text.data(), text.size()); }

// Checksum of a state map: its sizes and every value.
uint64_t StateChecksum(const FloatMap& state);

// Revision of the per-pixel math and the prior's construction: bumped whenever a change
// alters the states, so that a rerun with a newer mp-mvs recomputes older states instead
// of resuming from them.
constexpr int kStateMathRevision = 9;

// kStateMathRevision and the --MPMVS options that change a stage's result (declared so:
// ResultOptionsText). Image size, depth range and sources enter the inputs hash instead.
std::string StateOptionsText(const MpMvsOptions& options);

// "" when absent or unreadable (then the state counts as unknown).
bool ReadStateRecord(const std::string& path, StateRecord* record, std::string* why);
// Atomic write.
void WriteStateRecord(const std::string& path, const StateRecord& record);

}  // namespace mpmvs
