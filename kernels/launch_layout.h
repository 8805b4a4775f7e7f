#pragma once
// Which pixel each backend thread works on, and the layout of the per-pixel state buffers.
// Shared by the CPU backend (row loops), the CUDA backend (grid/block -> pixel) and the
// tests, so the checkerboard split and the buffer sizes exist once. No CUDA types here:
// the host side must compile without the CUDA headers.
#include <stddef.h>

#include "kernels/common.h"

namespace mpmvs {
namespace kernels {

// ---------------------------------------------------------------------------------------
// Checkerboard: pixel (u, v) has colour (u + v) % 2; a pass updates one colour, whose
// pixels only read neighbours of the other colour (propagation_pattern.h).

MPMVS_HD MPMVS_FORCE_INLINE int PixelColor(int u, int v) { return (u + v) & 1; }
// First column of colour `color` in row v; the colour's pixels are every second column.
MPMVS_HD MPMVS_FORCE_INLINE int CheckerboardRowBegin(int v, int color) { return (v + color) & 1; }

struct Dim2 {
  int x = 1;
  int y = 1;
};

// A 2D launch: grid of blocks of threads (the CUDA backend turns it into dim3s).
struct LaunchLayout {
  Dim2 grid;
  Dim2 block;
};

// Blocks of 16x8 = 128 threads, whole warps (the NCC counter is reduced per warp). The
// update kernel needs ~160 registers per thread: small blocks pack more warps per SM.
constexpr int kBlockSideX = 16;
constexpr int kBlockSideY = 8;

inline int CeilDiv(int a, int b) { return (a + b - 1) / b; }

// One thread per pixel (initialisation pass).
inline LaunchLayout ImageLaunchLayout(int width, int height) {
  LaunchLayout l;
  l.block = Dim2{kBlockSideX, kBlockSideY};
  l.grid = Dim2{MaxI(1, CeilDiv(width, kBlockSideX)), MaxI(1, CeilDiv(height, kBlockSideY))};
  return l;
}

// One thread per pixel of one colour: thread column k of row v is pixel
// u = 2k + CheckerboardRowBegin(v, color). Rows hold at most ceil(W/2) pixels of a colour,
// so both colours use the same layout; the threads past the row end do nothing.
inline LaunchLayout CheckerboardLaunchLayout(int width, int height) {
  LaunchLayout l;
  l.block = Dim2{kBlockSideX, kBlockSideY};
  l.grid =
      Dim2{MaxI(1, CeilDiv((width + 1) / 2, kBlockSideX)), MaxI(1, CeilDiv(height, kBlockSideY))};
  return l;
}

// Pixel of thread `thread` in block `block` (blocks of size `block_dim`) of an
// ImageLaunchLayout; false when the thread is outside the image.
MPMVS_HD MPMVS_FORCE_INLINE bool ImageThreadPixel(int width, int height, Dim2 block, Dim2 block_dim,
                                                  Dim2 thread, int* u, int* v) {
  *u = block.x * block_dim.x + thread.x;
  *v = block.y * block_dim.y + thread.y;
  return *u < width && *v < height;
}

// Pixel of colour `color` handled by a thread of a CheckerboardLaunchLayout; false when the
// thread has no pixel (past the end of the row or below the image).
MPMVS_HD MPMVS_FORCE_INLINE bool CheckerboardThreadPixel(int width, int height, int color,
                                                         Dim2 block, Dim2 block_dim, Dim2 thread,
                                                         int* u, int* v) {
  *v = block.y * block_dim.y + thread.y;
  *u = 2 * (block.x * block_dim.x + thread.x) + CheckerboardRowBegin(*v, color);
  return *u < width && *v < height;
}

// ---------------------------------------------------------------------------------------
// Per-pixel state buffers (PixelState, PatchMatchResult): pixel (u, v) is entry v * W + u;
// planes are interleaved, 4 floats (nx, ny, nz, d) per pixel, as LoadPlane/StorePlane
// (patch_match_pixel.h) index them.

constexpr int kPlaneFloatsPerPixel = 4;

struct StateLayout {
  size_t num_pixels = 0;
  size_t plane_floats = 0;  // plane (and prior plane / init plane) entries
  size_t cost_floats = 0;   // cost, photo_cost, geo_error (and init cost) entries
  size_t mask_words = 0;    // view_mask entries
  size_t label_bytes = 0;   // prior label entries
  size_t skip_bytes = 0;    // PixelState::skips_left entries
};

inline StateLayout MakeStateLayout(int width, int height) {
  StateLayout l;
  l.num_pixels =
      width > 0 && height > 0 ? static_cast<size_t>(width) * static_cast<size_t>(height) : 0;
  l.plane_floats = kPlaneFloatsPerPixel * l.num_pixels;
  l.cost_floats = l.num_pixels;
  l.mask_words = l.num_pixels;
  l.label_bytes = l.num_pixels;
  l.skip_bytes = l.num_pixels;
  return l;
}

}  // namespace kernels
}  // namespace mpmvs
