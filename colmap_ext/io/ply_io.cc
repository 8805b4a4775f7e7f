#include "colmap_ext/io/ply_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"

namespace mpmvs {
namespace {

enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

struct PlyProperty {
  std::string name;
  int size = 0;  // bytes of the scalar type (or of a list's items)
  char kind = 'f';  // 'i' signed, 'u' unsigned, 'f' floating
  bool is_list = false;
  int count_size = 0;  // list count type
  char count_kind = 'u';
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool ParseType(const std::string& t, int* size, char* kind) {
  static const struct {
    const char* name;
    int size;
    char kind;
  } kTypes[] = {{"char", 1, 'i'},   {"int8", 1, 'i'},    {"uchar", 1, 'u'},   {"uint8", 1, 'u'},
                {"short", 2, 'i'},  {"int16", 2, 'i'},   {"ushort", 2, 'u'},  {"uint16", 2, 'u'},
                {"int", 4, 'i'},    {"int32", 4, 'i'},   {"uint", 4, 'u'},    {"uint32", 4, 'u'},
                {"float", 4, 'f'},  {"float32", 4, 'f'}, {"double", 8, 'f'},  {"float64", 8, 'f'}};
  for (const auto& entry : kTypes) {
    if (t == entry.name) {
      *size = entry.size;
      *kind = entry.kind;
      return true;
    }
  }
  return false;
}

bool HostIsLittleEndian() {
  const uint16_t probe = 1;
  uint8_t first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

// Decodes one binary scalar as double.
double DecodeScalar(const uint8_t* p, int size, char kind, bool swap) {
  uint8_t buf[8];
  std::memcpy(buf, p, size);
  if (swap) std::reverse(buf, buf + size);
  switch (size) {
    case 1:
      return kind == 'i' ? static_cast<double>(static_cast<int8_t>(buf[0])) : buf[0];
    case 2: {
      if (kind == 'i') {
        int16_t v;
        std::memcpy(&v, buf, 2);
        return v;
      }
      uint16_t v;
      std::memcpy(&v, buf, 2);
      return v;
    }
    case 4: {
      if (kind == 'f') {
        float v;
        std::memcpy(&v, buf, 4);
        return v;
      }
      if (kind == 'i') {
        int32_t v;
        std::memcpy(&v, buf, 4);
        return v;
      }
      uint32_t v;
      std::memcpy(&v, buf, 4);
      return v;
    }
    default: {
      double v;
      std::memcpy(&v, buf, 8);
      return v;
    }
  }
}

uint8_t ColorValue(double v, char kind) {
  if (kind == 'f') v *= 255.0;  // float colours are in [0, 1]
  return static_cast<uint8_t>(std::lround(std::min(255.0, std::max(0.0, v))));
}

// Index of the first property with one of the names, or -1.
int FindProperty(const PlyElement& e, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (size_t i = 0; i < e.properties.size(); ++i) {
      if (e.properties[i].name == name) return static_cast<int>(i);
    }
  }
  return -1;
}

template <typename T>
void AppendLittleEndian(std::string* out, T value) {
  char buf[sizeof(T)];
  std::memcpy(buf, &value, sizeof(T));
  if (!HostIsLittleEndian()) std::reverse(buf, buf + sizeof(T));
  out->append(buf, sizeof(T));
}

}  // namespace

PlyPointCloud ReadPlyPointCloud(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) ThrowFileError(path, "cannot open the PLY file");
  std::string line;
  if (!std::getline(file, line) || line.substr(0, 3) != "ply") {
    ThrowFileError(path, "not a PLY file (no 'ply' magic line)");
  }
  PlyFormat format = PlyFormat::kAscii;
  bool have_format = false;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (std::getline(file, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (word == "format") {
      std::string f;
      ss >> f;
      if (f == "ascii") format = PlyFormat::kAscii;
      else if (f == "binary_little_endian") format = PlyFormat::kBinaryLittle;
      else if (f == "binary_big_endian") format = PlyFormat::kBinaryBig;
      else ThrowFileError(path, "unknown PLY format '" + f + "'");
      have_format = true;
    } else if (word == "element") {
      PlyElement e;
      long long count = -1;
      ss >> e.name >> count;
      if (!ss || count < 0) ThrowFileError(path, "malformed PLY element line '" + line + "'");
      e.count = static_cast<uint64_t>(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) ThrowFileError(path, "PLY property before any element");
      PlyProperty p;
      std::string type;
      ss >> type;
      if (type == "list") {
        std::string count_type, item_type;
        ss >> count_type >> item_type >> p.name;
        p.is_list = true;
        if (!ParseType(count_type, &p.count_size, &p.count_kind) ||
            !ParseType(item_type, &p.size, &p.kind)) {
          ThrowFileError(path, "unknown PLY list type in '" + line + "'");
        }
      } else {
        ss >> p.name;
        if (!ParseType(type, &p.size, &p.kind)) {
          ThrowFileError(path, "unknown PLY property type '" + type + "'");
        }
      }
      elements.back().properties.push_back(p);
    } else if (word == "end_header") {
      ended = true;
      break;
    }
    // comment / obj_info lines are skipped.
  }
  if (!ended) ThrowFileError(path, "PLY header has no end_header line");
  if (!have_format) ThrowFileError(path, "PLY header has no format line");
  int vertex_index = -1;
  for (size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].name == "vertex") vertex_index = static_cast<int>(i);
  }
  if (vertex_index < 0) ThrowFileError(path, "PLY file has no vertex element");
  const PlyElement& vertex = elements[vertex_index];
  for (const PlyProperty& p : vertex.properties) {
    if (p.is_list) ThrowFileError(path, "PLY vertex element has a list property '" + p.name + "'");
  }
  const int ix = FindProperty(vertex, {"x"}), iy = FindProperty(vertex, {"y"}),
            iz = FindProperty(vertex, {"z"});
  if (ix < 0 || iy < 0 || iz < 0) ThrowFileError(path, "PLY vertices lack x, y or z");
  const int inx = FindProperty(vertex, {"nx"}), iny = FindProperty(vertex, {"ny"}),
            inz = FindProperty(vertex, {"nz"});
  const int ir = FindProperty(vertex, {"red", "r", "diffuse_red"});
  const int ig = FindProperty(vertex, {"green", "g", "diffuse_green"});
  const int ib = FindProperty(vertex, {"blue", "b", "diffuse_blue"});

  PlyPointCloud cloud;
  cloud.has_normals = inx >= 0 && iny >= 0 && inz >= 0;
  cloud.has_colors = ir >= 0 && ig >= 0 && ib >= 0;
  const std::string body((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const size_t nprop = vertex.properties.size();
  std::vector<double> values(nprop);
  auto store = [&](const std::vector<double>& v) {
    PlyPoint pt;
    pt.x = static_cast<float>(v[ix]);
    pt.y = static_cast<float>(v[iy]);
    pt.z = static_cast<float>(v[iz]);
    if (cloud.has_normals) {
      pt.nx = static_cast<float>(v[inx]);
      pt.ny = static_cast<float>(v[iny]);
      pt.nz = static_cast<float>(v[inz]);
    }
    if (cloud.has_colors) {
      pt.r = ColorValue(v[ir], vertex.properties[ir].kind);
      pt.g = ColorValue(v[ig], vertex.properties[ig].kind);
      pt.b = ColorValue(v[ib], vertex.properties[ib].kind);
    }
    cloud.points.push_back(pt);
  };

  if (format == PlyFormat::kAscii) {
    std::istringstream in(body);
    for (int e = 0; e <= vertex_index; ++e) {
      const PlyElement& el = elements[e];
      for (uint64_t k = 0; k < el.count; ++k) {
        if (e < vertex_index) {  // one line per element of earlier elements
          std::string skip;
          // Stops at the end of the body: a huge count must not spin on an empty stream.
          if (!std::getline(in, skip)) {
            ThrowFileError(path, "PLY ascii body ends inside element '" + el.name + "' (" +
                                     std::to_string(el.count) + " promised)");
          }
          continue;
        }
        for (size_t p = 0; p < nprop; ++p) {
          if (!(in >> values[p])) {
            ThrowFileError(path, "PLY ascii body ends before vertex " + std::to_string(k) +
                                     " of " + std::to_string(el.count));
          }
        }
        store(values);
      }
    }
    return cloud;
  }

  const bool swap = (format == PlyFormat::kBinaryLittle) != HostIsLittleEndian();
  const uint8_t* data = reinterpret_cast<const uint8_t*>(body.data());
  size_t pos = 0;
  auto need = [&](size_t bytes) {
    if (bytes > body.size() - pos) ThrowFileError(path, "PLY body is shorter than its header says");
  };
  for (int e = 0; e < vertex_index; ++e) {  // skip earlier elements
    if (elements[e].properties.empty()) continue;  // nothing to skip, however many
    for (uint64_t k = 0; k < elements[e].count; ++k) {
      for (const PlyProperty& p : elements[e].properties) {
        if (p.is_list) {
          need(p.count_size);
          const double n = DecodeScalar(data + pos, p.count_size, p.count_kind, swap);
          pos += p.count_size;
          // Checked before the conversion: a negative, fractional or huge count (of a float
          // count type) must not reach the size_t cast or overflow the product.
          if (!(n >= 0) || n != std::floor(n) || n > static_cast<double>(body.size() - pos) / p.size) {
            ThrowFileError(path, "PLY list property '" + p.name + "' has an invalid or too large count " +
                                     std::to_string(n));
          }
          need(static_cast<size_t>(n) * p.size);
          pos += static_cast<size_t>(n) * p.size;
        } else {
          need(p.size);
          pos += p.size;
        }
      }
    }
  }
  size_t stride = 0;
  for (const PlyProperty& p : vertex.properties) stride += p.size;
  if (stride == 0 || vertex.count > (body.size() - pos) / stride) {
    ThrowFileError(path, "PLY body is shorter than its " + std::to_string(vertex.count) +
                             " vertices need");
  }
  cloud.points.reserve(vertex.count);
  for (uint64_t k = 0; k < vertex.count; ++k) {
    for (size_t p = 0; p < nprop; ++p) {
      const PlyProperty& prop = vertex.properties[p];
      values[p] = DecodeScalar(data + pos, prop.size, prop.kind, swap);
      pos += prop.size;
    }
    store(values);
  }
  return cloud;
}

void WritePlyPointCloud(const std::string& path, const PlyPointCloud& cloud) {
  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " +
                       std::to_string(cloud.points.size()) +
                       "\nproperty float x\nproperty float y\nproperty float z\n";
  if (cloud.has_normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (cloud.has_colors) {
    header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  }
  header += "end_header\n";
  std::string body;
  body.reserve(cloud.points.size() * 27);
  for (const PlyPoint& p : cloud.points) {
    AppendLittleEndian(&body, p.x);
    AppendLittleEndian(&body, p.y);
    AppendLittleEndian(&body, p.z);
    if (cloud.has_normals) {
      AppendLittleEndian(&body, p.nx);
      AppendLittleEndian(&body, p.ny);
      AppendLittleEndian(&body, p.nz);
    }
    if (cloud.has_colors) {
      body.push_back(static_cast<char>(p.r));
      body.push_back(static_cast<char>(p.g));
      body.push_back(static_cast<char>(p.b));
    }
  }
  WriteFileAtomically(path, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

}  // namespace mpmvs
