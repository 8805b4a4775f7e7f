#include "colmap_ext/util/file_util.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "colmap_ext/util/error.h"

namespace fs = std::filesystem;

namespace mpmvs {
namespace {

// pid + a per-process counter: unique across processes and across threads of one process.
std::string TemporarySibling(const std::string& path) {
  static std::atomic<unsigned long> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

void RemoveQuietly(const std::string& path) {
  std::error_code ec;
  fs::remove(path, ec);
}

}  // namespace

void WriteFileViaTemporaryPath(const std::string& path,
                               const std::function<void(const std::string& tmp_path)>& write) {
  const std::string tmp_path = TemporarySibling(path);
  try {
    write(tmp_path);
    std::error_code ec;
    if (!fs::is_regular_file(tmp_path, ec)) ThrowFileError(path, "the writer created no file");
    fs::rename(tmp_path, path, ec);
    if (ec) ThrowFileError(path, "cannot rename the temporary file into place (" + ec.message() + ")");
  } catch (const Error&) {
    RemoveQuietly(tmp_path);
    throw;
  } catch (const std::exception& e) {
    RemoveQuietly(tmp_path);
    ThrowFileError(path, std::string("write failed: ") + e.what());
  } catch (...) {
    RemoveQuietly(tmp_path);
    throw;
  }
}

void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write) {
  WriteFileViaTemporaryPath(path, [&](const std::string& tmp_path) {
    std::ofstream file(tmp_path, std::ios::binary | std::ios::trunc);
    if (!file.is_open()) {
      ThrowFileError(path, std::string("cannot create file (") + std::strerror(errno) + ")");
    }
    write(file);
    file.flush();
    if (!file.good()) ThrowFileError(path, "write failed (disk full?)");
    file.close();
    if (file.fail()) ThrowFileError(path, "write failed when closing the file");
  });
}

std::vector<uint8_t> ReadFileBytes(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    ThrowFileError(path, fs::exists(path, ec) ? "not a regular file" : "file does not exist");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file.is_open()) ThrowFileError(path, "cannot open file for reading");
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) ThrowFileError(path, "cannot determine the file size");
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (size > 0 && !file.read(reinterpret_cast<char*>(bytes.data()),
                             static_cast<std::streamsize>(size))) {
    ThrowFileError(path, "read failed");
  }
  return bytes;
}

bool FileExists(const std::string& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

bool DirectoryExists(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec);
}

void CreateDirectories(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !DirectoryExists(path)) {
    ThrowFileError(path, "cannot create directory (" + ec.message() + ")");
  }
}

std::string JoinPaths(const std::string& a, const std::string& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  const bool a_slash = a.back() == '/';
  const bool b_slash = b.front() == '/';
  if (a_slash && b_slash) return a + b.substr(1);
  if (a_slash || b_slash) return a + b;
  return a + "/" + b;
}

std::string ParentPath(const std::string& path) {
  return fs::path(path).parent_path().string();
}

uint64_t DirectoryBytes(const std::string& path) {
  namespace fs = std::filesystem;
  uint64_t bytes = 0;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code size_error;
    if (it->is_regular_file(size_error)) {
      const uintmax_t size = it->file_size(size_error);
      if (!size_error) bytes += size;
    }
  }
  return bytes;
}

}  // namespace mpmvs
