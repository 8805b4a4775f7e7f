#pragma once
// Splits an index range over plain std::threads for embarrassingly parallel loops whose
// results must not depend on the split (each index writes only its own outputs), and runs
// two independent pieces of work side by side.
#include <functional>

namespace mpmvs {

// Runs body(begin, end) over [0, n) in contiguous chunks on up to num_threads threads
// (-1 = all hardware threads, 1 = the calling thread only).
void RunRangeInThreads(int n, int num_threads,
                       const std::function<void(int begin, int end)>& body);

// Runs side on a second thread while here runs on the calling thread, and returns once both
// are done; an exception of here, else of side, is rethrown then. Without a thread to spare,
// side runs first, then here.
void RunBeside(const std::function<void()>& side, const std::function<void()>& here);

}  // namespace mpmvs
