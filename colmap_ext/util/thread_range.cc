#include "colmap_ext/util/thread_range.h"

#include <algorithm>
#include <thread>
#include <vector>

namespace mpmvs {

void RunRangeInThreads(int n, int num_threads,
                       const std::function<void(int begin, int end)>& body) {
  if (n <= 0) return;
  int threads = num_threads > 0
                    ? num_threads
                    : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, n);
  if (threads <= 1) {
    body(0, n);
    return;
  }
  std::vector<std::thread> workers;
  const int chunk = (n + threads - 1) / threads;
  for (int begin = 0; begin < n; begin += chunk) {
    workers.emplace_back(body, begin, std::min(n, begin + chunk));
  }
  for (std::thread& w : workers) w.join();
}

}  // namespace mpmvs
