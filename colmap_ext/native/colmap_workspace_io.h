#pragma once
// WorkspaceIo on COLMAP's own classes (COLMAP 3.12.x - 4.1.x, built from source): the sparse
// model through colmap::Reconstruction / mvs::Workspace / mvs::Model, images through
// colmap::Bitmap (grey, mvs::Image::Downsize and Bitmap::Rescale for max_image_size), maps
// through mvs::DepthMap / mvs::NormalMap / mvs::ConsistencyGraph::Write. Only this folder
// includes COLMAP headers; this header does not, so callers need no COLMAP include paths.
#include <memory>

#include "colmap_ext/io/workspace_io.h"

namespace mpmvs {

std::unique_ptr<WorkspaceIo> MakeColmapWorkspaceIo();

}  // namespace mpmvs
