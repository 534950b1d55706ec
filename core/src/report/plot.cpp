#include "thermodec/report/plot.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <cctype>
#include <fcntl.h>
#include <sstream>
#include <unistd.h>

#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"
#include "thermodec/common/interrupt_cleanup.h"

namespace thermodec {
namespace fs = std::filesystem;

fs::path plot_scripts_dir() {
  if (const char* env = std::getenv("THERMODEC_PLOTS_DIR")) return env;
#ifdef THERMODEC_SOURCE_PLOTS_DIR
  if (fs::exists(THERMODEC_SOURCE_PLOTS_DIR)) return THERMODEC_SOURCE_PLOTS_DIR;
#endif
#ifdef THERMODEC_INSTALL_PLOTS_DIR
  return THERMODEC_INSTALL_PLOTS_DIR;
#else
  return {};
#endif
}

namespace {
std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}
}  // namespace

namespace {
// A private folder (mkdtemp, mode 0700) for the data file and the picture: nobody else can
// plant a symlink there, and the child never writes beside the user's files. Removed on every
// exit path, and on SIGINT/SIGTERM (common/interrupt_cleanup.h).
class PrivateTempDir {
 public:
  PrivateTempDir()
      : dir_(
            [] {
              std::string pattern = (fs::temp_directory_path() / "thermodec_plot_XXXXXX").string();
              if (!::mkdtemp(pattern.data()))
                throw IOError("cannot create a private temporary folder in " + fs::temp_directory_path().string());
              return fs::path(pattern);
            },
            true) {}
  const fs::path& path() const { return dir_.path(); }

 private:
  TemporaryPath dir_;
};

// Creates `path` exclusively (O_EXCL | O_NOFOLLOW: never through a planted link).
void write_exclusive(const fs::path& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) throw IOError("cannot create " + path.string());
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) {
      ::close(fd);
      throw IOError("cannot write " + path.string());
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) throw IOError("cannot write " + path.string());
}
}  // namespace

void plot_png(const std::string& kind, const nlohmann::json& data, const fs::path& png_path) {
  // Pictures are PNG: another extension would get PNG bytes under a misleading name.
  std::string ext = png_path.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png") throw InvalidInput(png_path.string() + ": plots are PNG files; the name must end in .png");
  // note: Debian's python3, not whatever python3 is first on PATH: only it has matplotlib.
  const fs::path python = fs::exists("/usr/bin/python3") ? fs::path("/usr/bin/python3") : fs::path("python3");
  const fs::path script = plot_scripts_dir() / (kind + ".py");
  if (!fs::exists(script)) throw IOError("plot script not found: " + script.string());
  const PrivateTempDir tmp;
  const fs::path data_file = tmp.path() / "data.json", picture = tmp.path() / "plot.png";
  write_exclusive(data_file, data.dump());
  const std::string cmd = "MPLBACKEND=Agg " + shell_quote(python.string()) + " " +
                          shell_quote(script.string()) + " " + shell_quote(data_file.string()) + " " +
                          shell_quote(picture.string()) + " 2>&1";
  std::string output;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) throw IOError("cannot run " + python.string());
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), buf.size(), p)) output += buf.data();
  const int status = ::pclose(p);
  if (status != 0) throw IOError("plot '" + kind + "' failed: " + output);
  std::ifstream in(picture, std::ios::binary);
  if (!in) throw IOError("plot '" + kind + "' wrote no picture: " + output);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  write_text_atomically(png_path, bytes.str());
}

}  // namespace thermodec
