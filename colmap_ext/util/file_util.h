#pragma once
// File-system helpers. Every output file is written to a temporary sibling and renamed,
// so a crash never leaves a half-written file and an earlier file stays intact until the
// new one is complete.
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace mpmvs {

// Calls write(stream) on "path.tmp.<pid>.<n>" (n: per-process counter, so threads never
// share a temporary) and renames it to path. Creates no directories.
// On any failure the temporary is removed and Error is thrown naming path.
void WriteFileAtomically(const std::string& path,
                         const std::function<void(std::ostream&)>& write);

// Same for writers that take a file name (e.g. COLMAP's Mat::Write): write(tmp_path) must
// create the file; it is then renamed to path. Any exception from write is rethrown as
// Error naming path, and the temporary is removed.
void WriteFileViaTemporaryPath(const std::string& path,
                               const std::function<void(const std::string& tmp_path)>& write);

// Whole file as bytes; Error naming the path when missing or unreadable.
std::vector<uint8_t> ReadFileBytes(const std::string& path);

bool FileExists(const std::string& path);
bool DirectoryExists(const std::string& path);
// Total size of the regular files under path (0 when it does not exist; files that vanish
// while it counts are skipped).
uint64_t DirectoryBytes(const std::string& path);
// Creates the directory and its parents (no error if it exists).
void CreateDirectories(const std::string& path);
// a + "/" + b, without doubling slashes.
std::string JoinPaths(const std::string& a, const std::string& b);
// Directory part of a path ("" if none).
std::string ParentPath(const std::string& path);

}  // namespace mpmvs
