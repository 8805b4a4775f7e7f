#include "colmap_ext/util/thread_range.h"

#include <algorithm>
#include <exception>
#include <system_error>
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

void RunBeside(const std::function<void()>& side, const std::function<void()>& here) {
  std::exception_ptr side_error;
  auto run_side = [&] {
    try {
      side();
    } catch (...) {
      side_error = std::current_exception();
    }
  };
  std::thread thread;
  try {
    thread = std::thread(run_side);
  } catch (const std::system_error&) {
    run_side();
  }
  try {
    here();
  } catch (...) {
    if (thread.joinable()) thread.join();
    throw;
  }
  if (thread.joinable()) thread.join();
  if (side_error) std::rethrow_exception(side_error);
}

}  // namespace mpmvs
