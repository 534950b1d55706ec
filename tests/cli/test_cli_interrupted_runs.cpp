// `reduce --out D` killed at any moment leaves D with the previous complete result or the new
// one, never a mix or nothing; a second run into a folder in use is refused naming the first;
// SIGINT/SIGTERM remove every temporary and say "interrupted"; a result that cannot be written
// completely is a failure that leaves the previous result in place.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {

using namespace thermodec::test;
using Clock = std::chrono::steady_clock;

const fs::path kData = THERMODEC_TEST_DATA_DIR;

// `thermodec ARGS` started in the background, output in DIR/TAG.out and DIR/TAG.err; `env`
// entries ("NAME=value") are added to its environment.
pid_t spawn_cli(const std::vector<std::string>& args, const fs::path& dir, const std::string& tag,
                const std::vector<std::string>& env = {}) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  ::setpgid(0, 0);  // its own group: a signal sent to the test's group does not reach it
  if (!std::freopen((dir / (tag + ".out")).c_str(), "w", stdout) || !std::freopen((dir / (tag + ".err")).c_str(), "w", stderr))
    ::_exit(120);
  for (const auto& e : env) ::putenv(const_cast<char*>(e.c_str()));
  std::vector<char*> argv{const_cast<char*>(THERMODEC_CLI)};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  ::execv(THERMODEC_CLI, argv.data());
  ::_exit(121);
}

// The exit code, or 1000 + the signal that ended it.
int wait_for(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

std::set<std::string> names_in(const fs::path& d) {
  std::set<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(d, ec)) out.insert(e.path().filename().string());
  return out;
}

ino_t inode_of(const fs::path& p) {
  struct stat st;
  return ::lstat(p.c_str(), &st) == 0 ? st.st_ino : 0;
}

// Waits (up to 60 s) until `changed()` or the child has exited; true if changed.
template <class F>
bool wait_until(pid_t pid, F changed) {
  const auto end = Clock::now() + std::chrono::seconds(60);
  while (Clock::now() < end) {
    if (changed()) return true;
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      ADD_FAILURE() << "the run ended before the moment the test waited for";
      return false;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ADD_FAILURE() << "timed out";
  return false;
}

std::vector<std::string> reduce_args(const fs::path& out, int rays, bool plots = false) {
  std::vector<std::string> a{"reduce", (kData / "example_model.json").string(), "-q", "--tolerance", "2",
                             "--rays-per-face", std::to_string(rays), "--max-evaluations", "2", "--noise-target", "0", "--out", out.string()};
  if (!plots) a.push_back("--no-plots");
  return a;
}

std::string joined(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += " " + q(a);
  return s;
}

// D holds one complete result: the three files, a report naming `rays`, a model that loads.
void expect_complete(const fs::path& out, const fs::path& scratch, const std::set<int>& rays_allowed) {
  EXPECT_EQ(names_in(out), (std::set<std::string>{"model.json", "reduced.obj", "report.json"}));
  const std::string report = read_text(out / "report.json");
  bool matched = false;
  for (int rays : rays_allowed) matched = matched || has(read_text(out / "model.json"), "\"rays_per_face\": " + std::to_string(rays));
  EXPECT_TRUE(matched) << read_text(out / "model.json");
  const CliRun info = run_cli("info " + q(out / "model.json"), scratch);
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_FALSE(report.empty());
}

// Beside D: D alone (no staging folder, no lock, no temporary).
void expect_nothing_beside(const fs::path& out) {
  EXPECT_EQ(names_in(out.parent_path()), std::set<std::string>{out.filename().string()});
}

}  // namespace

TEST(CliInterruptedRuns, reduce_killed_at_any_moment_leaves_the_previous_or_the_new_result_whole) {
  auto d = temp_dir("kill");
  auto scratch = temp_dir("kill_scratch");
  const fs::path out = d / "result";
  ASSERT_EQ(run_cli(joined(reduce_args(out, 200)), scratch).exit_code, 0);
  expect_complete(out, scratch, {200});
  // Killed at the first change beside the folder (the lock, the staging folder), then at the
  // first change of the folder itself (the swap).
  const std::set<std::string> before = names_in(d);
  pid_t pid = spawn_cli(reduce_args(out, 300), scratch, "first");
  if (wait_until(pid, [&] { return names_in(d) != before; })) ::kill(pid, SIGKILL);
  EXPECT_EQ(wait_for(pid), 1000 + SIGKILL);
  expect_complete(out, scratch, {200});
  const ino_t old_inode = inode_of(out);
  pid = spawn_cli(reduce_args(out, 300), scratch, "swap");
  if (wait_until(pid, [&] { return inode_of(out) != old_inode; })) ::kill(pid, SIGKILL);
  wait_for(pid);
  expect_complete(out, scratch, {300});
  // The next run removes what the killed ones left and replaces the result.
  const CliRun again = run_cli(joined(reduce_args(out, 400)), scratch);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  expect_complete(out, scratch, {400});
  expect_nothing_beside(out);
}

TEST(CliInterruptedRuns, a_second_reduce_into_a_folder_in_use_is_refused_naming_the_first) {
  auto d = temp_dir("concurrent");
  auto scratch = temp_dir("concurrent_scratch");
  const fs::path out = d / "result";
  const pid_t first = spawn_cli(reduce_args(out, 20000), scratch, "first");
  ASSERT_TRUE(wait_until(first, [&] { return fs::exists(d / ".result.lock"); }));
  const CliRun second = run_cli(joined(reduce_args(out, 200)), scratch);
  EXPECT_EQ(second.exit_code, 1);
  EXPECT_TRUE(has(second.err, "in use by another thermodec run (pid " + std::to_string(first) + ")")) << second.err;
  EXPECT_EQ(wait_for(first), 0) << read_text(scratch / "first.err");
  expect_complete(out, scratch, {20000});
  expect_nothing_beside(out);
}

TEST(CliInterruptedRuns, sigterm_and_sigint_remove_every_temporary_and_say_interrupted) {
  auto d = temp_dir("signals");
  auto scratch = temp_dir("signals_scratch");
  auto tmp = temp_dir("signals_tmp");
  const fs::path out = d / "result";
  ASSERT_EQ(run_cli(joined(reduce_args(out, 200)), scratch).exit_code, 0);
  const std::string old_report = read_text(out / "report.json");
  // SIGTERM while the plots are drawn (their private folders in TMPDIR).
  const std::string tmpdir = "TMPDIR=" + tmp.string();
  pid_t pid = spawn_cli(reduce_args(out, 300, true), scratch, "term", {tmpdir});
  if (wait_until(pid, [&] { return !names_in(tmp).empty(); })) ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_for(pid), 128 + SIGTERM);
  EXPECT_TRUE(has(read_text(scratch / "term.err"), "interrupted (SIGTERM)")) << read_text(scratch / "term.err");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // plot children see their folder gone
  EXPECT_EQ(names_in(tmp), std::set<std::string>{});
  EXPECT_EQ(read_text(out / "report.json"), old_report);
  expect_nothing_beside(out);
  // SIGINT as soon as the staging folder exists.
  pid = spawn_cli(reduce_args(out, 300), scratch, "int");
  if (wait_until(pid, [&] {
        for (const auto& n : names_in(d))
          if (n.rfind(".result.staging-", 0) == 0) return true;
        return false;
      }))
    ::kill(pid, SIGINT);
  EXPECT_EQ(wait_for(pid), 128 + SIGINT);
  EXPECT_TRUE(has(read_text(scratch / "int.err"), "interrupted (SIGINT)")) << read_text(scratch / "int.err");
  EXPECT_EQ(read_text(out / "report.json"), old_report);
  expect_nothing_beside(out);
}

TEST(CliInterruptedRuns, a_result_whose_plots_cannot_be_written_fails_and_keeps_the_previous_one) {
  auto d = temp_dir("plots_fail");
  auto scratch = temp_dir("plots_fail_scratch");
  auto plots = temp_dir("plots_fail_scripts");
  const fs::path out = d / "result";
  ASSERT_EQ(run_cli(joined(reduce_args(out, 200)), scratch).exit_code, 0);
  const std::string old_report = read_text(out / "report.json");
  // Plot scripts that fail as a full disk makes them fail: no picture written.
  for (const char* kind : {"sensitivity", "predicted_vs_real", "temperatures_before_after", "mesh_view"})
    write_text(plots / (std::string(kind) + ".py"), "import sys\nsys.stderr.write('No space left on device')\nsys.exit(1)\n");
  const CliRun r = run_cli(joined(reduce_args(out, 300, true)), scratch, "THERMODEC_PLOTS_DIR=" + q(plots));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "could not be written completely")) << r.err;
  EXPECT_FALSE(has(r.out, "results:")) << r.out;
  EXPECT_EQ(read_text(out / "report.json"), old_report);
  expect_nothing_beside(out);
}

TEST(CliInterruptedRuns, a_full_disk_fails_the_run_and_keeps_the_previous_result) {
  // A 256 KiB tmpfs mounted in a private mount namespace (unshare -m): skipped where the system
  // does not allow it.
  auto d = temp_dir("full_disk");
  const fs::path disk = d / "disk";
  fs::create_directories(disk);
  auto reduce = [&](int rays, bool plots) {
    std::string cmd = q(THERMODEC_CLI);
    for (const auto& a : reduce_args(disk / "result", rays, plots)) cmd += " " + q(a);
    return cmd;
  };
  const std::string script =
      "mount -t tmpfs -o size=256k tmpfs " + q(disk) + " || exit 77\n" + reduce(200, false) + " >/dev/null 2>&1 || exit 78\n" +
      "cp " + q(disk / "result" / "report.json") + " " + q(d / "report_before") + "\n" +
      // 32 KiB left: room for the JSON and the mesh (3 pages, twice), none for a plot (39-76 KB).
      "dd if=/dev/zero of=" + q(disk / "room") + " bs=1k count=32 2>/dev/null\n" +
      "dd if=/dev/zero of=" + q(disk / "filler") + " bs=1k count=100000 2>/dev/null\nrm " + q(disk / "room") + "\n" +
      reduce(300, true) + " >" + q(d / "out") + " 2>" + q(d / "err") + "; echo $? >" + q(d / "rc") + "\n" +
      "ls -A " + q(disk) + " >" + q(d / "beside") + "; ls -A " + q(disk / "result") + " >" + q(d / "inside") + "\n" +
      "cp " + q(disk / "result" / "report.json") + " " + q(d / "report_after") + "\n" +
      reduce(300, false) + " >" + q(d / "out2") + " 2>" + q(d / "err2") + "; echo $? >" +
      q(d / "rc2") + "\n";
  write_text(d / "script.sh", script);
  const int status = std::system(("unshare -m sh " + q(d / "script.sh") + " 2>" + q(d / "unshare.err")).c_str());
  if (!WIFEXITED(status) || WEXITSTATUS(status) == 77 || !fs::exists(d / "rc"))
    GTEST_SKIP() << "no private tmpfs here: " << read_text(d / "unshare.err");
  ASSERT_NE(WEXITSTATUS(status), 78) << "the first run failed";
  EXPECT_EQ(read_text(d / "rc"), "1\n") << read_text(d / "err");
  EXPECT_TRUE(has(read_text(d / "err"), "could not be written completely") || has(read_text(d / "err"), "disk full"))
      << read_text(d / "err");
  EXPECT_FALSE(has(read_text(d / "out"), "results:"));
  EXPECT_EQ(read_text(d / "beside"), "filler\nresult\n");
  EXPECT_EQ(read_text(d / "inside"), "model.json\nreduced.obj\nreport.json\n");
  EXPECT_EQ(read_text(d / "report_after"), read_text(d / "report_before"));
  // Without plots the new result fits: the disk, not the run, was at fault.
  EXPECT_EQ(read_text(d / "rc2"), "0\n") << read_text(d / "err2");
}
