#pragma once
//! PNG plots for people. The core writes plain JSON; a small matplotlib script per plot kind
//! (core/share/plots/<kind>.py, run with Debian's /usr/bin/python3 which has
//! python3-matplotlib) turns it into a PNG. Plotting never decides anything: a failed plot is
//! reported and the JSON stays the result.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace thermodec {

//! Writes `data` to a temporary JSON file and runs `plots/<kind>.py DATA.json OUT.png`.
//! The PNG is written atomically by the script (temporary + rename).
//! \throw IOError if the interpreter or script is missing or the script fails (with its stderr).
void plot_png(const std::string& kind, const nlohmann::json& data,
              const std::filesystem::path& png_path);

//! Folder holding the plot scripts: $THERMODEC_PLOTS_DIR if set, else the source tree's
//! core/share/plots, else <prefix>/share/thermodec/plots.
std::filesystem::path plot_scripts_dir();

}  // namespace thermodec
