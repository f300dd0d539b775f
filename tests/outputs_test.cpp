// Output files (io.hpp): AtomicOutput writes regular files only and checks every byte, an
// OutputSet writes all its files or none, check_output_paths refuses an output that is an input.
// The checks look at the file system itself (file types, contents, leftover temporary files), not
// at what the code says it did.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <string>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"

namespace {

namespace fs = std::filesystem;
using namespace toolpoint;

class Outputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("toolpoint_outputs_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Every entry of the scratch folder (recursively), hidden temporary files included.
  std::vector<std::string> listing() const {
    std::vector<std::string> v;
    for (const auto& e : fs::recursive_directory_iterator(dir_)) v.push_back(fs::relative(e.path(), dir_).string());
    std::sort(v.begin(), v.end());
    return v;
  }
  fs::path dir_;
};

bool is_character_device(const char* p) {
  struct stat st {};
  return ::lstat(p, &st) == 0 && S_ISCHR(st.st_mode);
}

// /dev/full must not be replaced by a renamed temporary file (as root, rename() would do it):
// refused before anything is created, and /dev holds no temporary file afterwards.
TEST_F(Outputs, DevicesFifosAndFoldersAreRefusedAndLeftAsTheyAre) {
  ASSERT_TRUE(is_character_device("/dev/full"));
  const auto dev_before = [] {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator("/dev")) v.push_back(e.path().filename().string());
    return v.size();
  };
  const std::size_t n = dev_before();
  try {
    write_text_file("/dev/full", "x");
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("character device"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(is_character_device("/dev/full"));
  EXPECT_EQ(dev_before(), n);

  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0644), 0);
  EXPECT_THROW(write_text_file(path("fifo"), "x"), IoError);
  fs::create_directories(path("folder"));
  EXPECT_THROW(write_text_file(path("folder"), "x"), IoError);
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
  EXPECT_TRUE(fs::is_directory(path("folder")));
  EXPECT_EQ(listing(), (std::vector<std::string>{"fifo", "folder"}));
}

// A write that fails part-way (here the process's file-size limit, the same error path as a full
// disk: write() returns an error after some bytes) is an IoError; the old file keeps its content
// and no temporary file stays.
TEST_F(Outputs, AWriteThatFailsPartWayLeavesTheOldFile) {
  write_text_file(path("a.csv"), "old\n");
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string message;
  try {
    write_text_file(path("a.csv"), std::string(100000, 'x'));
  } catch (const IoError& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  EXPECT_NE(message.find("write failed after 4096 of 100000 bytes"), std::string::npos) << message;
  EXPECT_EQ(read_text_file(path("a.csv")), "old\n");
  EXPECT_EQ(listing(), std::vector<std::string>{"a.csv"});
}

// A folder that cannot be made (its path runs through a regular file): IoError, nothing created.
// A read-only folder does the same for a user other than root (root writes anyway, so it is
// checked only then).
TEST_F(Outputs, AFolderThatCannotBeMadeOrWrittenIsAnError) {
  write_text_file(path("file"), "x");
  EXPECT_THROW(write_text_file(path("file/sub/a.csv"), "y"), IoError);
  EXPECT_EQ(listing(), std::vector<std::string>{"file"});
  if (::geteuid() != 0) {
    fs::create_directories(path("ro"));
    fs::permissions(path("ro"), fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_THROW(write_text_file(path("ro/a.csv"), "y"), IoError);
    fs::permissions(path("ro"), fs::perms::owner_all);
    EXPECT_TRUE(fs::is_empty(path("ro")));
  }
}

// A symbolic link to a regular file is written through: the link stays, the file changes.
TEST_F(Outputs, ASymbolicLinkIsWrittenThrough) {
  write_text_file(path("real.csv"), "old\n");
  fs::create_symlink(path("real.csv"), path("link.csv"));
  write_text_file(path("link.csv"), "new\n");
  EXPECT_TRUE(fs::is_symlink(path("link.csv")));
  EXPECT_EQ(read_text_file(path("real.csv")), "new\n");
}

// Folders made for a file that is then not written are removed again.
TEST_F(Outputs, FoldersMadeForADiscardedFileAreRemoved) {
  { AtomicOutput out(path("a/b/c.csv")); }
  EXPECT_TRUE(listing().empty());
}

// All or none: a set whose third file cannot be written leaves the first two targets as they were
// (one existed, one did not); committed, every file is there.
TEST_F(Outputs, ASetWritesAllOrNone) {
  write_text_file(path("one.csv"), "old one\n");
  fs::create_directories(path("dir/three.csv"));  // a folder where the third file should go
  try {
    OutputSet set;
    write_text_file(path("one.csv"), "new one\n");
    write_text_file(path("dir/two.csv"), "two\n");
    EXPECT_EQ(read_text_file(path("one.csv")), "old one\n");  // staged, not yet written
    write_text_file(path("dir/three.csv"), "three\n");
    set.commit();
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("three.csv"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text_file(path("one.csv")), "old one\n");
  EXPECT_EQ(listing(), (std::vector<std::string>{"dir", "dir/three.csv", "one.csv"}));

  fs::remove(path("dir/three.csv"));
  {
    OutputSet set;
    write_text_file(path("one.csv"), "new one\n");
    write_text_file(path("dir/two.csv"), "two\n");
    write_text_file(path("dir/three.csv"), "three\n");
    EXPECT_EQ(set.staged().size(), 3u);
    EXPECT_EQ(set.commit().size(), 3u);
  }
  EXPECT_EQ(read_text_file(path("one.csv")), "new one\n");
  EXPECT_EQ(read_text_file(path("dir/three.csv")), "three\n");
  EXPECT_EQ(listing(), (std::vector<std::string>{"dir", "dir/three.csv", "dir/two.csv", "one.csv"}));
}

// A rename that fails during commit (the second file's temporary file removed behind the set's
// back) puts the first target's old content back and removes the new third one.
TEST_F(Outputs, ARenameThatFailsDuringCommitIsUndone) {
  write_text_file(path("a.csv"), "old a\n");
  write_text_file(path("b.csv"), "old b\n");
  std::string message;
  {
    OutputSet set;
    write_text_file(path("a.csv"), "new a\n");
    write_text_file(path("b.csv"), "new b\n");
    write_text_file(path("c.csv"), "new c\n");
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().rfind(".b.csv.tmp.", 0) == 0) fs::remove(e.path());
    try {
      set.commit();
    } catch (const IoError& e) {
      message = e.what();
    }
  }
  EXPECT_NE(message.find("b.csv: cannot replace the file"), std::string::npos) << message;
  EXPECT_NE(message.find("none of the 3 files"), std::string::npos) << message;
  EXPECT_EQ(read_text_file(path("a.csv")), "old a\n");
  EXPECT_EQ(read_text_file(path("b.csv")), "old b\n");
  EXPECT_EQ(listing(), (std::vector<std::string>{"a.csv", "b.csv"}));
}

// An input read while the set is open cannot be staged as an output (by any name of it: a hard
// link too), nor one target twice; nothing is written.
TEST_F(Outputs, ASetRefusesItsInputsAndRepeatedTargets) {
  write_text_file(path("in.toml"), "input\n");
  fs::create_hard_link(path("in.toml"), path("alias.toml"));
  {
    OutputSet set;
    read_text_file(path("in.toml"));
    EXPECT_THROW(write_text_file(path("alias.toml"), "output\n"), InvalidArgument);
    write_text_file(path("out.csv"), "1\n");
    EXPECT_THROW(write_text_file(path("./out.csv"), "2\n"), InvalidArgument);
  }
  EXPECT_EQ(read_text_file(path("in.toml")), "input\n");
  EXPECT_EQ(listing(), (std::vector<std::string>{"alias.toml", "in.toml"}));
}

// The same file under other names: "./x", "sub/../x", a hard link; two equal outputs.
TEST_F(Outputs, CheckOutputPathsSeesThroughNames) {
  write_text_file(path("in.csv"), "x\n");
  fs::create_hard_link(path("in.csv"), path("link.csv"));
  const std::string dot = (dir_ / "." / "in.csv").string(), up = (dir_ / "sub" / ".." / "in.csv").string();
  for (const std::string& out : {dot, up, path("link.csv")}) {
    try {
      check_output_paths({{path("in.csv"), "--sh"}}, {{out, "--output"}});
      FAIL() << out;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("--output " + out + " is the --sh"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(check_output_paths({}, {{path("new.csv"), "--output"}, {(dir_ / "." / "new.csv").string(), "--envelope"}}),
               InvalidArgument);
  EXPECT_NO_THROW(check_output_paths({{path("in.csv"), "--sh"}}, {{path("new.csv"), "--output"}, {"", "--plot"}}));
}

}  // namespace
