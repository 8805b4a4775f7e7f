#pragma once
// Splits an index range over plain std::threads for embarrassingly parallel loops whose
// results must not depend on the split (each index writes only its own outputs).
#include <functional>

namespace mpmvs {

// Runs body(begin, end) over [0, n) in contiguous chunks on up to num_threads threads
// (-1 = all hardware threads, 1 = the calling thread only).
void RunRangeInThreads(int n, int num_threads,
                       const std::function<void(int begin, int end)>& body);

}  // namespace mpmvs
