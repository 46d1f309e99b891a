// Output sets as transactions (al/core/output_set.hpp): what a reader sees, what is never touched.
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <functional>

#include <gtest/gtest.h>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/output_set.hpp"
#include "al/core/report.hpp"
#include "src/core/folder_fd.hpp"
#include "src/core/output_lock.hpp"
#include "test_data.hpp"

namespace al {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& p, const std::string& s) { test::WriteText(p, s); }
std::string Read(const fs::path& p) { return test::ReadText(p); }

// Every entry of dir's parent that is not dir itself or `keep` (staging left behind, .tmp files).
std::vector<std::string> Leftovers(const fs::path& dir, const std::vector<std::string>& keep = {}) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir.parent_path())) {
    const std::string n = e.path().filename().string();
    if (e.path() != dir && std::find(keep.begin(), keep.end(), n) == keep.end()) out.push_back(n);
  }
  return out;
}

// A set with files a.txt and sub/b.txt, committed into out.
nlohmann::json CommitSet(const fs::path& out, const std::string& tag, OutputSetOptions o = {}) {
  o.command = "test";
  OutputSet set(out, o);
  Write(set.dir() / "a.txt", "a" + tag);
  Write(set.dir() / "sub" / "b.txt", "b" + tag);
  return set.Commit(NewReport("test"));
}

pid_t DeadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

// A run into `out` killed (no destructor, no commit) after `work` wrote into its staging.
void KilledRun(const fs::path& out, OutputSetOptions o, const std::function<void(OutputSet&)>& work) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    OutputSet* set = new OutputSet(out, o);  // never destroyed: what SIGKILL leaves
    work(*set);
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

std::vector<std::string> Named(const fs::path& dir, const std::string& prefix) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(prefix, 0) == 0) found.push_back(e.path().filename().string());
  std::sort(found.begin(), found.end());
  return found;
}

TEST(OutputSet, CommitPublishesTheSetWithAManifestAndLeavesNothingBehind) {
  const fs::path out = test::TempDir() / "out";
  const auto report = CommitSet(out, "1");
  EXPECT_EQ(Read(out / "a.txt"), "a1");
  EXPECT_EQ(Read(out / "sub" / "b.txt"), "b1");
  const auto files = report["manifest"]["files"];
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0]["path"], "a.txt");
  EXPECT_EQ(files[0]["bytes"], 2);
  EXPECT_EQ(files[0]["sha256"], Sha256File(out / "a.txt"));
  EXPECT_EQ(files[1]["path"], "sub/b.txt");
  EXPECT_TRUE(Leftovers(out).empty());
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
}

TEST(OutputSet, ASecondRunReplacesTheWholeEarlierSet) {
  const fs::path out = test::TempDir() / "out";
  CommitSet(out, "1");
  Write(out / "old_only.txt", "x");  // foreign: not in the manifest, so kept
  {
    OutputSet set(out, OutputSetOptions("test"));
    Write(set.dir() / "a.txt", "a2");
    set.Commit(NewReport("test"));
  }
  EXPECT_EQ(Read(out / "a.txt"), "a2");
  EXPECT_FALSE(fs::exists(out / "sub"));  // listed by the earlier manifest, not written again
  EXPECT_EQ(Read(out / "old_only.txt"), "x");
  EXPECT_TRUE(Leftovers(out).empty());
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
}

TEST(OutputSet, AFailedRunLeavesTheEarlierSetUntouched) {
  const fs::path out = test::TempDir() / "out";
  CommitSet(out, "1");
  {
    OutputSet set(out, OutputSetOptions("test"));
    Write(set.dir() / "a.txt", "half");
  }  // no Commit: an exception unwound the run
  EXPECT_EQ(Read(out / "a.txt"), "a1");
  EXPECT_TRUE(Leftovers(out).empty());
}

// --out under folders that do not exist yet: a run that is refused (the constructor throws) or
// fails (no Commit) removes the folders it created; a committed run keeps them; a folder that
// someone else filled meanwhile stays.
TEST(OutputSet, ARunThatNeverCommitsLeavesNoNewFolders) {
  const fs::path base = test::TempDir() / "new";
  const fs::path out = base / "a" / "b" / "out";
  OutputSetOptions refused("test", {out / "a.txt"}, {"a.txt"});  // an input this run would replace
  EXPECT_THROW(OutputSet(out, refused), Error);
  EXPECT_FALSE(fs::exists(base));
  {
    OutputSet set(out, OutputSetOptions("test"));
    Write(set.dir() / "a.txt", "half");
  }  // no Commit
  EXPECT_FALSE(fs::exists(base));
  {
    OutputSet set(out, OutputSetOptions("test"));
    Write(base / "a" / "theirs.txt", "x");  // another process writes beside --out meanwhile
  }
  EXPECT_FALSE(fs::exists(base / "a" / "b"));
  EXPECT_EQ(Read(base / "a" / "theirs.txt"), "x");
  CommitSet(out, "1");
  EXPECT_EQ(Read(out / "a.txt"), "a1");
}

TEST(OutputSet, ForeignFilesUnderPlannedNamesAreRefusedUnlessForced) {
  const fs::path out = test::TempDir() / "out";
  Write(out / "a.txt", "user's");
  OutputSetOptions o("test");
  o.planned = {"a.txt"};
  EXPECT_THROW(OutputSet(out, o), Error);
  // Not planned up front: the commit refuses instead, and the user's file survives.
  EXPECT_THROW(CommitSet(out, "1"), Error);
  EXPECT_EQ(Read(out / "a.txt"), "user's");
  EXPECT_TRUE(Leftovers(out).empty());
  o.force = true;
  CommitSet(out, "1", o);
  EXPECT_EQ(Read(out / "a.txt"), "a1");
  EXPECT_TRUE(Leftovers(out).empty());  // the replaced foreign file is gone, not parked beside
}

TEST(OutputSet, InputsInsideOutAreRefusedOnlyWhenTheRunWouldReplaceThem) {
  const fs::path out = test::TempDir() / "out";
  CommitSet(out, "1");
  Write(out / "masks" / "v.png", "mask");
  OutputSetOptions o("test");
  o.inputs = {out / "sub" / "b.txt"};  // listed by the earlier manifest: replaced by this run
  EXPECT_THROW(OutputSet(out, o), Error);
  o.inputs = {out / "masks"};  // the user's folder, not written by this run
  EXPECT_NO_THROW(OutputSet(out, o));
  o.planned = {"masks"};
  EXPECT_THROW(OutputSet(out, o), Error);
}

TEST(OutputSet, AnOutThatIsAFileOrUnwritableIsRefusedAtOnce) {
  const fs::path dir = test::TempDir();
  Write(dir / "file", "x");
  EXPECT_THROW(OutputSet(dir / "file", OutputSetOptions("test")), Error);
  EXPECT_THROW(OutputSet(dir / "file" / "sub", OutputSetOptions("test")), Error);
  EXPECT_THROW(OutputSet("/", OutputSetOptions("test")), Error);
}

TEST(OutputSet, AKilledRunsStagingIsRemovedByTheNextRunAndLookAlikesAreLeftAlone) {
  const fs::path out = test::TempDir() / "out";
  KilledRun(out, OutputSetOptions("test"), [](OutputSet& set) { Write(set.dir() / "a.txt", "half"); });
  ASSERT_EQ(Named(out.parent_path(), ".out.al-staging-").size(), 1u);
  // Look-alikes: a dead process's name, a live one's, another --out's. None is recorded anywhere.
  const fs::path dead = out.parent_path() / (".out.al-staging-" + std::to_string(DeadPid()));
  const fs::path alive = out.parent_path() / ".out.al-staging-1";
  const fs::path other = out.parent_path() / ".other.al-staging-999999";
  for (const auto& p : {dead, alive, other}) Write(p / "x", "x");
  const auto report = CommitSet(out, "1");
  EXPECT_EQ(Named(out.parent_path(), ".out.al-staging-"),
            (std::vector<std::string>{alive.filename().string(), dead.filename().string()}));
  for (const auto& p : {dead, alive, other}) EXPECT_EQ(Read(p / "x"), "x");
  const std::string warnings = report["warnings"].dump();
  EXPECT_NE(warnings.find(dead.filename().string()), std::string::npos);
  EXPECT_NE(warnings.find("left alone"), std::string::npos);
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
}

// What a journaled commit killed half-way leaves: its folder, named in the lock's record.
TEST(OutputSet, AnInterruptedCommitIsFinishedByTheNextRun) {
  const fs::path out = test::TempDir() / "out";
  CommitSet(out, "1");
  const std::string commit = ".out.al-commit-" + std::to_string(DeadPid()) + "-0123456789abcdef";
  {
    const output_set::UniqueFd dir = output_set::OpenFolder(out.parent_path());
    output_set::OutputLock lock(dir.get(), ".out.al-lock", out.parent_path() / ".out.al-lock", out, false, {});
    lock.Record({DeadPid(), "", commit, {}});
  }  // the lock is released: its holder was killed
  const fs::path folder = out.parent_path() / commit;
  Write(folder / "sub" / "b.txt", "b2");
  Write(folder / "report.json", Read(out / "report.json"));
  fs::remove(out / "report.json");
  EXPECT_EQ(VerifyOutputSet(out).state, "incomplete");
  { OutputSet next(out, OutputSetOptions("test")); }  // recovery happens before anything else
  EXPECT_EQ(Read(out / "sub" / "b.txt"), "b2");
  EXPECT_TRUE(fs::exists(out / "report.json"));
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_TRUE(Leftovers(out).empty());
}

TEST(OutputSet, JournalsSurviveKillsAndFailuresAndAreAdoptedByTheNextRun) {
  const fs::path out = test::TempDir() / "out";
  OutputSetOptions o("test");
  o.journals = {"results.jsonl"};
  // A sweep killed before its first commit leaves the journal, claimed in the lock's record.
  KilledRun(out, o, [](OutputSet& set) { std::ofstream(set.Journal("results.jsonl")) << "{\"id\":1}\n"; });
  {
    OutputSet failed(out, o);  // adopted: not a foreign collision; then this run fails too
    std::ofstream(failed.Journal("results.jsonl"), std::ios::app) << "{\"id\":2}\n";
  }
  OutputSet set(out, o);  // a failure keeps the claim as well
  std::ofstream(set.Journal("results.jsonl"), std::ios::app) << "{\"id\":3}\n";
  Write(set.dir() / "results.csv", "id\n1\n2\n3\n");
  const auto report = set.Commit(NewReport("test"));
  EXPECT_EQ(Read(out / "results.jsonl"), "{\"id\":1}\n{\"id\":2}\n{\"id\":3}\n");
  EXPECT_TRUE(report["manifest"]["files"][1]["append_only"].get<bool>());
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
  EXPECT_TRUE(Leftovers(out).empty());  // the claim is settled: no lock file is left
  std::ofstream(out / "results.jsonl", std::ios::app) << "{\"id\":4}\n";  // the next run appends
  EXPECT_EQ(VerifyOutputSet(out).state, "extended");
}

// A neighbour's forged claim (the folder and file an older al-refine used) does not make a user's
// results.jsonl al-refine's.
TEST(OutputSet, AForgedJournalClaimIsNotHonoured) {
  const fs::path out = test::TempDir() / "out";
  Write(out / "results.jsonl", "mine\n");
  Write(out.parent_path() / (".out.al-staging-" + std::to_string(DeadPid())) / ".al-journals", "results.jsonl\n");
  OutputSetOptions o("test");
  o.journals = {"results.jsonl"};
  EXPECT_THROW(OutputSet(out, o), Error);
  EXPECT_EQ(Read(out / "results.jsonl"), "mine\n");
}

TEST(OutputSet, ACommitIntoTheWorkingFolderKeepsItInPlace) {
  const fs::path out = test::TempDir() / "out";
  CommitSet(out, "1");
  const fs::path before = fs::current_path();
  fs::current_path(out);
  CommitSet(".", "2");  // an exchange would leave this process (and a user's shell) in a deleted folder
  EXPECT_TRUE(fs::exists(fs::current_path() / "report.json"));
  EXPECT_EQ(Read("a.txt"), "a2");
  fs::current_path(before);
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
}

// Docker's -v DIR:/out or a mounted disk as --out: a staging folder beside it would lie on another
// filesystem, from where nothing can be renamed into --out. The set is staged inside it.
TEST(OutputSet, AMountPointAsOutIsStagedInsideIt) {
  const fs::path out = test::TempDir() / "mnt";
  fs::create_directories(out);
  if (::geteuid() != 0 || ::mount("tmpfs", out.c_str(), "tmpfs", 0, "size=16m") != 0)
    GTEST_SKIP() << "creating a mount point needs root and mount(2)";
  struct Unmount {
    fs::path dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  } unmount{out};
  CommitSet(out, "1");
  CommitSet(out, "2");
  EXPECT_EQ(Read(out / "a.txt"), "a2");
  EXPECT_EQ(Read(out / "sub" / "b.txt"), "b2");
  EXPECT_EQ(VerifyOutputSet(out).state, "complete");
  EXPECT_TRUE(Leftovers(out).empty());
  // A killed run's staging inside --out is reported by verify and removed by the next run.
  KilledRun(out, OutputSetOptions("test"), [](OutputSet& set) { Write(set.dir() / "a.txt", "x"); });
  const OutputSetStatus status = VerifyOutputSet(out);
  ASSERT_EQ(status.problems.size(), 1u);
  EXPECT_NE(status.problems[0].find("staging of a killed run"), std::string::npos);
  CommitSet(out, "3");
  std::vector<std::string> inside;
  for (const auto& e : fs::directory_iterator(out)) inside.push_back(e.path().filename().string());
  std::sort(inside.begin(), inside.end());
  EXPECT_EQ(inside, (std::vector<std::string>{"a.txt", "report.json", "sub"}));
}

TEST(OutputSet, VerifyNamesFilesThatDifferFromTheManifest) {
  const fs::path out = test::TempDir() / "out";
  CommitSet(out, "1");
  Write(out / "a.txt", "a9");  // same size, other bytes
  fs::remove(out / "sub" / "b.txt");
  const OutputSetStatus s = VerifyOutputSet(out);
  EXPECT_EQ(s.state, "incomplete");
  ASSERT_EQ(s.problems.size(), 2u);
  EXPECT_NE(s.problems[0].find("a.txt"), std::string::npos);
  EXPECT_NE(s.problems[1].find("missing"), std::string::npos);
  EXPECT_EQ(VerifyOutputSet(out.parent_path() / "nothing").state, "not_a_set");
}

}  // namespace
}  // namespace al
