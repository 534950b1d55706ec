#include "thermodec/common/output_paths.h"

#include <algorithm>
#include <cctype>
#include <unistd.h>

#include "thermodec/common/atomic_write.h"
#include "thermodec/common/errors.h"

namespace thermodec {
namespace fs = std::filesystem;

void check_output_file(const fs::path& path, const std::string& what, const std::vector<std::string>& extensions,
                       const std::vector<fs::path>& inputs) {
  const std::string p = path.string();
  if (p.empty()) throw InvalidInput(what + ": empty output path");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InvalidInput(what + " " + p + ": is a folder; give a file name");
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (!extensions.empty() && std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) {
    std::string list;
    for (const auto& e : extensions) list += (list.empty() ? "" : ", ") + e;
    throw InvalidInput(what + " " + p + ": unknown output extension '" + ext + "' (expected " + list + ")");
  }
  if (!path.has_filename() || path.filename() == "." || path.filename() == "..")
    throw InvalidInput(what + " " + p + ": not a file name");
  if (extensions.empty() && ext.empty())
    throw InvalidInput(what + " " + p + ": no file extension; give the output a name with one");
  try {
    check_replaceable_output(path);
  } catch (const InvalidInput& e) {
    throw InvalidInput(what + " " + e.what());
  }
  for (const auto& in : inputs)
    if (!in.empty() && same_file(path, in)) throw InvalidInput(what + " " + p + ": is an input of this command; refusing to overwrite it");
  // The nearest existing ancestor must be a writable folder (missing folders are created).
  fs::path parent = fs::absolute(path, ec).parent_path();
  while (!parent.empty() && !fs::exists(parent, ec) && parent != parent.parent_path()) parent = parent.parent_path();
  if (!fs::is_directory(parent, ec)) throw InvalidInput(what + " " + p + ": " + parent.string() + " is not a folder");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InvalidInput(what + " " + p + ": folder " + parent.string() + " is not writable");
}

void check_output_folder(const fs::path& dir, const std::vector<std::string>& own_files, const std::vector<fs::path>& inputs) {
  std::error_code ec;
  const std::string d = dir.string();
  if (!fs::exists(dir, ec)) {
    fs::path parent = fs::absolute(dir, ec).parent_path();
    while (!parent.empty() && !fs::exists(parent, ec) && parent != parent.parent_path()) parent = parent.parent_path();
    if (!fs::is_directory(parent, ec)) throw InvalidInput("output folder " + d + ": " + parent.string() + " is not a folder");
    if (::access(parent.c_str(), W_OK | X_OK) != 0) throw InvalidInput("output folder " + d + ": " + parent.string() + " is not writable");
    return;
  }
  if (!fs::is_directory(dir, ec)) throw InvalidInput("output folder " + d + ": exists and is not a folder");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) throw InvalidInput("output folder " + d + ": not writable");
  // The new result is staged beside the folder and swapped in (common/staged_folder.h).
  fs::path whole = fs::absolute(dir, ec).lexically_normal();
  if (!whole.has_filename()) whole = whole.parent_path();  // "out/"
  const fs::path parent = whole.parent_path();
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InvalidInput("output folder " + d + ": its parent " + parent.string() +
                       " is not writable (the result is written beside the folder and swapped in)");
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (std::find(own_files.begin(), own_files.end(), name) == own_files.end())
      throw InvalidInput("output folder " + d + ": not empty and not an earlier thermodec output ('" + name +
                         "' is not one of its files); choose a new or empty folder");
  }
  for (const auto& in : inputs)
    for (const auto& name : own_files)
      if (!in.empty() && same_file(dir / name, in))
        throw InvalidInput("output folder " + d + ": its " + name + " is an input of this command; refusing to overwrite it");
}

void clear_own_outputs(const fs::path& dir, const std::vector<std::string>& own_files) {
  for (const auto& name : own_files) {
    std::error_code ec;
    const fs::path p = dir / name;
    if (fs::is_regular_file(fs::symlink_status(p, ec)) || fs::is_symlink(fs::symlink_status(p, ec))) {
      fs::remove(p, ec);
      if (ec) throw IOError(p.string() + ": cannot remove an earlier output: " + ec.message());
    }
  }
}

}  // namespace thermodec
