#include "thermodec/common/atomic_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <ostream>
#include <streambuf>
#include <system_error>

#include "thermodec/common/errors.h"
#include "thermodec/common/interrupt_cleanup.h"

namespace thermodec {
namespace fs = std::filesystem;
namespace {

// A write-only stream buffer over a file descriptor; a failed write(2) makes the stream bad
// and keeps its errno for the message.
class FdBuffer : public std::streambuf {
 public:
  explicit FdBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        error_ = n < 0 ? errno : ENOSPC;
        setp(buffer_, buffer_ + sizeof buffer_);
        return false;
      }
      p += n;
    }
    setp(buffer_, buffer_ + sizeof buffer_);
    return true;
  }
  int fd_;
  int error_ = 0;
  char buffer_[1 << 16];
};

mode_t current_umask() {
  const mode_t m = ::umask(022);
  ::umask(m);
  return m;
}

}  // namespace

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void check_replaceable_output(const fs::path& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) return;  // absent (or a dangling link, which rename replaces)
  if (S_ISDIR(st.st_mode)) throw InvalidInput(path.string() + ": is a folder; give a file name");
  if (!S_ISREG(st.st_mode))
    throw InvalidInput(path.string() + ": exists and is not a regular file (a device, FIFO or socket); "
                       "refusing to replace it: choose another output path");
}

namespace {

// The content written to a fresh temporary beside `path`, flushed to disk, with the mode the
// output is to have; the temporary is removed if anything fails.
std::unique_ptr<TemporaryPath> write_temporary(const fs::path& path, const std::function<void(std::ostream&)>& write,
                                               const std::vector<fs::path>& protected_inputs) {
  for (const auto& in : protected_inputs)
    if (!in.empty() && same_file(path, in))
      throw InvalidInput("refusing to overwrite input file " + in.string() +
                         ": choose another output path");
  check_replaceable_output(path);
  std::error_code ec;
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) throw IOError("cannot create folder " + parent.string() + ": " + ec.message());
  // An existing output keeps its permissions; a new one gets the usual 0666 & ~umask.
  struct stat old;
  const mode_t mode = ::stat(path.c_str(), &old) == 0 ? (old.st_mode & 07777 & ~mode_t(S_ISUID | S_ISGID))
                                                      : (0666 & ~current_umask());
  // note: mkstemp creates with O_CREAT | O_EXCL under an unpredictable name, so a link planted
  // in a shared folder is never followed and concurrent writers never share a temporary.
  int fd = -1;
  auto tmp = std::make_unique<TemporaryPath>(
      [&] {
        std::string pattern = (parent / ("." + path.filename().string() + ".tmp-XXXXXX")).string();
        fd = ::mkostemp(pattern.data(), O_CLOEXEC);
        if (fd < 0) throw IOError("cannot create a temporary file in " + parent.string() + ": " + std::strerror(errno));
        return fs::path(pattern);
      },
      false);
  int error = 0;
  {
    FdBuffer buffer(fd);
    std::ostream out(&buffer);
    try {
      write(out);
    } catch (...) {
      ::close(fd);
      throw;
    }
    out.flush();
    if (!out) error = buffer.error() ? buffer.error() : EIO;
  }
  if (!error && ::fchmod(fd, mode) != 0) error = errno;
  if (!error && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && !error) error = errno;
  if (error)
    throw IOError("write failed for " + path.string() + ": " + std::strerror(error) +
                  (error == ENOSPC || error == EDQUOT ? " (disk full)" : ""));
  return tmp;
}

void rename_into_place(TemporaryPath& tmp, const fs::path& path) {
  if (::rename(tmp.path().c_str(), path.c_str()) != 0)
    throw IOError("cannot rename temporary onto " + path.string() + ": " + std::strerror(errno));
  tmp.release();
}

}  // namespace

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write,
                           const std::vector<fs::path>& protected_inputs) {
  const auto tmp = write_temporary(path, write, protected_inputs);
  rename_into_place(*tmp, path);
}

AtomicFileSet::AtomicFileSet() = default;
AtomicFileSet::~AtomicFileSet() = default;

void AtomicFileSet::add(const fs::path& path, const std::function<void(std::ostream&)>& write,
                        const std::vector<fs::path>& protected_inputs) {
  staged_.emplace_back(path, write_temporary(path, write, protected_inputs));
}

std::vector<fs::path> AtomicFileSet::commit() {
  std::vector<fs::path> done;
  for (auto& [path, tmp] : staged_) {
    rename_into_place(*tmp, path);
    done.push_back(path);
  }
  staged_.clear();
  return done;
}

void write_text_atomically(const fs::path& path, const std::string& text,
                           const std::vector<fs::path>& protected_inputs) {
  write_file_atomically(path, [&](std::ostream& o) { o << text; }, protected_inputs);
}

}  // namespace thermodec
