// Output sets against neighbours (docs/reliability.md, "Threat model"): one writer at a time, a
// lock file only this user can write, nothing under --out followed through a link or opened in a
// way that blocks.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>

#include <gtest/gtest.h>

#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "src/core/folder_fd.hpp"
#include "test_data.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& p, const std::string& s) { test::WriteText(p, s); }
std::string Read(const fs::path& p) { return test::ReadText(p); }

void CommitA(const fs::path& out, const std::string& text, OutputSetOptions o = OutputSetOptions("test")) {
  OutputSet set(out, o);
  Write(set.dir() / "a.txt", text);
  set.Commit(NewReport("test"));
}

double SecondsOf(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(OutputLock, ASecondWriterWaitsForTheFirstOrIsRefused) {
  const fs::path out = test::TempDir() / "out";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    OutputSet set(out, OutputSetOptions("test"));
    Write(set.dir() / "a.txt", "first");
    (void)!::write(ready[1], "x", 1);
    ::usleep(400000);
    set.Commit(NewReport("test"));
    ::_exit(0);
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  OutputSetOptions refuse("test");
  refuse.wait = false;
  EXPECT_THROW(OutputSet(out, refuse), Error);
  std::vector<std::string> notices;
  SetOutputNotices([&](const std::string& n) { notices.push_back(n); });
  CommitA(out, "second");  // waits until the first has committed, then replaces its set
  SetOutputNotices({});
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("waiting for another al-refine (pid " + std::to_string(child) + ")"), std::string::npos);
  EXPECT_EQ(Read(out / "a.txt"), "second");
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
  ::close(ready[0]);
  ::close(ready[1]);
}

TEST(OutputLock, ALockFileThatIsNotThisUsersAloneIsRefused) {
  const fs::path dir = test::TempDir();
  const fs::path out = dir / "out", lock = dir / ".out.al-lock";
  fs::create_symlink(dir / "elsewhere", lock);
  EXPECT_THROW(CommitA(out, "x"), Error);
  EXPECT_FALSE(fs::exists(dir / "elsewhere"));  // the link was not followed to create a file
  fs::remove(lock);
  ASSERT_EQ(::mkfifo(lock.c_str(), 0600), 0);
  EXPECT_LT(SecondsOf([&] { EXPECT_THROW(CommitA(out, "x"), Error); }), 1.0);
  fs::remove(lock);
  Write(lock, "");
  fs::permissions(lock, fs::perms::owner_read | fs::perms::owner_write | fs::perms::others_write);
  EXPECT_THROW(CommitA(out, "x"), Error);
  if (::geteuid() == 0) {  // root: a lock file another user made is theirs, not ours
    fs::permissions(lock, fs::perms::owner_read | fs::perms::owner_write);
    ASSERT_EQ(::chown(lock.c_str(), 65534, 65534), 0);
    EXPECT_THROW(CommitA(out, "x"), Error);
  }
  EXPECT_FALSE(fs::exists(out));
}

// A FIFO where report.json should be: refused at once (it is not al-refine's), never opened.
TEST(OutputLock, AFifoUnderOutIsForeignAndNeverBlocks) {
  const fs::path out = test::TempDir() / "out";
  fs::create_directories(out);
  ASSERT_EQ(::mkfifo((out / "report.json").c_str(), 0600), 0);
  EXPECT_LT(SecondsOf([&] { EXPECT_THROW(CommitA(out, "x"), Error); }), 1.0);
  OutputSetStatus status;
  EXPECT_LT(SecondsOf([&] { status = VerifyOutputSet(out); }), 1.0);
  EXPECT_EQ(status.state, "not_a_set");
  OutputSetOptions journal("test");
  journal.journals = {"results.jsonl"};
  ASSERT_EQ(::mkfifo((out / "results.jsonl").c_str(), 0600), 0);
  journal.force = true;  // even replacing what is not ours: the FIFO is never opened for appending
  OutputSet set(out, journal);
  EXPECT_LT(SecondsOf([&] { EXPECT_THROW(set.OpenJournal("results.jsonl"), Error); }), 1.0);
}

// A listed file that became a link (to a file outside --out) is not al-refine's any more: a run
// refuses to replace it, and with --force replaces the link, never the file it points to.
TEST(OutputLock, AListedFileThatBecameALinkIsForeignAndNeverFollowed) {
  const fs::path dir = test::TempDir();
  const fs::path out = dir / "out";
  CommitA(out, "1");
  Write(dir / "victim.txt", "precious");
  fs::remove(out / "a.txt");
  fs::create_symlink(dir / "victim.txt", out / "a.txt");
  OutputSetOptions planned("test");
  planned.planned = {"a.txt"};
  EXPECT_THROW(OutputSet(out, planned), Error);
  EXPECT_NE(VerifyOutputSet(out).state, "complete");
  planned.force = true;
  CommitA(out, "2", planned);
  EXPECT_EQ(Read(dir / "victim.txt"), "precious");
  EXPECT_FALSE(fs::is_symlink(out / "a.txt"));
  EXPECT_EQ(Read(out / "a.txt"), "2");
}

TEST(FolderFd, RemoveTreeNeverFollowsLinks) {
  const fs::path dir = test::TempDir();
  Write(dir / "keep" / "k.txt", "k");
  Write(dir / "tree" / "sub" / "f.txt", "f");
  fs::create_directory_symlink(dir / "keep", dir / "tree" / "sub" / "link");
  fs::create_symlink(dir / "keep" / "k.txt", dir / "tree" / "file_link");
  const output_set::UniqueFd fd = output_set::OpenFolder(dir);
  ASSERT_TRUE(fd);
  EXPECT_TRUE(output_set::RemoveTreeAt(fd.get(), "tree"));
  EXPECT_FALSE(fs::exists(dir / "tree"));
  EXPECT_EQ(Read(dir / "keep" / "k.txt"), "k");
  fs::create_directory_symlink(dir / "keep", dir / "top_link");
  EXPECT_TRUE(output_set::RemoveTreeAt(fd.get(), "top_link"));  // the link goes, its target stays
  EXPECT_EQ(Read(dir / "keep" / "k.txt"), "k");
  EXPECT_FALSE(output_set::OpenFolder(dir / "missing"));
}

}  // namespace
}  // namespace al
