#include "thermodec/common/staged_folder.h"

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "thermodec/common/errors.h"

namespace thermodec {
namespace fs = std::filesystem;
namespace {

// The folder as one absolute name without a trailing slash; a symlink to a folder is followed.
fs::path resolved(const fs::path& dir) {
  std::error_code ec;
  fs::path d = fs::absolute(dir, ec).lexically_normal();
  if (!d.has_filename()) d = d.parent_path();
  if (fs::is_symlink(fs::symlink_status(d, ec))) {
    const fs::path target = fs::canonical(d, ec);
    if (!ec) d = target;
  }
  return d;
}

fs::path beside(const fs::path& dir, const std::string& suffix) {
  return dir.parent_path() / ("." + dir.filename().string() + suffix);
}

std::string read_small(int fd) {
  char buf[64] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string s(buf, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

mode_t folder_mode(const fs::path& dir) {
  struct stat st;
  if (::stat(dir.c_str(), &st) == 0) return st.st_mode & 07777;
  const mode_t m = ::umask(022);
  ::umask(m);
  return 0777 & ~m;
}

}  // namespace

OutputFolderLock::OutputFolderLock(const fs::path& dir) : path_(beside(resolved(dir), ".lock")) {
  std::error_code ec;
  fs::create_directories(path_.parent_path(), ec);
  // note: a lock file removed by its owner between this open and the flock is a different file from
  // the one now at the path; such a lock is worthless, so open again (the classic flock race).
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0)
      throw IOError("cannot create the lock file " + path_.string() + ": " + std::strerror(errno) +
                    " (the result is written beside the output folder and swapped in: its parent must be writable)");
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const std::string pid = read_small(fd);
      ::close(fd);
      throw InvalidInput("output folder " + dir.string() + " is in use by another thermodec run" +
                         (pid.empty() ? std::string() : " (pid " + pid + ")") +
                         "; wait for it to finish or choose another folder");
    }
    struct stat held, now;
    if (::fstat(fd, &held) == 0 && ::lstat(path_.c_str(), &now) == 0 && held.st_dev == now.st_dev &&
        held.st_ino == now.st_ino) {
      const std::string pid = std::to_string(::getpid()) + "\n";
      // The id only serves the message of a run refused; failing to write it is harmless.
      if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) < 0) errno = 0;
      fd_ = fd;
      file_ = std::make_unique<TemporaryPath>([this] { return path_; }, false);
      return;
    }
    ::close(fd);
  }
  throw IOError("cannot lock " + path_.string() + ": it keeps being replaced");
}

OutputFolderLock::~OutputFolderLock() {
  if (fd_ < 0) return;
  file_.reset();  // unlinked while still holding the lock: see the constructor's note
  ::close(fd_);
}

StagedFolder::StagedFolder(const fs::path& dir)
    : dir_(resolved(dir)),
      lock_(dir),
      staging_(
          [this] {
            // Under the lock, every staging folder beside the target is an interrupted run's.
            const std::string prefix = "." + dir_.filename().string() + ".staging-";
            std::error_code ec;
            for (const auto& e : fs::directory_iterator(dir_.parent_path(), ec)) {
              const std::string name = e.path().filename().string();
              if (name.rfind(prefix, 0) == 0) fs::remove_all(e.path(), ec);
            }
            std::string pattern = beside(dir_, ".staging-XXXXXX").string();
            if (!::mkdtemp(pattern.data()))
              throw IOError("cannot create a staging folder beside " + dir_.string() + ": " + std::strerror(errno));
            return fs::path(pattern);
          },
          true) {}

void StagedFolder::commit() {
  const fs::path& staging = staging_.path();
  if (::chmod(staging.c_str(), folder_mode(dir_)) != 0)
    throw IOError("cannot set the permissions of " + staging.string() + ": " + std::strerror(errno));
  struct stat st;
  if (::lstat(dir_.c_str(), &st) != 0) {
    if (::rename(staging.c_str(), dir_.c_str()) != 0)
      throw IOError("cannot rename " + staging.string() + " to " + dir_.string() + ": " + std::strerror(errno));
    staging_.release();
    return;
  }
  // One step: the old result moves to the staging name, from where it is removed.
  if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) == 0) {
    staging_.remove();
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
    throw IOError("cannot put " + staging.string() + " in place of " + dir_.string() + ": " + std::strerror(errno));
  // A file system without RENAME_EXCHANGE: two renames; the old result waits under a staging name
  // (removed by the next run) for the moment between them.
  const fs::path aside = staging.string() + ".old";
  if (::rename(dir_.c_str(), aside.c_str()) != 0)
    throw IOError("cannot move " + dir_.string() + " aside: " + std::strerror(errno));
  if (::rename(staging.c_str(), dir_.c_str()) != 0) {
    const int e = errno;
    ::rename(aside.c_str(), dir_.c_str());
    throw IOError("cannot rename " + staging.string() + " to " + dir_.string() + ": " + std::strerror(e));
  }
  staging_.release();
  std::error_code ec;
  fs::remove_all(aside, ec);
}

}  // namespace thermodec
