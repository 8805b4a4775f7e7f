#include "colmap_ext/io/mat_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "colmap_ext/util/file_util.h"
#include "tests/io_test_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

using test::TempDir;
using test::WriteText;

// Every file in dir (to check that no temporary was left behind).
std::vector<std::string> ListDirectory(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

FloatMap MakeMap(int width, int height, int channels) {
  FloatMap map(width, height, channels);
  for (int d = 0; d < channels; ++d) {
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) map.At(r, c, d) = 1000.f * d + 10.f * r + c + 0.5f;
    }
  }
  return map;
}

TEST(MatIo, DepthMapLayoutIsColmaps) {
  TempDir dir;
  const FloatMap map = MakeMap(3, 2, 1);
  WriteFloatMap(dir / "d.bin", map);
  const std::vector<uint8_t> bytes = ReadFileBytes(dir / "d.bin");
  const std::string header = "3&2&1&";
  ASSERT_EQ(bytes.size(), header.size() + 4 * 6);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + header.size()), header);
  // Row-major: value (r, c) is float number r*W + c.
  for (int i = 0; i < 6; ++i) {
    float value;
    std::memcpy(&value, bytes.data() + header.size() + 4 * i, 4);
    EXPECT_EQ(value, 10.f * (i / 3) + (i % 3) + 0.5f) << i;
  }
}

TEST(MatIo, NormalMapIsPlanar) {
  TempDir dir;
  const FloatMap map = MakeMap(4, 3, 3);
  WriteFloatMap(dir / "n.bin", map);
  const std::vector<uint8_t> bytes = ReadFileBytes(dir / "n.bin");
  const size_t header = std::string("4&3&3&").size();
  ASSERT_EQ(bytes.size(), header + 4 * 36);
  for (int d = 0; d < 3; ++d) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        float value;
        std::memcpy(&value, bytes.data() + header + 4 * (d * 12 + r * 4 + c), 4);
        EXPECT_EQ(value, map.At(r, c, d));
      }
    }
  }
  const FloatMap read = ReadFloatMap(dir / "n.bin", 3);
  EXPECT_EQ(read.width, 4);
  EXPECT_EQ(read.height, 3);
  EXPECT_EQ(read.channels, 3);
  EXPECT_EQ(read.data, map.data);
  EXPECT_EQ(ReadFloatMap(dir / "n.bin").channels, 3);
}

TEST(MatIo, ReadsHandMadeColmapFile) {
  TempDir dir;
  std::vector<uint8_t> bytes = {'1', '6', '0', '&', '1', '2', '0', '&', '1', '&'};
  const size_t header = bytes.size();
  bytes.resize(header + 4 * 160 * 120);
  test::PutValue<float>(&bytes, header + 4 * (119 * 160 + 159), 6.25f);
  test::WriteBytes(dir / "x.bin", bytes);
  const FloatMap map = ReadFloatMap(dir / "x.bin", 1);
  EXPECT_EQ(map.width, 160);
  EXPECT_EQ(map.height, 120);
  EXPECT_EQ(map.At(119, 159), 6.25f);
  EXPECT_EQ(map.At(0, 0), 0.f);
}

TEST(MatIo, CorruptFilesNameTheFile) {
  TempDir dir;
  const std::string path = dir / "bad.geometric.bin";
  struct Case {
    std::string header;
    size_t num_floats;
    std::string expected;
  };
  const Case cases[] = {
      {"", 0, "file ends inside"},
      {"abc", 0, "malformed header"},
      {"3&2&", 6, "malformed header"},
      {"3&2&1", 0, "malformed header"},
      {"3 &2&1&", 6, "malformed header"},
      {" 3&2&1&", 6, "malformed header"},
      {"-3&2&1&", 6, "malformed header"},
      {"+3&2&1&", 6, "malformed header"},
      {"3.0&2&1&", 6, "malformed header"},
      {"0&2&1&", 0, "width 0 is out of range"},
      {"3&2&0&", 0, "channels 0 is out of range"},
      {"3&2&1&", 5, "header says 3x2x1 floats, but the file holds 5"},
      {"3&2&1&", 7, "but the file holds 7"},
      {"99999999999&2&1&", 6, "too large"},
      {"2000000000&2000000000&3&", 6, "header says 2000000000x2000000000x3"},
      {"3&2&1&", 0, "header says 3x2x1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.header);
    std::vector<uint8_t> bytes(c.header.begin(), c.header.end());
    bytes.resize(bytes.size() + 4 * c.num_floats, 0);
    test::WriteBytes(path, bytes);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_MPMVS_ERROR(ReadFloatMap(path), path + ": ");
    EXPECT_MPMVS_ERROR(ReadFloatMap(path), c.expected);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  }
  // A byte that is not a whole float.
  std::vector<uint8_t> odd = {'1', '&', '1', '&', '1', '&', 0, 0, 0, 0, 0};
  test::WriteBytes(path, odd);
  EXPECT_MPMVS_ERROR(ReadFloatMap(path), "not a multiple of 4");
  EXPECT_MPMVS_ERROR(ReadFloatMap(dir / "missing.bin"), "missing.bin: file does not exist");
}

TEST(MatIo, WrongChannelCount) {
  TempDir dir;
  WriteFloatMap(dir / "n.bin", MakeMap(2, 2, 3));
  EXPECT_MPMVS_ERROR(ReadFloatMap(dir / "n.bin", 1), "n.bin: has 3 channels, expected 1");
}

TEST(MatIo, WriterRejectsInconsistentMap) {
  TempDir dir;
  FloatMap map = MakeMap(2, 2, 1);
  map.data.pop_back();
  EXPECT_MPMVS_ERROR(WriteFloatMap(dir / "m.bin", map), "m.bin");
  EXPECT_MPMVS_ERROR(WriteFloatMap(dir / "e.bin", FloatMap()), "e.bin");
  EXPECT_TRUE(ListDirectory(dir.path()).empty());
}

TEST(MatIo, ConsistencyGraphRoundTrip) {
  TempDir dir;
  ConsistencyGraph graph;
  graph.width = 5;
  graph.height = 4;
  graph.data = {0, 0, 2, 1, 3,  // col 0, row 0: images 1 and 3
                4, 1, 1, 0,     // col 4, row 1
                2, 3, 3, 0, 1, 2};
  WriteConsistencyGraph(dir / "g.bin", graph);
  const std::vector<uint8_t> bytes = ReadFileBytes(dir / "g.bin");
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 6), "5&4&1&");
  EXPECT_EQ(bytes.size(), 6 + 4 * graph.data.size());
  const ConsistencyGraph read = ReadConsistencyGraph(dir / "g.bin");
  EXPECT_EQ(read.width, 5);
  EXPECT_EQ(read.height, 4);
  EXPECT_EQ(read.data, graph.data);

  // Empty graph (no consistent pixel) is valid.
  graph.data.clear();
  WriteConsistencyGraph(dir / "empty.bin", graph);
  EXPECT_TRUE(ReadConsistencyGraph(dir / "empty.bin").data.empty());
}

TEST(MatIo, CorruptConsistencyGraph) {
  TempDir dir;
  const std::string path = dir / "g.bin";
  const auto write = [&](const std::string& header, const std::vector<int32_t>& values) {
    std::vector<uint8_t> bytes(header.begin(), header.end());
    const size_t offset = bytes.size();
    bytes.resize(offset + 4 * values.size());
    if (!values.empty()) std::memcpy(bytes.data() + offset, values.data(), 4 * values.size());
    test::WriteBytes(path, bytes);
  };
  write("5&4&2&", {});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "g.bin: consistency graph header must have 1 channel");
  write("5&4&1&", {0, 0});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "g.bin: record truncated");
  write("5&4&1&", {5, 0, 1, 2});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "outside the 5x4 image");
  write("5&4&1&", {0, 0, 3, 1, 2});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "bad image count 3");
  write("5&4&1&", {0, 0, 0});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "bad image count 0");
  write("5&4&1&", {0, 0, 1, -4});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "negative image index");
  write("5&4&x&", {});
  EXPECT_MPMVS_ERROR(ReadConsistencyGraph(path), "g.bin: malformed header");
}

// ---- atomic writes -----------------------------------------------------------------------

TEST(FileUtil, FailedWriteLeavesEarlierFileAndNoTemporary) {
  TempDir dir;
  const std::string path = dir / "depth.geometric.bin";
  const FloatMap original = MakeMap(3, 3, 1);
  WriteFloatMap(path, original);
  const std::vector<uint8_t> original_bytes = ReadFileBytes(path);

  // A writer that has written half of its data and then throws.
  EXPECT_MPMVS_ERROR(WriteFileAtomically(path,
                                         [](std::ostream& out) {
                                           out << "7&7&1&" << std::string(50, 'x');
                                           throw std::runtime_error("simulated crash");
                                         }),
                     "depth.geometric.bin: write failed: simulated crash");
  EXPECT_EQ(ReadFileBytes(path), original_bytes);
  EXPECT_EQ(ListDirectory(dir.path()), std::vector<std::string>{"depth.geometric.bin"});

  // An mpmvs::Error from the writer passes through unchanged.
  EXPECT_MPMVS_ERROR(WriteFileAtomically(path, [](std::ostream&) { throw Error("inner"); }),
                     "inner");
  EXPECT_EQ(ReadFileBytes(path), original_bytes);
  EXPECT_EQ(ListDirectory(dir.path()).size(), 1u);

  // A successful write replaces the file.
  WriteFloatMap(path, MakeMap(2, 2, 1));
  EXPECT_EQ(ReadFloatMap(path).width, 2);
  EXPECT_EQ(ListDirectory(dir.path()).size(), 1u);
}

TEST(FileUtil, WriteIntoMissingFolderFails) {
  TempDir dir;
  EXPECT_MPMVS_ERROR(WriteFloatMap(dir / "no/such/dir/x.bin", MakeMap(1, 1, 1)),
                     "no/such/dir/x.bin: cannot create file");
}

TEST(FileUtil, PathsAndFiles) {
  EXPECT_EQ(JoinPaths("a", "b"), "a/b");
  EXPECT_EQ(JoinPaths("a/", "b"), "a/b");
  EXPECT_EQ(JoinPaths("a/", "/b"), "a/b");
  EXPECT_EQ(JoinPaths("a", "/b"), "a/b");
  EXPECT_EQ(JoinPaths("", "b"), "b");
  EXPECT_EQ(JoinPaths("a", ""), "a");
  EXPECT_EQ(ParentPath("a/b/c.bin"), "a/b");
  EXPECT_EQ(ParentPath("c.bin"), "");
  TempDir dir;
  EXPECT_TRUE(DirectoryExists(dir.path()));
  EXPECT_FALSE(FileExists(dir.path()));
  CreateDirectories(dir / "x/y/z");
  CreateDirectories(dir / "x/y/z");
  EXPECT_TRUE(DirectoryExists(dir / "x/y/z"));
  WriteText(dir / "f", "abc");
  EXPECT_TRUE(FileExists(dir / "f"));
  EXPECT_EQ(ReadFileBytes(dir / "f"), (std::vector<uint8_t>{'a', 'b', 'c'}));
  EXPECT_MPMVS_ERROR(ReadFileBytes(dir / "g"), "g: file does not exist");
  EXPECT_MPMVS_ERROR(ReadFileBytes(dir / "x"), "x: not a regular file");
  EXPECT_MPMVS_ERROR(CreateDirectories(dir / "f/sub"), "f/sub: cannot create directory");
}

}  // namespace
}  // namespace mpmvs
