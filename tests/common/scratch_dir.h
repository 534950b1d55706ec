#pragma once
// Scratch folders for tests: an empty folder under the system's temporary directory, unique to
// this process and name, removed with its contents when the test process exits, so that test
// runs leave nothing behind. THERMODEC_KEEP_TEST_FILES=1 keeps them for a look after a failure.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace thermodec::test {

class ScratchFolders {
 public:
  static ScratchFolders& instance() {
    static ScratchFolders folders;
    return folders;
  }
  //! BASE/PREFIX_PID_NAME, emptied and created.
  std::filesystem::path make(const std::filesystem::path& base, const std::string& prefix, const std::string& name) {
    const auto d = base / (prefix + "_" + std::to_string(::getpid()) + "_" + name);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    std::lock_guard<std::mutex> lock(mutex_);
    made_.push_back(d);
    return d;
  }
  ~ScratchFolders() {
    const char* keep = std::getenv("THERMODEC_KEEP_TEST_FILES");
    if (keep && std::string(keep) == "1") return;
    std::error_code ec;
    for (const auto& d : made_) std::filesystem::remove_all(d, ec);
  }

 private:
  ScratchFolders() = default;
  std::mutex mutex_;
  std::vector<std::filesystem::path> made_;
};

//! An empty folder TMP/PREFIX_PID_NAME, removed when the test process exits.
inline std::filesystem::path scratch_dir(const std::string& prefix, const std::string& name) {
  return ScratchFolders::instance().make(std::filesystem::temp_directory_path(), prefix, name);
}

//! The same under `base` (e.g. /dev/shm).
inline std::filesystem::path scratch_dir_in(const std::filesystem::path& base, const std::string& prefix,
                                            const std::string& name) {
  return ScratchFolders::instance().make(base, prefix, name);
}

}  // namespace thermodec::test
