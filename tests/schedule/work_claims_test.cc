// Work claims: atomic creation, a live claim is respected, a dead holder's claim is taken
// over, release removes it (schedule/work_claims.h).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "colmap_ext/schedule/work_claims.h"
#include "colmap_ext/util/file_util.h"
#include "tests/test_util.h"

namespace mpmvs {
namespace {

TEST(WorkClaims, OneHolderAtATimeAndRelease) {
  test::TempDir tmp;
  WorkClaims a(tmp / "claims", 600);
  WorkClaims b(tmp / "claims", 600);  // same process: a's pid is alive, so a's claim is live
  EXPECT_EQ(a.TryClaim("sub/x.png.photometric"), WorkClaims::Result::kClaimed);
  EXPECT_TRUE(FileExists(a.ClaimPath("sub/x.png.photometric")));
  ClaimHolder holder;
  EXPECT_EQ(b.TryClaim("sub/x.png.photometric", &holder), WorkClaims::Result::kHeld);
  EXPECT_EQ(holder.host, WorkClaims::ThisHost());
  EXPECT_EQ(holder.pid, static_cast<long>(::getpid()));
  EXPECT_EQ(b.TryClaim("sub/x.png.geometric1"), WorkClaims::Result::kClaimed);  // other key
  a.Release("sub/x.png.photometric");
  EXPECT_FALSE(FileExists(a.ClaimPath("sub/x.png.photometric")));
  EXPECT_EQ(b.TryClaim("sub/x.png.photometric"), WorkClaims::Result::kClaimed);
}

TEST(WorkClaims, ConcurrentClaimsHaveOneWinner) {
  test::TempDir tmp;
  for (int round = 0; round < 20; ++round) {
    WorkClaims a(tmp / "claims", 600), b(tmp / "claims", 600);
    WorkClaims::Result ra, rb;
    std::thread t([&] { ra = a.TryClaim("k" + std::to_string(round)); });
    rb = b.TryClaim("k" + std::to_string(round));
    t.join();
    EXPECT_NE(ra, rb) << "round " << round;
  }
}

TEST(WorkClaims, ClaimOfADeadProcessIsTakenOver) {
  test::TempDir tmp;
  // A child claims and dies without releasing (as under kill -9).
  const pid_t child = ::fork();
  if (child == 0) {
    WorkClaims c(tmp / "claims", 600);
    const bool ok = c.TryClaim("img.prior") == WorkClaims::Result::kClaimed;
    std::_Exit(ok ? 0 : 1);  // no destructor: the claim stays
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  WorkClaims me(tmp / "claims", 600);
  ASSERT_TRUE(FileExists(me.ClaimPath("img.prior")));
  EXPECT_EQ(me.TryClaim("img.prior"), WorkClaims::Result::kClaimed);

  // Another host's claim: honoured within the (local) lease, taken over after it.
  WorkClaims short_lease(tmp / "claims", 2);
  std::ofstream(me.ClaimPath("far.prior")) << "some-other-host 1 1 2\n";
  ClaimHolder holder;
  EXPECT_EQ(short_lease.TryClaim("far.prior", &holder), WorkClaims::Result::kHeld);
  EXPECT_EQ(holder.Describe(), "some-other-host:1");
  std::this_thread::sleep_for(std::chrono::milliseconds(3100));
  EXPECT_EQ(short_lease.TryClaim("far.prior"), WorkClaims::Result::kClaimed);
}

// Issue 35, defect 8: a foreign claim's own lease overrode the local --MPMVS.claim_lease
// (a claim saying "lease 1" was taken over after 1 s by a process told to wait 600 s); and
// a garbage claim file was printed raw into the log.
TEST(WorkClaims, LocalLeaseDecidesAndGarbageClaimsAreNotPrinted) {
  test::TempDir tmp;
  WorkClaims me(tmp / "claims", 600);
  CreateDirectories(tmp / "claims");
  std::ofstream(me.ClaimPath("far.prior")) << "some-other-host 1 1 1\n";
  std::this_thread::sleep_for(std::chrono::milliseconds(2100));
  EXPECT_EQ(me.TryClaim("far.prior"), WorkClaims::Result::kHeld);

  WorkClaims short_lease(tmp / "claims", 1);
  std::ofstream(me.ClaimPath("junk.prior"), std::ios::binary) << "\x1b[31mjunk\xff 7 1 600\n";
  struct timespec old_times[2] = {{1, 0}, {1, 0}};  // long unrefreshed
  ::utimensat(AT_FDCWD, me.ClaimPath("junk.prior").c_str(), old_times, 0);
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const WorkClaims::Result result = short_lease.TryClaim("junk.prior");
  const std::string log = testing::internal::GetCapturedStdout() + testing::internal::GetCapturedStderr();
  EXPECT_EQ(result, WorkClaims::Result::kClaimed) << log;
  EXPECT_EQ(log.find("junk"), log.find("junk.prior")) << log;  // only the file name, never its bytes
  EXPECT_EQ(log.find('\x1b'), std::string::npos) << log;
  EXPECT_NE(log.find("unreadable"), std::string::npos) << log;
}

TEST(WorkClaims, HolderKeepsItsLeaseFresh) {
  test::TempDir tmp;
  WorkClaims a(tmp / "claims", 1);  // heartbeat every 250 ms
  ASSERT_EQ(a.TryClaim("img.geometric2"), WorkClaims::Result::kClaimed);
  // Past its 1 s lease the file's mtime is still fresh: another host would not take it over.
  const std::string path = a.ClaimPath("img.geometric2");
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  struct stat st;
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_LE(std::time(nullptr) - st.st_mtime, 1);
}

}  // namespace
}  // namespace mpmvs
