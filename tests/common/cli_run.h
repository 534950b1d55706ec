#pragma once
// Running the thermodec CLI from a test (every stage's CLI tests share these): exit code, stdout
// and stderr, in a fresh folder per test.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/scratch_dir.h"

namespace thermodec::test {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code;
  std::string out, err;
};

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

// An empty folder under the system's temporary directory, unique to this process and `name`,
// removed when the test process exits.
inline fs::path temp_dir(const std::string& name) { return thermodec::test::scratch_dir("thermodec_test_cli", name); }

// Runs `thermodec ARGS` with stdout and stderr captured in `dir`; `prefix` goes before the CLI
// (e.g. "timeout 4").
inline CliRun run_cli(const std::string& args, const fs::path& dir, const std::string& prefix = "") {
  const std::string cmd = prefix + " '" + THERMODEC_CLI + "' " + args + " >'" + (dir / "stdout").string() + "' 2>'" +
                          (dir / "stderr").string() + "'";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(dir / "stdout"), read_text(dir / "stderr")};
}

// Runs `thermodec ARGS` with stdout and stderr together in the file `log`; returns the exit code.
inline int run_cli_logged(const std::string& args, const fs::path& log) {
  const std::string cmd = "'" + std::string(THERMODEC_CLI) + "' " + args + " >'" + log.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// As run_cli_logged, with the log (stdout and stderr together) in `output`; the log file is a
// scratch file of this process.
inline int run_cli_text(const std::string& args, std::string& output) {
  const fs::path log = thermodec::test::scratch_dir("thermodec_test_cli_log", "run") / "log.txt";
  const int code = run_cli_logged(args, log);
  output = read_text(log);
  return code;
}

inline std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

inline bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace thermodec::test
