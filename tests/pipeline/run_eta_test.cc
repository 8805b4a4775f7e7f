// The whole run's time left (pipeline/run_eta.h).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "colmap_ext/pipeline/run_eta.h"

namespace mpmvs {
namespace {

TEST(RunEta, ScalesTheComputedRateToTheWorkLeftAndSkippedWorkTakesNoTime) {
  const double image = RunEta::Units(100, 50, 2);
  EXPECT_EQ(RunEta::Units(100, 50, 0), RunEta::Units(100, 50, 1));  // the depth check: one unit each
  RunEta eta(4 * image);
  EXPECT_LT(eta.SecondsLeft(), 0);  // nothing computed yet: no rate
  eta.Done(image, false);           // resumed
  EXPECT_LT(eta.SecondsLeft(), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  eta.Done(image, true);
  // About 0.1 s per image computed, two images left.
  EXPECT_GT(eta.SecondsLeft(), 0.15);
  EXPECT_LT(eta.SecondsLeft(), 1.0);
  eta.Done(2 * image, true);
  EXPECT_EQ(eta.SecondsLeft(), 0);
}

}  // namespace
}  // namespace mpmvs
