#pragma once
//! What an interrupted run leaves behind: temporaries (output files being written, staging
//! folders, plot folders, lock files) are registered while they exist, and a program that calls
//! `remove_temporaries_on_interrupt` removes them all when it receives SIGINT, SIGTERM or SIGHUP,
//! says "interrupted" and exits with 128 + the signal number. SIGKILL cannot be caught: what it
//! leaves is named so that the next run recognises and removes it (docs/architecture.md).
#include <filesystem>
#include <functional>
#include <string>

namespace thermodec {

//! A file or folder removed when the guard goes out of scope (unless released) or when the
//! process is interrupted, whichever comes first.
class TemporaryPath {
 public:
  //! Runs `create`, which makes the file or folder and returns its path, under the lock the
  //! interrupt cleanup takes: a temporary is never created unseen by it. `folder`: removed with
  //! its contents.
  //! \throw whatever `create` throws (nothing is registered then).
  TemporaryPath(const std::function<std::filesystem::path()>& create, bool folder);
  ~TemporaryPath();
  TemporaryPath(const TemporaryPath&) = delete;
  TemporaryPath& operator=(const TemporaryPath&) = delete;

  const std::filesystem::path& path() const { return path_; }
  //! Keeps the path: it was renamed into place (or is no longer there).
  void release();
  //! Removes it now.
  void remove();

 private:
  std::filesystem::path path_;
  bool folder_ = false;
  bool active_ = false;
};

//! Installs handlers for SIGINT, SIGTERM and SIGHUP that remove every live TemporaryPath, print
//! "`program`: interrupted (SIGNAME); temporary files removed" on stderr and exit with 128 + the
//! signal number. The handler only wakes a watcher thread, which does the work. Call once, early.
void remove_temporaries_on_interrupt(const std::string& program);

}  // namespace thermodec
