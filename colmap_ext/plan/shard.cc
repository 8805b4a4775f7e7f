#include "colmap_ext/plan/shard.h"

#include <algorithm>
#include <fstream>
#include <set>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace mpmvs {
namespace {

std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

bool ParseNonNegative(const std::string& text, int* value) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return false;
  *value = std::stoi(text);
  return true;
}

// Positions of the references that the list keeps (all when it is empty).
std::vector<size_t> ListedPositions(const DenseWorkspace& workspace, const std::vector<ReferenceProblem>& problems,
                                    const std::vector<std::string>& image_names) {
  std::vector<size_t> positions;
  if (image_names.empty()) {
    for (size_t i = 0; i < problems.size(); ++i) positions.push_back(i);
    return positions;
  }
  const std::set<std::string> wanted(image_names.begin(), image_names.end());
  std::set<std::string> found;
  for (size_t i = 0; i < problems.size(); ++i) {
    const std::string& name = workspace.views[problems[i].ref].name;
    if (wanted.count(name)) {
      positions.push_back(i);
      found.insert(name);
    }
  }
  for (const std::string& name : wanted) {
    if (found.count(name)) continue;
    const bool is_view = std::any_of(workspace.views.begin(), workspace.views.end(),
                                     [&](const DenseView& v) { return v.name == name; });
    if (!is_view) throw Error("--MPMVS.image_list_path names " + name + ", which is not an image of the workspace");
    LogWarning("--MPMVS.image_list_path: " + name + " cannot run (see the warnings above); left out");
  }
  return positions;
}

}  // namespace

ShardSpec ParseShard(const std::string& text) {
  ShardSpec shard;
  if (text.empty()) return shard;
  const size_t slash = text.find('/');
  if (slash == std::string::npos || !ParseNonNegative(text.substr(0, slash), &shard.index) ||
      !ParseNonNegative(text.substr(slash + 1), &shard.count) || shard.count < 1 || shard.index >= shard.count) {
    throw Error("--MPMVS.shard = " + text + " is invalid: must be i/n with 0 <= i < n (e.g. 0/4)");
  }
  return shard;
}

std::vector<std::string> ReadImageList(const std::string& path) {
  std::ifstream in(path);
  if (!in) ThrowFileError(path, "cannot read the image list");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    line = Trim(line);
    if (!line.empty() && line[0] != '#') names.push_back(line);
  }
  return names;
}

double ReferenceCost(const DenseWorkspace& workspace, const ReferenceProblem& problem) {
  const DenseView& v = workspace.views[problem.ref];
  return static_cast<double>(v.width) * v.height * static_cast<double>(problem.src.size());
}

std::vector<std::vector<size_t>> SplitIntoShards(const DenseWorkspace& workspace,
                                                 const std::vector<ReferenceProblem>& problems,
                                                 const std::vector<std::string>& image_names, int count) {
  std::vector<size_t> order = ListedPositions(workspace, problems, image_names);
  std::vector<double> cost(problems.size(), 0.0);
  for (size_t i : order) cost[i] = ReferenceCost(workspace, problems[i]);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  std::vector<std::vector<size_t>> shards(std::max(count, 1));
  std::vector<double> load(shards.size(), 0.0);
  for (size_t i : order) {
    const size_t k = std::min_element(load.begin(), load.end()) - load.begin();  // first minimum
    shards[k].push_back(i);
    load[k] += cost[i];
  }
  for (auto& s : shards) std::sort(s.begin(), s.end());
  return shards;
}

std::vector<size_t> SelectShard(const DenseWorkspace& workspace, const std::vector<ReferenceProblem>& problems,
                                const std::vector<std::string>& image_names, const ShardSpec& shard) {
  return SplitIntoShards(workspace, problems, image_names, shard.count)[shard.index];
}

}  // namespace mpmvs
