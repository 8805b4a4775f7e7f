#pragma once
// The files a stage leaves for the user: COLMAP's depth and normal maps (and consistency
// graph) of a reference image, and the pictures of each stage in stereo/mpmvs/pictures.
#include <string>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/io/workspace_io.h"
#include "colmap_ext/plan/reference_problems.h"
#include "colmap_ext/prior/planar_prior.h"
#include "kernels/patch_match.h"

namespace mpmvs {

class StageStore;

// Writes NAME.TYPE.bin depth and normal maps (normal first: fusion aborts on a depth map
// without its normal map), the consistency graph if asked, their record (store's
// WriteMapsRecord, after removing the old one first) and their pictures if asked.
void WriteFinalMaps(WorkspaceIo* io, const StageStore& store, const DenseWorkspace& workspace,
                    const ReferenceProblem& problem,
                    const kernels::PatchMatchProblem& pm_problem, const kernels::PatchMatchResult& result,
                    const std::string& type, bool write_consistency_graph, bool write_pictures);

// Pictures of one stage's depth map and, for a prior stage, of the planar prior model.
void WriteStagePictures(const DenseWorkspace& workspace, const ReferenceProblem& problem,
                        const kernels::Camera& camera, const std::string& stage,
                        const kernels::PatchMatchResult& result, const PlanarPriorModel* prior);

}  // namespace mpmvs
