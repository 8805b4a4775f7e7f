#include "colmap_ext/io/sparse_model.h"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/file_util.h"
#include "colmap_ext/util/logging.h"

// The binary files are little-endian; values are copied byte-wise from/to host memory.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "mp-mvs assumes a little-endian host");

namespace mpmvs {
namespace {

struct CameraModelInfo {
  int id;
  const char* name;
  int num_params;
};

// COLMAP 3.8 knows ids 0-10; 11-17 exist in newer COLMAP (docs/colmap_interface.md §3) and are
// listed so such models still load (the dense workspace then rejects them as distorted).
constexpr CameraModelInfo kCameraModels[] = {
    {0, "SIMPLE_PINHOLE", 3},
    {1, "PINHOLE", 4},
    {2, "SIMPLE_RADIAL", 4},
    {3, "RADIAL", 5},
    {4, "OPENCV", 8},
    {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},
    {7, "FOV", 5},
    {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5},
    {10, "THIN_PRISM_FISHEYE", 12},
    {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16},
    {12, "SIMPLE_DIVISION", 4},
    {13, "DIVISION", 5},
    {14, "SIMPLE_FISHEYE", 3},
    {15, "FISHEYE", 4},
    {16, "EUCM", 6},
    {17, "EQUIRECTANGULAR", 2},
};

const CameraModelInfo* FindCameraModel(int model_id) {
  for (const auto& info : kCameraModels) {
    if (info.id == model_id) return &info;
  }
  return nullptr;
}

// Minimum bytes of one record in the binary files; used to reject absurd counts before
// anything is reserved.
constexpr size_t kMinCameraRecordBytes = 4 + 4 + 8 + 8;
constexpr size_t kMinImageRecordBytes = 4 + 7 * 8 + 4 + 1 + 8;
constexpr size_t kPoint2DRecordBytes = 8 + 8 + 8;
constexpr size_t kMinPoint3DRecordBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr size_t kTrackElementBytes = 4 + 4;

// ---------------------------------------------------------------------------------------
// Binary reading.

class BinaryReader {
 public:
  explicit BinaryReader(const std::string& path) : path_(path), bytes_(ReadFileBytes(path)) {}

  size_t Remaining() const { return bytes_.size() - offset_; }

  template <typename T>
  T Read(const char* what) {
    if (Remaining() < sizeof(T)) Fail(std::string("file is truncated (while reading ") + what + ")");
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }

  std::string ReadNullTerminated(const char* what) {
    const auto begin = bytes_.begin() + static_cast<std::ptrdiff_t>(offset_);
    const auto end = std::find(begin, bytes_.end(), uint8_t{0});
    if (end == bytes_.end()) Fail(std::string("file is truncated (while reading ") + what + ")");
    std::string text(begin, end);
    offset_ += text.size() + 1;
    return text;
  }

  // A count of records, each at least min_record_bytes long, must fit in the rest of the
  // file; otherwise the file is corrupt and the count must not be used to allocate.
  size_t ReadCount(size_t min_record_bytes, const char* what) {
    const uint64_t count = Read<uint64_t>(what);
    if (count > Remaining() / min_record_bytes) {
      Fail(std::string(what) + " is " + std::to_string(count) + ", but only " +
           std::to_string(Remaining()) + " bytes follow (file corrupt or truncated)");
    }
    return static_cast<size_t>(count);
  }

  void ExpectEnd() const {
    if (Remaining() != 0) {
      Fail(std::to_string(Remaining()) + " unexpected bytes after the last record");
    }
  }

  [[noreturn]] void Fail(const std::string& what) const {
    ThrowFileError(path_, what + " at byte offset " + std::to_string(offset_));
  }

 private:
  std::string path_;
  std::vector<uint8_t> bytes_;
  size_t offset_ = 0;
};

std::vector<SparseCamera> ReadCamerasBinary(const std::string& path) {
  BinaryReader reader(path);
  const size_t num_cameras = reader.ReadCount(kMinCameraRecordBytes, "number of cameras");
  std::vector<SparseCamera> cameras(num_cameras);
  for (SparseCamera& camera : cameras) {
    camera.camera_id = reader.Read<uint32_t>("camera id");
    camera.model_id = reader.Read<int32_t>("camera model id");
    const int num_params = CameraModelNumParams(camera.model_id);
    if (num_params < 0) {
      reader.Fail("camera " + std::to_string(camera.camera_id) + " has unknown model id " +
                  std::to_string(camera.model_id));
    }
    camera.width = reader.Read<uint64_t>("camera width");
    camera.height = reader.Read<uint64_t>("camera height");
    camera.params.resize(static_cast<size_t>(num_params));
    for (double& param : camera.params) param = reader.Read<double>("camera parameters");
  }
  reader.ExpectEnd();
  return cameras;
}

std::vector<SparseImage> ReadImagesBinary(const std::string& path) {
  BinaryReader reader(path);
  const size_t num_images = reader.ReadCount(kMinImageRecordBytes, "number of images");
  std::vector<SparseImage> images(num_images);
  for (SparseImage& image : images) {
    image.image_id = reader.Read<uint32_t>("image id");
    for (double& q : image.qvec) q = reader.Read<double>("image rotation");
    for (double& t : image.tvec) t = reader.Read<double>("image translation");
    image.camera_id = reader.Read<uint32_t>("image camera id");
    image.name = reader.ReadNullTerminated("image name");
    const size_t num_points2D = reader.ReadCount(kPoint2DRecordBytes, "number of 2D points");
    image.points2D.resize(num_points2D);
    for (SparsePoint2D& point : image.points2D) {
      point.x = reader.Read<double>("2D point");
      point.y = reader.Read<double>("2D point");
      point.point3D_id = reader.Read<uint64_t>("2D point's 3D point id");
    }
  }
  reader.ExpectEnd();
  return images;
}

std::vector<SparsePoint3D> ReadPoints3DBinary(const std::string& path) {
  BinaryReader reader(path);
  const size_t num_points = reader.ReadCount(kMinPoint3DRecordBytes, "number of 3D points");
  std::vector<SparsePoint3D> points(num_points);
  for (SparsePoint3D& point : points) {
    point.point3D_id = reader.Read<uint64_t>("3D point id");
    for (double& x : point.xyz) x = reader.Read<double>("3D point position");
    for (uint8_t& c : point.rgb) c = reader.Read<uint8_t>("3D point colour");
    point.error = reader.Read<double>("3D point error");
    const size_t track_length = reader.ReadCount(kTrackElementBytes, "track length");
    point.track.resize(track_length);
    for (SparseTrackElement& element : point.track) {
      element.image_id = reader.Read<uint32_t>("track image id");
      element.point2D_idx = reader.Read<uint32_t>("track 2D point index");
    }
  }
  reader.ExpectEnd();
  return points;
}

// ---------------------------------------------------------------------------------------
// Binary writing.

template <typename T>
void WriteBinary(std::ostream& stream, const T& value) {
  stream.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

void CheckCameraParams(const SparseCamera& camera, const std::string& path) {
  const int num_params = CameraModelNumParams(camera.model_id);
  if (num_params < 0) {
    ThrowFileError(path, "camera " + std::to_string(camera.camera_id) + " has unknown model id " +
                             std::to_string(camera.model_id));
  }
  if (camera.params.size() != static_cast<size_t>(num_params)) {
    ThrowFileError(path, "camera " + std::to_string(camera.camera_id) + " of model " +
                             CameraModelName(camera.model_id) + " needs " +
                             std::to_string(num_params) + " parameters, has " +
                             std::to_string(camera.params.size()));
  }
}

// ---------------------------------------------------------------------------------------
// Text reading.

bool ParseDouble(const std::string& token, double* value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  *value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && errno != ERANGE;
}

template <typename T>
bool ParseInteger(const std::string& token, T* value) {
  const char* begin = token.data();
  const char* end = token.data() + token.size();
  if (begin != end && *begin == '+') ++begin;
  const auto result = std::from_chars(begin, end, *value);
  return result.ec == std::errc() && result.ptr == end && begin != end;
}

struct Token {
  std::string text;
  size_t offset;  // in the line, for "rest of line" names
};

std::vector<Token> SplitWhitespace(const std::string& line) {
  std::vector<Token> tokens;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i == line.size()) break;
    const size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    tokens.push_back({line.substr(start, i - start), start});
  }
  return tokens;
}

std::string Trim(const std::string& text) {
  size_t begin = 0, end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

class TextReader {
 public:
  explicit TextReader(const std::string& path) : path_(path), file_(path) {
    if (!FileExists(path)) ThrowFileError(path, "file does not exist");
    if (!file_.is_open()) ThrowFileError(path, "cannot open file for reading");
  }

  // Next line that is neither empty nor a '#' comment, trimmed.
  bool NextDataLine(std::string* line) {
    while (NextRawLine(line)) {
      *line = Trim(*line);
      if (!line->empty() && (*line)[0] != '#') return true;
    }
    return false;
  }

  // The very next line, whatever it holds (second line of an image record).
  bool NextRawLine(std::string* line) {
    if (!std::getline(file_, *line)) return false;
    ++line_number_;
    return true;
  }

  [[noreturn]] void Fail(const std::string& what) const {
    ThrowFileError(path_, "line " + std::to_string(line_number_) + ": " + what);
  }

  double Double(const std::string& token, const char* what) const {
    double value;
    if (!ParseDouble(token, &value)) Fail(std::string("bad ") + what + " '" + token + "'");
    return value;
  }

  template <typename T>
  T Integer(const std::string& token, const char* what) const {
    T value;
    if (!ParseInteger(token, &value)) Fail(std::string("bad ") + what + " '" + token + "'");
    return value;
  }

 private:
  std::string path_;
  std::ifstream file_;
  int line_number_ = 0;
};

std::vector<SparseCamera> ReadCamerasText(const std::string& path) {
  TextReader reader(path);
  std::vector<SparseCamera> cameras;
  std::string line;
  while (reader.NextDataLine(&line)) {
    const std::vector<Token> tokens = SplitWhitespace(line);
    if (tokens.size() < 4) reader.Fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS...");
    SparseCamera camera;
    camera.camera_id = reader.Integer<uint32_t>(tokens[0].text, "camera id");
    camera.model_id = CameraModelIdFromName(tokens[1].text);
    if (camera.model_id < 0) reader.Fail("unknown camera model '" + tokens[1].text + "'");
    camera.width = reader.Integer<uint64_t>(tokens[2].text, "width");
    camera.height = reader.Integer<uint64_t>(tokens[3].text, "height");
    const size_t num_params = static_cast<size_t>(CameraModelNumParams(camera.model_id));
    if (tokens.size() - 4 != num_params) {
      reader.Fail("camera model " + tokens[1].text + " needs " + std::to_string(num_params) +
                  " parameters, found " + std::to_string(tokens.size() - 4));
    }
    for (size_t i = 0; i < num_params; ++i) {
      camera.params.push_back(reader.Double(tokens[4 + i].text, "camera parameter"));
    }
    cameras.push_back(std::move(camera));
  }
  return cameras;
}

std::vector<SparseImage> ReadImagesText(const std::string& path) {
  TextReader reader(path);
  std::vector<SparseImage> images;
  std::string line;
  while (reader.NextDataLine(&line)) {
    const std::vector<Token> tokens = SplitWhitespace(line);
    if (tokens.size() < 10) {
      reader.Fail("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    }
    SparseImage image;
    image.image_id = reader.Integer<uint32_t>(tokens[0].text, "image id");
    for (int i = 0; i < 4; ++i) image.qvec[i] = reader.Double(tokens[1 + i].text, "quaternion");
    for (int i = 0; i < 3; ++i) image.tvec[i] = reader.Double(tokens[5 + i].text, "translation");
    image.camera_id = reader.Integer<uint32_t>(tokens[8].text, "camera id");
    // The name is the rest of the line, so names with spaces survive.
    image.name = Trim(line.substr(tokens[9].offset));

    // Second line: X Y POINT3D_ID triples; may be empty or absent at the end of the file.
    std::string points_line;
    if (reader.NextRawLine(&points_line)) {
      const std::vector<Token> values = SplitWhitespace(points_line);
      if (values.size() % 3 != 0) {
        reader.Fail("2D point line of image '" + image.name +
                    "' must hold X Y POINT3D_ID triples, has " + std::to_string(values.size()) +
                    " values");
      }
      image.points2D.resize(values.size() / 3);
      for (size_t i = 0; i < image.points2D.size(); ++i) {
        SparsePoint2D& point = image.points2D[i];
        point.x = reader.Double(values[3 * i].text, "2D point x");
        point.y = reader.Double(values[3 * i + 1].text, "2D point y");
        const std::string& id = values[3 * i + 2].text;
        if (id == "-1") {
          point.point3D_id = UINT64_MAX;
        } else {
          point.point3D_id = reader.Integer<uint64_t>(id, "POINT3D_ID");
        }
      }
    }
    images.push_back(std::move(image));
  }
  return images;
}

std::vector<SparsePoint3D> ReadPoints3DText(const std::string& path) {
  TextReader reader(path);
  std::vector<SparsePoint3D> points;
  std::string line;
  while (reader.NextDataLine(&line)) {
    const std::vector<Token> tokens = SplitWhitespace(line);
    if (tokens.size() < 8 || (tokens.size() - 8) % 2 != 0) {
      reader.Fail("expected POINT3D_ID X Y Z R G B ERROR followed by IMAGE_ID POINT2D_IDX pairs");
    }
    SparsePoint3D point;
    point.point3D_id = reader.Integer<uint64_t>(tokens[0].text, "3D point id");
    for (int i = 0; i < 3; ++i) point.xyz[i] = reader.Double(tokens[1 + i].text, "coordinate");
    for (int i = 0; i < 3; ++i) point.rgb[i] = reader.Integer<uint8_t>(tokens[4 + i].text, "colour");
    point.error = reader.Double(tokens[7].text, "error");
    point.track.resize((tokens.size() - 8) / 2);
    for (size_t i = 0; i < point.track.size(); ++i) {
      point.track[i].image_id = reader.Integer<uint32_t>(tokens[8 + 2 * i].text, "track image id");
      point.track[i].point2D_idx =
          reader.Integer<uint32_t>(tokens[9 + 2 * i].text, "track 2D point index");
    }
    points.push_back(std::move(point));
  }
  return points;
}

// ---------------------------------------------------------------------------------------
// Consistency between the three files (what later stages rely on).

void ValidateModel(const SparseModel& model, const std::string& cameras_path,
                   const std::string& images_path, const std::string& points_path) {
  std::unordered_set<uint32_t> camera_ids;
  for (const SparseCamera& camera : model.cameras) {
    if (!camera_ids.insert(camera.camera_id).second) {
      ThrowFileError(cameras_path, "camera id " + std::to_string(camera.camera_id) +
                                       " appears more than once");
    }
  }
  std::unordered_set<uint32_t> image_ids;
  std::unordered_set<std::string> image_names;
  for (const SparseImage& image : model.images) {
    if (!image_ids.insert(image.image_id).second) {
      ThrowFileError(images_path,
                     "image id " + std::to_string(image.image_id) + " appears more than once");
    }
    if (image.name.empty()) {
      ThrowFileError(images_path, "image " + std::to_string(image.image_id) + " has no name");
    }
    if (!image_names.insert(image.name).second) {
      ThrowFileError(images_path, "image name '" + image.name + "' appears more than once");
    }
    if (camera_ids.count(image.camera_id) == 0) {
      ThrowFileError(images_path, "image '" + image.name + "' refers to camera id " +
                                      std::to_string(image.camera_id) + ", which is not in " +
                                      cameras_path);
    }
  }
  std::unordered_map<uint32_t, size_t> num_points2D;  // image id -> its 2D points
  for (const SparseImage& image : model.images) num_points2D[image.image_id] = image.points2D.size();
  size_t bad_indices = 0;
  std::string first_bad;
  std::unordered_set<uint64_t> point_ids;
  for (const SparsePoint3D& point : model.points) {
    if (!point_ids.insert(point.point3D_id).second) {
      ThrowFileError(points_path, "3D point id " + std::to_string(point.point3D_id) +
                                      " appears more than once");
    }
    for (const SparseTrackElement& element : point.track) {
      if (image_ids.count(element.image_id) == 0) {
        ThrowFileError(points_path, "3D point " + std::to_string(point.point3D_id) +
                                        " is observed by image id " +
                                        std::to_string(element.image_id) + ", which is not in " +
                                        images_path);
      }
      // The dense stages use only the track's image ids (as COLMAP's mvs::Model), so an
      // index past the image's 2D points is reported, not fatal.
      if (element.point2D_idx >= num_points2D[element.image_id] && bad_indices++ == 0) {
        first_bad = "3D point " + std::to_string(point.point3D_id) + " names 2D point " +
                    std::to_string(element.point2D_idx) + " of image id " + std::to_string(element.image_id) +
                    ", which has " + std::to_string(num_points2D[element.image_id]);
      }
    }
  }
  if (bad_indices > 0) {
    LogWarning(points_path + ": " + std::to_string(bad_indices) +
               " track entries name a 2D point their image does not have (first: " + first_bad +
               "); the model may be damaged or mixed from two reconstructions");
  }
}

void RequireDirectory(const std::string& dir) {
  if (!DirectoryExists(dir)) ThrowFileError(dir, "sparse model folder does not exist");
}

}  // namespace

std::string CameraModelName(int model_id) {
  const CameraModelInfo* info = FindCameraModel(model_id);
  return info ? info->name : "UNKNOWN";
}

int CameraModelIdFromName(const std::string& name) {
  for (const auto& info : kCameraModels) {
    if (name == info.name) return info.id;
  }
  return -1;
}

int CameraModelNumParams(int model_id) {
  const CameraModelInfo* info = FindCameraModel(model_id);
  return info ? info->num_params : -1;
}

int SparseModel::FindCamera(uint32_t camera_id) const {
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (cameras[i].camera_id == camera_id) return static_cast<int>(i);
  }
  return -1;
}

int SparseModel::FindImageByName(const std::string& name) const {
  for (size_t i = 0; i < images.size(); ++i) {
    if (images[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int SparseModel::FindImageById(uint32_t image_id) const {
  for (size_t i = 0; i < images.size(); ++i) {
    if (images[i].image_id == image_id) return static_cast<int>(i);
  }
  return -1;
}

bool HasBinarySparseModel(const std::string& dir) {
  return FileExists(JoinPaths(dir, "cameras.bin")) && FileExists(JoinPaths(dir, "images.bin")) &&
         FileExists(JoinPaths(dir, "points3D.bin"));
}

std::string SparseModelFilePath(const std::string& dir, const std::string& stem) {
  return JoinPaths(dir, stem + (HasBinarySparseModel(dir) ? ".bin" : ".txt"));
}

SparseModel ReadSparseModel(const std::string& dir) {
  RequireDirectory(dir);
  if (HasBinarySparseModel(dir)) return ReadSparseModelBinary(dir);
  const bool any_text = FileExists(JoinPaths(dir, "cameras.txt")) ||
                        FileExists(JoinPaths(dir, "images.txt")) ||
                        FileExists(JoinPaths(dir, "points3D.txt"));
  const bool any_binary = FileExists(JoinPaths(dir, "cameras.bin")) ||
                          FileExists(JoinPaths(dir, "images.bin")) ||
                          FileExists(JoinPaths(dir, "points3D.bin"));
  if (!any_text && !any_binary) {
    ThrowFileError(dir, "no sparse model here (expected cameras, images and points3D as .bin "
                        "or .txt)");
  }
  // An incomplete binary model without text files: report the missing .bin file.
  if (!any_text) return ReadSparseModelBinary(dir);
  return ReadSparseModelText(dir);
}

SparseModel ReadSparseModelBinary(const std::string& dir) {
  RequireDirectory(dir);
  const std::string cameras_path = JoinPaths(dir, "cameras.bin");
  const std::string images_path = JoinPaths(dir, "images.bin");
  const std::string points_path = JoinPaths(dir, "points3D.bin");
  SparseModel model;
  model.cameras = ReadCamerasBinary(cameras_path);
  model.images = ReadImagesBinary(images_path);
  model.points = ReadPoints3DBinary(points_path);
  ValidateModel(model, cameras_path, images_path, points_path);
  return model;
}

SparseModel ReadSparseModelText(const std::string& dir) {
  RequireDirectory(dir);
  const std::string cameras_path = JoinPaths(dir, "cameras.txt");
  const std::string images_path = JoinPaths(dir, "images.txt");
  const std::string points_path = JoinPaths(dir, "points3D.txt");
  SparseModel model;
  model.cameras = ReadCamerasText(cameras_path);
  model.images = ReadImagesText(images_path);
  model.points = ReadPoints3DText(points_path);
  ValidateModel(model, cameras_path, images_path, points_path);
  return model;
}

void WriteSparseModelBinary(const SparseModel& model, const std::string& dir) {
  const std::string cameras_path = JoinPaths(dir, "cameras.bin");
  for (const SparseCamera& camera : model.cameras) CheckCameraParams(camera, cameras_path);
  WriteFileAtomically(cameras_path, [&](std::ostream& out) {
    WriteBinary<uint64_t>(out, model.cameras.size());
    for (const SparseCamera& camera : model.cameras) {
      WriteBinary<uint32_t>(out, camera.camera_id);
      WriteBinary<int32_t>(out, camera.model_id);
      WriteBinary<uint64_t>(out, camera.width);
      WriteBinary<uint64_t>(out, camera.height);
      for (double param : camera.params) WriteBinary(out, param);
    }
  });
  WriteFileAtomically(JoinPaths(dir, "images.bin"), [&](std::ostream& out) {
    WriteBinary<uint64_t>(out, model.images.size());
    for (const SparseImage& image : model.images) {
      WriteBinary<uint32_t>(out, image.image_id);
      for (double q : image.qvec) WriteBinary(out, q);
      for (double t : image.tvec) WriteBinary(out, t);
      WriteBinary<uint32_t>(out, image.camera_id);
      out.write(image.name.c_str(), static_cast<std::streamsize>(image.name.size() + 1));
      WriteBinary<uint64_t>(out, image.points2D.size());
      for (const SparsePoint2D& point : image.points2D) {
        WriteBinary(out, point.x);
        WriteBinary(out, point.y);
        WriteBinary<uint64_t>(out, point.point3D_id);
      }
    }
  });
  WriteFileAtomically(JoinPaths(dir, "points3D.bin"), [&](std::ostream& out) {
    WriteBinary<uint64_t>(out, model.points.size());
    for (const SparsePoint3D& point : model.points) {
      WriteBinary<uint64_t>(out, point.point3D_id);
      for (double x : point.xyz) WriteBinary(out, x);
      for (uint8_t c : point.rgb) WriteBinary(out, c);
      WriteBinary(out, point.error);
      WriteBinary<uint64_t>(out, point.track.size());
      for (const SparseTrackElement& element : point.track) {
        WriteBinary<uint32_t>(out, element.image_id);
        WriteBinary<uint32_t>(out, element.point2D_idx);
      }
    }
  });
}

void WriteSparseModelText(const SparseModel& model, const std::string& dir) {
  const std::string cameras_path = JoinPaths(dir, "cameras.txt");
  for (const SparseCamera& camera : model.cameras) CheckCameraParams(camera, cameras_path);
  for (const SparseImage& image : model.images) {
    // The text layout cannot hold names that start/end with spaces or span lines.
    if (image.name.empty() || image.name != Trim(image.name) ||
        image.name.find('\n') != std::string::npos) {
      ThrowFileError(JoinPaths(dir, "images.txt"),
                     "image name '" + image.name + "' cannot be written as text");
    }
  }
  // 17 significant digits make every double round-trip exactly.
  const auto set_precision = [](std::ostream& out) {
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
  };
  WriteFileAtomically(cameras_path, [&](std::ostream& out) {
    set_precision(out);
    out << "# Camera list with one line of data per camera:\n"
        << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        << "# Number of cameras: " << model.cameras.size() << "\n";
    for (const SparseCamera& camera : model.cameras) {
      out << camera.camera_id << " " << CameraModelName(camera.model_id) << " " << camera.width
          << " " << camera.height;
      for (double param : camera.params) out << " " << param;
      out << "\n";
    }
  });
  WriteFileAtomically(JoinPaths(dir, "images.txt"), [&](std::ostream& out) {
    set_precision(out);
    out << "# Image list with two lines of data per image:\n"
        << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
        << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
        << "# Number of images: " << model.images.size() << "\n";
    for (const SparseImage& image : model.images) {
      out << image.image_id;
      for (double q : image.qvec) out << " " << q;
      for (double t : image.tvec) out << " " << t;
      out << " " << image.camera_id << " " << image.name << "\n";
      for (size_t i = 0; i < image.points2D.size(); ++i) {
        const SparsePoint2D& point = image.points2D[i];
        if (i > 0) out << " ";
        out << point.x << " " << point.y << " ";
        if (point.point3D_id == UINT64_MAX) {
          out << "-1";
        } else {
          out << point.point3D_id;
        }
      }
      out << "\n";
    }
  });
  WriteFileAtomically(JoinPaths(dir, "points3D.txt"), [&](std::ostream& out) {
    set_precision(out);
    out << "# 3D point list with one line of data per point:\n"
        << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
        << "# Number of points: " << model.points.size() << "\n";
    for (const SparsePoint3D& point : model.points) {
      out << point.point3D_id;
      for (double x : point.xyz) out << " " << x;
      for (uint8_t c : point.rgb) out << " " << static_cast<int>(c);
      out << " " << point.error;
      for (const SparseTrackElement& element : point.track) {
        out << " " << element.image_id << " " << element.point2D_idx;
      }
      out << "\n";
    }
  });
}

void QuaternionToRotationMatrix(const double q[4], double R[9]) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(norm > 0) || !std::isfinite(norm)) {
    // Not a rotation; identity keeps callers defined (readers validate quaternions).
    const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::copy(identity, identity + 9, R);
    return;
  }
  const double w = q[0] / norm, x = q[1] / norm, y = q[2] / norm, z = q[3] / norm;
  R[0] = 1 - 2 * (y * y + z * z);
  R[1] = 2 * (x * y - w * z);
  R[2] = 2 * (x * z + w * y);
  R[3] = 2 * (x * y + w * z);
  R[4] = 1 - 2 * (x * x + z * z);
  R[5] = 2 * (y * z - w * x);
  R[6] = 2 * (x * z - w * y);
  R[7] = 2 * (y * z + w * x);
  R[8] = 1 - 2 * (x * x + y * y);
}

void RotationMatrixToQuaternion(const double R[9], double q[4]) {
  // Shepperd's method: divide by the largest of the four candidates for stability.
  const double trace = R[0] + R[4] + R[8];
  double w, x, y, z;
  if (trace > 0) {
    const double s = 2 * std::sqrt(1 + trace);
    w = s / 4;
    x = (R[7] - R[5]) / s;
    y = (R[2] - R[6]) / s;
    z = (R[3] - R[1]) / s;
  } else if (R[0] > R[4] && R[0] > R[8]) {
    const double s = 2 * std::sqrt(1 + R[0] - R[4] - R[8]);
    w = (R[7] - R[5]) / s;
    x = s / 4;
    y = (R[1] + R[3]) / s;
    z = (R[2] + R[6]) / s;
  } else if (R[4] > R[8]) {
    const double s = 2 * std::sqrt(1 + R[4] - R[0] - R[8]);
    w = (R[2] - R[6]) / s;
    x = (R[1] + R[3]) / s;
    y = s / 4;
    z = (R[5] + R[7]) / s;
  } else {
    const double s = 2 * std::sqrt(1 + R[8] - R[0] - R[4]);
    w = (R[3] - R[1]) / s;
    x = (R[2] + R[6]) / s;
    y = (R[5] + R[7]) / s;
    z = s / 4;
  }
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  const double sign = w < 0 ? -1.0 : 1.0;
  q[0] = sign * w / norm;
  q[1] = sign * x / norm;
  q[2] = sign * y / norm;
  q[3] = sign * z / norm;
}

}  // namespace mpmvs
