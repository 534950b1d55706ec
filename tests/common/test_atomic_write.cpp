#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/scratch_dir.h"
#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/staged_folder.h"

namespace fs = std::filesystem;
using namespace thermodec;

namespace {
fs::path temp_dir(const char* name) { return thermodec::test::scratch_dir("thermodec_test", name); }
std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(AtomicWrite, writes_whole_file_and_leaves_no_temporary) {
  auto d = temp_dir("aw1");
  write_text_atomically(d / "sub" / "out.txt", "hello");
  EXPECT_EQ(read(d / "sub" / "out.txt"), "hello");
  int n = 0;
  for (auto& e : fs::directory_iterator(d / "sub")) { (void)e; ++n; }
  EXPECT_EQ(n, 1);
}

TEST(AtomicWrite, failed_writer_keeps_previous_content) {
  auto d = temp_dir("aw2");
  write_text_atomically(d / "out.txt", "old");
  EXPECT_THROW(write_file_atomically(d / "out.txt", [](std::ostream&) { throw InvalidInput("x"); }),
               InvalidInput);
  EXPECT_EQ(read(d / "out.txt"), "old");
}

TEST(AtomicWrite, refuses_to_overwrite_an_input) {
  auto d = temp_dir("aw3");
  write_text_atomically(d / "in.obj", "v 0 0 0\n");
  EXPECT_THROW(write_text_atomically(d / "in.obj", "x", {d / "in.obj"}), InvalidInput);
  EXPECT_EQ(read(d / "in.obj"), "v 0 0 0\n");
}

namespace {
int count_entries(const fs::path& d) {
  int n = 0;
  for (auto& e : fs::directory_iterator(d)) { (void)e; ++n; }
  return n;
}
}  // namespace

TEST(AtomicWrite, never_follows_a_link_planted_at_a_temporary_name) {
  auto d = temp_dir("aw_link");
  write_text_atomically(d / "victim.txt", "precious");
  fs::create_directories(d / "shared");
  // The old fixed name (.NAME.tmpPID) and a spread of names in the new pattern's shape.
  fs::create_symlink("../victim.txt", d / "shared" / (".r.json.tmp" + std::to_string(::getpid())));
  for (const char* s : {"aaaaaa", "XXXXXX", "000000"})
    fs::create_symlink("../victim.txt", d / "shared" / (std::string(".r.json.tmp-") + s));
  std::string seen;
  write_file_atomically(d / "shared" / "r.json", [&](std::ostream& o) {
    // While writing, the temporary is a regular file of this process, private to its owner.
    for (auto& e : fs::directory_iterator(d / "shared"))
      if (!fs::is_symlink(e.symlink_status()) && e.path().filename() != "r.json") {
        seen = e.path().filename().string();
        EXPECT_EQ(fs::status(e.path()).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
      }
    o << "{}";
  });
  EXPECT_EQ(read(d / "victim.txt"), "precious");
  EXPECT_EQ(read(d / "shared" / "r.json"), "{}");
  EXPECT_EQ(seen.rfind(".r.json.tmp-", 0), 0u) << seen;
  EXPECT_EQ(count_entries(d / "shared"), 5);  // r.json and the four links: no temporary left
}

TEST(AtomicWrite, an_existing_output_keeps_its_mode_and_a_new_one_follows_the_umask) {
  auto d = temp_dir("aw_mode");
  write_text_atomically(d / "private.json", "old");
  fs::permissions(d / "private.json", fs::perms::owner_read | fs::perms::owner_write);
  const mode_t old_umask = ::umask(022);
  write_text_atomically(d / "private.json", "new");
  write_text_atomically(d / "fresh.json", "new");
  ::umask(old_umask);
  EXPECT_EQ(read(d / "private.json"), "new");
  EXPECT_EQ(fs::status(d / "private.json").permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(fs::status(d / "fresh.json").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read);
}

TEST(AtomicWrite, refuses_to_replace_a_fifo_or_a_device) {
  auto d = temp_dir("aw_fifo");
  ASSERT_EQ(::mkfifo((d / "pipe.json").c_str(), 0600), 0);
  EXPECT_THROW(write_text_atomically(d / "pipe.json", "x"), InvalidInput);
  EXPECT_TRUE(fs::is_fifo(d / "pipe.json"));
  // A private character device (the null device's numbers) where the system allows one.
  if (::mknod((d / "null.bdf").c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0) {
    EXPECT_THROW(write_text_atomically(d / "null.bdf", "x"), InvalidInput);
    EXPECT_TRUE(fs::is_character_file(d / "null.bdf"));
  }
  EXPECT_EQ(count_entries(d), fs::exists(d / "null.bdf") ? 2 : 1);
}

TEST(AtomicFileSet, a_set_cut_short_leaves_the_earlier_set_whole) {
  auto d = temp_dir("aw_set");
  {
    AtomicFileSet set;
    set.add(d / "a.csv", [](std::ostream& o) { o << "old a"; });
    set.add(d / "b.csv", [](std::ostream& o) { o << "old b"; });
    set.commit();
  }
  {
    AtomicFileSet set;
    set.add(d / "a.csv", [](std::ostream& o) { o << "new a"; });
    EXPECT_THROW(set.add(d / "b.csv", [](std::ostream&) { throw IOError("disk full"); }), IOError);
  }  // not committed: the new a is dropped with its temporary
  EXPECT_EQ(read(d / "a.csv"), "old a");
  EXPECT_EQ(read(d / "b.csv"), "old b");
  EXPECT_EQ(count_entries(d), 2);
}

TEST(StagedFolder, replaces_the_folder_whole_and_keeps_it_if_not_committed) {
  auto d = temp_dir("staged");
  {
    StagedFolder out(d / "result");
    write_text_atomically(out.staging() / "model.json", "first");
    out.commit();
  }
  EXPECT_EQ(read(d / "result" / "model.json"), "first");
  {
    StagedFolder out(d / "result");
    write_text_atomically(out.staging() / "model.json", "second, unfinished");
  }  // dropped: an interrupted run
  EXPECT_EQ(read(d / "result" / "model.json"), "first");
  fs::permissions(d / "result", fs::perms::owner_all);
  {
    StagedFolder out(d / "result");
    write_text_atomically(out.staging() / "model.json", "third");
    write_text_atomically(out.staging() / "report.json", "{}");
    out.commit();
  }
  EXPECT_EQ(read(d / "result" / "model.json"), "third");
  EXPECT_EQ(count_entries(d / "result"), 2);
  EXPECT_EQ(fs::status(d / "result").permissions() & fs::perms::all, fs::perms::owner_all);
  EXPECT_EQ(count_entries(d), 1);  // no staging folder, no lock file
}

TEST(StagedFolder, a_staging_folder_left_by_a_killed_run_is_removed_by_the_next) {
  auto d = temp_dir("staged_stale");
  fs::create_directories(d / ".result.staging-abc123");
  write_text_atomically(d / ".result.staging-abc123" / "model.json", "half");
  {
    StagedFolder out(d / "result");
    EXPECT_FALSE(fs::exists(d / ".result.staging-abc123"));
    out.commit();
  }
  EXPECT_EQ(count_entries(d), 1);
}

TEST(OutputFolderLock, a_folder_in_use_is_refused_naming_the_process) {
  auto d = temp_dir("lock");
  const OutputFolderLock held(d / "result");
  try {
    const OutputFolderLock second(d / "result");
    ADD_FAILURE() << "a second lock on the same folder was granted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("in use"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pid " + std::to_string(::getpid())), std::string::npos) << e.what();
  }
}
