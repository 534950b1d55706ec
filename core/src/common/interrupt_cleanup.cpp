#include "thermodec/common/interrupt_cleanup.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>

namespace thermodec {
namespace fs = std::filesystem;
namespace {

struct Registry {
  std::mutex mutex;
  std::map<const TemporaryPath*, bool> live;  // guard -> removed with contents
  std::string program = "thermodec";
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: the watcher may use it during exit
  return *r;
}

void remove_path(const fs::path& p, bool folder) {
  std::error_code ec;
  if (folder) fs::remove_all(p, ec);
  else fs::remove(p, ec);
}

int g_wake_pipe[2] = {-1, -1};

// Async-signal-safe: only write(2); the watcher thread does the rest.
void on_signal(int sig) {
  const unsigned char b = static_cast<unsigned char>(sig);
  const int saved = errno;
  [[maybe_unused]] const ssize_t n = ::write(g_wake_pipe[1], &b, 1);
  errno = saved;
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    default: return "signal";
  }
}

void watch() {
  unsigned char sig = 0;
  while (::read(g_wake_pipe[0], &sig, 1) != 1) {
    if (errno != EINTR) return;
  }
  Registry& r = registry();
  r.mutex.lock();  // held until _exit: no temporary is created or renamed into place from here on
  for (const auto& [guard, folder] : r.live) remove_path(guard->path(), folder);
  const std::string message = r.program + ": interrupted (" + signal_name(sig) + "); temporary files removed\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, message.data(), message.size());
  ::_exit(128 + sig);
}

}  // namespace

TemporaryPath::TemporaryPath(const std::function<fs::path()>& create, bool folder) : folder_(folder) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  path_ = create();
  r.live[this] = folder;
  active_ = true;
}

TemporaryPath::~TemporaryPath() { remove(); }

void TemporaryPath::release() {
  if (!active_) return;
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.live.erase(this);
  active_ = false;
}

void TemporaryPath::remove() {
  if (!active_) return;
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  remove_path(path_, folder_);
  r.live.erase(this);
  active_ = false;
}

void remove_temporaries_on_interrupt(const std::string& program) {
  static std::once_flag once;
  std::call_once(once, [&] {
    registry().program = program;
    if (::pipe2(g_wake_pipe, O_CLOEXEC) != 0) return;  // no cleanup rather than no program
    std::thread(watch).detach();
    struct sigaction sa;
    std::memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
  });
}

}  // namespace thermodec
