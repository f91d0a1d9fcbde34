// Files replaced whole, and the temporaries of killed writers: real files, and a real child
// process killed while it holds one.
#include "service/io/atomic_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace monocle {
namespace {

namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("monocle_atomic_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Read(const fs::path& p) const {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  std::vector<std::string> Names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename());
    std::sort(out.begin(), out.end());
    return out;
  }
  fs::path dir_;
};

TEST_F(AtomicFileTest, WritesAndReplacesLeavingNothingElse) {
  const fs::path target = dir_ / "cal.pbtxt";
  ASSERT_TRUE(WriteFileAtomically(target, "first\n").ok());
  EXPECT_EQ(Read(target), "first\n");
  ASSERT_TRUE(WriteFileAtomically(target, "second\n").ok());
  EXPECT_EQ(Read(target), "second\n");
  EXPECT_EQ(Names(), std::vector<std::string>{"cal.pbtxt"});
  EXPECT_EQ(fs::status(target).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                fs::perms::others_read);
  EXPECT_FALSE(WriteFileAtomically(dir_ / "no-such-dir" / "x", "x").ok());
}

// A temporary nobody holds is a killed writer's: the next write removes it. Files that only
// look alike stay.
TEST_F(AtomicFileTest, TheNextWriteRemovesAStaleTemporaryAndNothingElse) {
  const fs::path target = dir_ / "cal.pbtxt";
  for (const char* name : {".cal.pbtxt.Q1w2E3", ".cal.pbtxt.backup1", "cal.pbtxt.Q1w2E3",
                           ".calXpbtxt.Q1w2E3", ".other.pbtxt.Q1w2E3"})
    std::ofstream(dir_ / name) << "partial";
  ASSERT_TRUE(WriteFileAtomically(target, "new\n").ok());
  EXPECT_EQ(Names(),
            (std::vector<std::string>{".cal.pbtxt.backup1", ".calXpbtxt.Q1w2E3",
                                      ".other.pbtxt.Q1w2E3", "cal.pbtxt", "cal.pbtxt.Q1w2E3"}));
  EXPECT_EQ(RemoveStaleTemporaries(target), 0);
}

// A writer holds its temporary locked: while it lives the temporary is its own, and once it is
// killed (SIGKILL: no clean-up of its own) the kernel lets the lock go and the temporary is
// removed.
TEST_F(AtomicFileTest, AKilledWritersTemporaryIsRemovedALiveOnesIsNot) {
  const fs::path target = dir_ / "cal.pbtxt";
  const fs::path temporary = dir_ / ".cal.pbtxt.Zz9Yy8";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const int fd = ::open(temporary.c_str(), O_CREAT | O_WRONLY, 0644);
    ::flock(fd, LOCK_EX);
    (void)!::write(fd, "half", 4);
    (void)!::write(ready[1], "x", 1);
    ::pause();
    ::_exit(0);
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_EQ(RemoveStaleTemporaries(target), 0) << "its writer still holds it";
  EXPECT_TRUE(fs::exists(temporary));
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  EXPECT_EQ(RemoveStaleTemporaries(target), 1);
  EXPECT_FALSE(fs::exists(temporary));
  ::close(ready[0]);
  ::close(ready[1]);
}

}  // namespace
}  // namespace monocle
