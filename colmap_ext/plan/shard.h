#pragma once
// Which reference images one process of a split run computes (--MPMVS.shard i/n,
// --MPMVS.image_list_path). The rule, the same in every process of a run:
//   1. the image list (if given) keeps the references it names, in patch-match.cfg order;
//   2. the shards balance the work: each image costs width x height x number of sources;
//      longest first (ties: earlier in patch-match.cfg), each goes to the shard with the
//      least work so far (ties: the lower shard index);
//   3. a shard runs its images in patch-match.cfg order.
// Results never depend on the split (stages are Jacobi and every random draw is keyed by
// the image index, not the order), so the rule only decides who waits for whom.
#include <string>
#include <vector>

#include "colmap_ext/io/dense_workspace.h"
#include "colmap_ext/plan/reference_problems.h"

namespace mpmvs {

struct ShardSpec {
  int index = 0;  // 0-based
  int count = 1;
  bool All() const { return count == 1; }
};

// "i/n" with 0 <= i < n; "" = 0/1. Throws Error naming --MPMVS.shard otherwise.
ShardSpec ParseShard(const std::string& text);

// Image names, one per line (COLMAP's image list format; blank lines and '#' comments
// ignored, surrounding blanks trimmed). Throws Error naming the file when unreadable.
std::vector<std::string> ReadImageList(const std::string& path);

// Work of one reference image: pixels x sources.
double ReferenceCost(const DenseWorkspace& workspace, const ReferenceProblem& problem);

// Positions in problems of the images of shard `shard` after restricting to image_names
// (empty: all). Throws Error naming a listed image that is not a reference of the
// workspace; a listed image that cannot run (no sources, no depth range) is only warned about.
std::vector<size_t> SelectShard(const DenseWorkspace& workspace, const std::vector<ReferenceProblem>& problems,
                                const std::vector<std::string>& image_names, const ShardSpec& shard);

// The same for every shard at once: result[k] = SelectShard(..., {k, count}).
std::vector<std::vector<size_t>> SplitIntoShards(const DenseWorkspace& workspace,
                                                 const std::vector<ReferenceProblem>& problems,
                                                 const std::vector<std::string>& image_names, int count);

}  // namespace mpmvs
