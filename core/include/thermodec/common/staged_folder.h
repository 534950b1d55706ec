#pragma once
//! An output folder replaced as a whole: a command writes its result into a private staging
//! folder beside the target and, once every file is written, swaps it into place in one rename,
//! so the folder holds either the previous complete result or the new one, whenever the run is
//! interrupted or killed. A lock beside the folder keeps two runs from writing it at once.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "thermodec/common/interrupt_cleanup.h"

namespace thermodec {

//! An exclusive lock on the output folder `dir`: the file `.NAME.lock` beside it, locked with
//! flock(2) (released by the system when the process ends, however it ends) and holding the
//! owner's process id. Removed when the lock goes out of scope.
class OutputFolderLock {
 public:
  //! \throw InvalidInput if another process holds the lock, naming its process id.
  //! \throw IOError if the lock file cannot be created.
  explicit OutputFolderLock(const std::filesystem::path& dir);
  ~OutputFolderLock();
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;

 private:
  int fd_ = -1;
  std::filesystem::path path_;
  std::unique_ptr<TemporaryPath> file_;  // removed on SIGINT/SIGTERM too
};

//! A result folder written beside `dir` and put in its place by `commit`.
class StagedFolder {
 public:
  //! Locks `dir` (OutputFolderLock), removes the staging folders interrupted runs left beside it
  //! (`.NAME.staging-*`: no run can be using them while the lock is held) and creates an empty
  //! staging folder `.NAME.staging-XXXXXX` (mkdtemp). A `dir` that is a symlink is resolved.
  //! \throw InvalidInput if the folder is in use; IOError if the staging folder cannot be made.
  explicit StagedFolder(const std::filesystem::path& dir);

  //! Where to write the result.
  const std::filesystem::path& staging() const { return staging_.path(); }

  //! Puts the staging folder in place of `dir` in one step (renameat2 RENAME_EXCHANGE when `dir`
  //! exists, else rename), then removes the previous content. The folder keeps the permissions
  //! of the one it replaces. Without the staging folder's removal on failure, the previous
  //! result stays in place.
  //! \throw IOError if the rename fails (the previous result is untouched).
  void commit();

 private:
  std::filesystem::path dir_;
  OutputFolderLock lock_;
  TemporaryPath staging_;
};

}  // namespace thermodec
