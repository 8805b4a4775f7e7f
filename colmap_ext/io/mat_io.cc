#include "colmap_ext/io/mat_io.h"

#include <climits>
#include <filesystem>
#include <fstream>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "mp-mvs assumes a little-endian host");

namespace mpmvs {
namespace {

struct MatHeader {
  uint64_t width = 0;
  uint64_t height = 0;
  uint64_t channels = 0;
  uint64_t header_bytes = 0;
  uint64_t file_bytes = 0;
};

// Opens path and parses "W&H&C&" strictly: three positive decimal numbers (no signs, no
// spaces), each ending in '&'. The stream is left at the first data byte.
MatHeader ReadMatHeader(const std::string& path, std::ifstream* file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) ThrowFileError(path, "file does not exist");
  file->open(path, std::ios::binary);
  if (!file->is_open()) ThrowFileError(path, "cannot open file for reading");
  MatHeader header;
  header.file_bytes = std::filesystem::file_size(path, ec);
  if (ec) ThrowFileError(path, "cannot determine the file size");

  constexpr int kMaxDigits = 10;  // sizes fit in int
  uint64_t* fields[3] = {&header.width, &header.height, &header.channels};
  const char* names[3] = {"width", "height", "channels"};
  for (int i = 0; i < 3; ++i) {
    uint64_t value = 0;
    int digits = 0;
    char c = 0;
    while (file->get(c) && c >= '0' && c <= '9') {
      if (++digits > kMaxDigits) {
        ThrowFileError(path, std::string("malformed header: ") + names[i] + " is too large");
      }
      value = value * 10 + static_cast<uint64_t>(c - '0');
      ++header.header_bytes;
    }
    if (!*file) {
      ThrowFileError(path, "malformed header: file ends inside the \"WIDTH&HEIGHT&CHANNELS&\" header");
    }
    if (digits == 0 || c != '&') {
      ThrowFileError(path, std::string("malformed header: expected a decimal ") + names[i] +
                               " followed by '&' (not a COLMAP depth/normal map?)");
    }
    ++header.header_bytes;
    if (value == 0 || value > static_cast<uint64_t>(INT_MAX)) {
      ThrowFileError(path, std::string("malformed header: ") + names[i] + " " +
                               std::to_string(value) + " is out of range");
    }
    *fields[i] = value;
  }
  return header;
}

// Number of `element_bytes` elements after the header; Error unless it is a whole number.
uint64_t NumDataElements(const std::string& path, const MatHeader& header, uint64_t element_bytes) {
  const uint64_t data_bytes = header.file_bytes - header.header_bytes;
  if (data_bytes % element_bytes != 0) {
    ThrowFileError(path, "data size " + std::to_string(data_bytes) + " bytes is not a multiple of " +
                             std::to_string(element_bytes));
  }
  return data_bytes / element_bytes;
}

std::string HeaderText(uint64_t width, uint64_t height, uint64_t channels) {
  return std::to_string(width) + "&" + std::to_string(height) + "&" + std::to_string(channels) +
         "&";
}

}  // namespace

FloatMap ReadFloatMap(const std::string& path, int expected_channels) {
  std::ifstream file;
  const MatHeader header = ReadMatHeader(path, &file);
  if (expected_channels >= 1 && header.channels != static_cast<uint64_t>(expected_channels)) {
    ThrowFileError(path, "has " + std::to_string(header.channels) + " channels, expected " +
                             std::to_string(expected_channels));
  }
  // Compare by division so huge header values cannot overflow; nothing is allocated before.
  const uint64_t num_values = NumDataElements(path, header, sizeof(float));
  const bool sizes_match = num_values % header.width == 0 &&
                           (num_values / header.width) % header.height == 0 &&
                           num_values / header.width / header.height == header.channels;
  if (!sizes_match) {
    ThrowFileError(path, "header says " + std::to_string(header.width) + "x" +
                             std::to_string(header.height) + "x" + std::to_string(header.channels) +
                             " floats, but the file holds " + std::to_string(num_values) +
                             " (truncated or corrupt)");
  }
  FloatMap map;
  map.width = static_cast<int>(header.width);
  map.height = static_cast<int>(header.height);
  map.channels = static_cast<int>(header.channels);
  map.data.resize(num_values);
  if (!file.read(reinterpret_cast<char*>(map.data.data()),
                 static_cast<std::streamsize>(num_values * sizeof(float)))) {
    ThrowFileError(path, "read failed");
  }
  return map;
}

std::string CheckFloatMapFile(const std::string& path, int width, int height, int channels) {
  try {
    std::ifstream file;
    const MatHeader header = ReadMatHeader(path, &file);
    const std::string expected = HeaderText(width, height, channels);
    if (header.width != static_cast<uint64_t>(width) || header.height != static_cast<uint64_t>(height) ||
        header.channels != static_cast<uint64_t>(channels)) {
      return "header says " + HeaderText(header.width, header.height, header.channels) + ", expected " + expected;
    }
    const uint64_t expected_bytes =
        header.header_bytes + static_cast<uint64_t>(width) * height * channels * sizeof(float);
    if (header.file_bytes != expected_bytes) {
      return "file holds " + std::to_string(header.file_bytes) + " bytes, a " + expected + " map holds " +
             std::to_string(expected_bytes) + " (truncated or corrupt)";
    }
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

void WriteFloatMap(const std::string& path, const FloatMap& map) {
  if (map.width <= 0 || map.height <= 0 || map.channels <= 0 ||
      map.data.size() != static_cast<size_t>(map.width) * map.height * map.channels) {
    ThrowFileError(path, "cannot write a map of size " + std::to_string(map.width) + "x" +
                             std::to_string(map.height) + "x" + std::to_string(map.channels) +
                             " holding " + std::to_string(map.data.size()) + " values");
  }
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << HeaderText(map.width, map.height, map.channels);
    out.write(reinterpret_cast<const char*>(map.data.data()),
              static_cast<std::streamsize>(map.data.size() * sizeof(float)));
  });
}

namespace {

// Checks that the record stream is well formed: pixel inside the image, N > 0, all indices
// present and non-negative.
void ValidateConsistencyGraph(const std::string& path, const ConsistencyGraph& graph) {
  const std::vector<int32_t>& data = graph.data;
  size_t i = 0;
  while (i < data.size()) {
    if (data.size() - i < 3) ThrowFileError(path, "record truncated at value " + std::to_string(i));
    const int32_t col = data[i], row = data[i + 1], num = data[i + 2];
    if (col < 0 || col >= graph.width || row < 0 || row >= graph.height) {
      ThrowFileError(path, "record at value " + std::to_string(i) + " has pixel (" +
                               std::to_string(col) + ", " + std::to_string(row) +
                               ") outside the " + std::to_string(graph.width) + "x" +
                               std::to_string(graph.height) + " image");
    }
    if (num <= 0 || static_cast<size_t>(num) > data.size() - i - 3) {
      ThrowFileError(path, "record at value " + std::to_string(i) + " has a bad image count " +
                               std::to_string(num));
    }
    for (int32_t k = 0; k < num; ++k) {
      if (data[i + 3 + k] < 0) {
        ThrowFileError(path, "record at value " + std::to_string(i) + " has a negative image index");
      }
    }
    i += 3 + static_cast<size_t>(num);
  }
}

}  // namespace

ConsistencyGraph ReadConsistencyGraph(const std::string& path) {
  std::ifstream file;
  const MatHeader header = ReadMatHeader(path, &file);
  if (header.channels != 1) {
    ThrowFileError(path, "consistency graph header must have 1 channel, has " +
                             std::to_string(header.channels));
  }
  const uint64_t num_values = NumDataElements(path, header, sizeof(int32_t));
  ConsistencyGraph graph;
  graph.width = static_cast<int>(header.width);
  graph.height = static_cast<int>(header.height);
  graph.data.resize(num_values);
  if (num_values > 0 && !file.read(reinterpret_cast<char*>(graph.data.data()),
                                   static_cast<std::streamsize>(num_values * sizeof(int32_t)))) {
    ThrowFileError(path, "read failed");
  }
  ValidateConsistencyGraph(path, graph);
  return graph;
}

void WriteConsistencyGraph(const std::string& path, const ConsistencyGraph& graph) {
  if (graph.width <= 0 || graph.height <= 0) {
    ThrowFileError(path, "cannot write a consistency graph of size " + std::to_string(graph.width) +
                             "x" + std::to_string(graph.height));
  }
  ValidateConsistencyGraph(path, graph);
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << HeaderText(graph.width, graph.height, 1);
    out.write(reinterpret_cast<const char*>(graph.data.data()),
              static_cast<std::streamsize>(graph.data.size() * sizeof(int32_t)));
  });
}

}  // namespace mpmvs
