#pragma once
// The entry points of the fuzz harnesses (tests/fuzz/*_fuzzer.cc, built with libFuzzer in
// MPMVS_FUZZ builds) and of their replay in the ordinary test suite (fuzz_replay_test.cc):
// each writes the bytes where the reader expects its file(s) and calls the reader. A
// reader may refuse the input with mpmvs::Error; anything else (crash, sanitizer report,
// another exception) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {
namespace fuzz {

// A reader under test: name (= folder of its corpus in tests/fuzz/corpus) and entry point.
struct FuzzReader {
  const char* name;
  void (*run)(const uint8_t* data, size_t size);
};
const std::vector<FuzzReader>& FuzzReaders();
// The reader of that name; throws std::invalid_argument for an unknown name.
const FuzzReader& FindFuzzReader(const std::string& name);

// Inputs that hold several files (sparse models, the option list) separate them by this.
constexpr char kPartSeparator[] = "\n----\n";
// At most max_parts parts (the last keeps any further separators).
std::vector<std::string> SplitParts(const uint8_t* data, size_t size, size_t max_parts);

// Runs the reader, swallowing mpmvs::Error only. Returns 0 (libFuzzer's convention).
int RunFuzzReader(const FuzzReader& reader, const uint8_t* data, size_t size);

}  // namespace fuzz
}  // namespace mpmvs
