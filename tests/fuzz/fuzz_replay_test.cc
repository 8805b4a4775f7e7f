// Replays the fuzz corpus (tests/fuzz/corpus/<reader>) and every input that once crashed a
// reader (tests/fuzz/crashes/<reader>) through the harnesses' entry points: each must be
// read or refused with mpmvs::Error, never crash (the sanitizer builds catch memory errors).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_readers.h"

namespace mpmvs {
namespace fuzz {
// gtest prints the parameter by its name.
void PrintTo(const FuzzReader& reader, std::ostream* os) { *os << reader.name; }
}  // namespace fuzz

namespace {

namespace fs = std::filesystem;

std::vector<std::string> FilesIn(const fs::path& dir) {
  std::vector<std::string> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file()) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string ReaderName(const testing::TestParamInfo<fuzz::FuzzReader>& info) { return info.param.name; }

class FuzzReplay : public testing::TestWithParam<fuzz::FuzzReader> {};

TEST_P(FuzzReplay, CorpusAndCrashesAreReadOrRefused) {
  const fs::path root = fs::path(MPMVS_SOURCE_DIR) / "tests" / "fuzz";
  const std::vector<std::string> corpus = FilesIn(root / "corpus" / GetParam().name);
  const std::vector<std::string> crashes = FilesIn(root / "crashes" / GetParam().name);
  EXPECT_FALSE(corpus.empty()) << "no corpus in " << (root / "corpus" / GetParam().name);
  std::vector<std::string> files = corpus;
  files.insert(files.end(), crashes.begin(), crashes.end());
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // RunFuzzReader lets only mpmvs::Error through as a refusal.
    EXPECT_NO_THROW(fuzz::RunFuzzReader(GetParam(), reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
  }
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzReplay, testing::ValuesIn(fuzz::FuzzReaders()), ReaderName);

// Multi-file inputs (sparse models, option lists) are split like this.
TEST(FuzzInput, SplitPartsKeepsEmptyAndTrailingParts) {
  const std::string text = std::string("a") + fuzz::kPartSeparator + fuzz::kPartSeparator + "c";
  const auto* data = reinterpret_cast<const uint8_t*>(text.data());
  EXPECT_EQ(fuzz::SplitParts(data, text.size(), 3), (std::vector<std::string>{"a", "", "c"}));
  EXPECT_EQ(fuzz::SplitParts(data, text.size(), 2),
            (std::vector<std::string>{"a", std::string(fuzz::kPartSeparator) + "c"}));
  EXPECT_EQ(fuzz::SplitParts(data, 1, 3), (std::vector<std::string>{"a"}));
}

}  // namespace
}  // namespace mpmvs
