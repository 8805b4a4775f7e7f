// Work split over threads: every piece runs once, and errors reach the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "colmap_ext/util/thread_range.h"

namespace mpmvs {
namespace {

TEST(ThreadRange, RangeCoversEveryIndexOnce) {
  for (int threads : {1, 2, 3, 7}) {
    std::vector<std::atomic<int>> hits(100);
    RunRangeInThreads(100, threads, [&](int begin, int end) {
      for (int i = begin; i < end; ++i) ++hits[i];
    });
    for (int i = 0; i < 100; ++i) EXPECT_EQ(hits[i], 1) << "index " << i << ", " << threads << " threads";
  }
}

// Both pieces run, the side piece on another thread; the caller's error wins over the side's,
// and the side's is not lost when the caller's piece succeeds.
TEST(ThreadRange, RunBesideRunsBothAndRethrowsTheirErrors) {
  const std::thread::id caller = std::this_thread::get_id();
  std::thread::id side_thread, here_thread;
  RunBeside([&] { side_thread = std::this_thread::get_id(); }, [&] { here_thread = std::this_thread::get_id(); });
  EXPECT_EQ(here_thread, caller);
  EXPECT_NE(side_thread, std::thread::id());
  EXPECT_NE(side_thread, caller);

  bool side_ran = false;
  try {
    RunBeside([&] { side_ran = true; }, [] { throw std::runtime_error("here"); });
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "here");
  }
  EXPECT_TRUE(side_ran);

  bool here_ran = false;
  try {
    RunBeside([] { throw std::runtime_error("side"); }, [&] { here_ran = true; });
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "side");
  }
  EXPECT_TRUE(here_ran);

  try {
    RunBeside([] { throw std::runtime_error("side"); }, [] { throw std::runtime_error("here"); });
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "here");
  }
}

}  // namespace
}  // namespace mpmvs
