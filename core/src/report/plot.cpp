#include "thermodec/report/plot.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <unistd.h>

#include "thermodec/common/errors.h"

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

void plot_png(const std::string& kind, const nlohmann::json& data, const fs::path& png_path) {
  // note: Debian's python3, not whatever python3 is first on PATH: only it has matplotlib.
  const fs::path python = fs::exists("/usr/bin/python3") ? fs::path("/usr/bin/python3") : fs::path("python3");
  const fs::path script = plot_scripts_dir() / (kind + ".py");
  if (!fs::exists(script)) throw IOError("plot script not found: " + script.string());
  const fs::path tmp = fs::temp_directory_path() /
                       ("thermodec_plot_" + std::to_string(::getpid()) + "_" + kind + ".json");
  {
    std::ofstream out(tmp);
    if (!out) throw IOError("cannot write " + tmp.string());
    out << data.dump();
  }
  fs::create_directories(png_path.has_parent_path() ? png_path.parent_path() : fs::path("."));
  const std::string cmd = "MPLBACKEND=Agg " + shell_quote(python.string()) + " " +
                          shell_quote(script.string()) + " " + shell_quote(tmp.string()) + " " +
                          shell_quote(png_path.string()) + " 2>&1";
  std::string output;
  if (FILE* p = ::popen(cmd.c_str(), "r")) {
    std::array<char, 512> buf{};
    while (std::fgets(buf.data(), buf.size(), p)) output += buf.data();
    const int status = ::pclose(p);
    std::error_code ec;
    fs::remove(tmp, ec);
    if (status != 0) throw IOError("plot '" + kind + "' failed: " + output);
  } else {
    throw IOError("cannot run " + python.string());
  }
}

}  // namespace thermodec
