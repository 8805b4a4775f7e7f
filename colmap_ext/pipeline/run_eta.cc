#include "colmap_ext/pipeline/run_eta.h"

#include <algorithm>

namespace mpmvs {

RunEta::RunEta(double total_units) : total_units_(total_units), start_(std::chrono::steady_clock::now()) {}

double RunEta::Units(int width, int height, double iterations) {
  return static_cast<double>(width) * height * std::max(1.0, iterations);
}

void RunEta::Done(double units, bool computed) {
  done_units_ += units;
  if (computed) computed_units_ += units;
}

double RunEta::SecondsLeft() const {
  if (computed_units_ <= 0) return -1;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return elapsed / computed_units_ * std::max(0.0, total_units_ - done_units_);
}

}  // namespace mpmvs
