#pragma once
// Point clouds in PLY files: COLMAP's fused.ply layout (binary little endian; float x,y,z,
// float nx,ny,nz, uchar red,green,blue) for writing; reading accepts ascii and binary
// (either endianness), any scalar property types, properties in any order, extra
// properties and elements after the vertices.
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {

struct PlyPoint {
  float x = 0, y = 0, z = 0;
  float nx = 0, ny = 0, nz = 0;
  uint8_t r = 0, g = 0, b = 0;
};

struct PlyPointCloud {
  std::vector<PlyPoint> points;
  bool has_normals = false;
  bool has_colors = false;
};

// Throws Error naming the path for a missing file, a malformed header, missing x/y/z, list
// properties inside the vertex element, or a body shorter than the header promises.
PlyPointCloud ReadPlyPointCloud(const std::string& path);
// Atomic (temporary + rename). Normals/colours are written when the flags say so.
void WritePlyPointCloud(const std::string& path, const PlyPointCloud& cloud);

}  // namespace mpmvs
