#pragma once
// The time left for a whole run (not only the stage under way): each (reference image,
// stage) is work of its pixels times its iterations (one for the depth check), and the rate
// is the run's elapsed time per unit of work computed so far. Images resumed or skipped
// count as done without time.
#include <chrono>
#include <string>

namespace mpmvs {

class RunEta {
 public:
  explicit RunEta(double total_units);

  // Work units of one image in a stage; iterations: full-resolution ones, a half-resolution
  // one counting a quarter (at least one in all).
  static double Units(int width, int height, double iterations);

  // One (image, stage) handled; computed: its work took time (else resumed or skipped).
  void Done(double units, bool computed);
  // Seconds left; negative until some work was computed.
  double SecondsLeft() const;

 private:
  double total_units_;
  double done_units_ = 0;
  double computed_units_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace mpmvs
