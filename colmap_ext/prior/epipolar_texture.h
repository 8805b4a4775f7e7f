#pragma once
// Windows that no source view can place in depth: their intensity does not change along
// any source's epipolar line (kernels/DESIGN.md 29). A straight edge parallel to the
// baseline (a ceiling's edge against the far wall, seen by cameras that move sideways) is
// texture, yet every plane through the edge's 3-D line matches it in every view.
#include <cstdint>
#include <vector>

#include "kernels/camera.h"
#include "kernels/ncc.h"

namespace mpmvs {

// 1 where candidate[i] is set and, for every source, the variance over the window's
// samples of the intensity difference between the points one pixel before and after the
// sample along that source's epipolar line through the pixel is at most max_ratio times
// the variance such a difference has from the image's noise alone (2 * noise_variance
// along an image axis, less on slanted lines, where bilinear samples average pixels). The
// mean difference is taken out: a linear shading ramp shifts no NCC. Samples whose points
// leave the image do not count; a window with fewer than half its samples left is not
// blind. 0 elsewhere. A source whose epipolar line through a pixel is undefined (the pixel
// at its epipole) does not see the pixel's window either way.
std::vector<uint8_t> EpipolarBlindMask(const kernels::ImageView& ref, const kernels::Camera& ref_camera,
                                       const std::vector<kernels::Camera>& sources,
                                       const kernels::WindowSpec& window, float noise_variance,
                                       float max_ratio, const std::vector<uint8_t>& candidate,
                                       int num_threads);

}  // namespace mpmvs
