#include "thermodec/common/atomic_write.h"

#include <fstream>
#include <system_error>
#include <unistd.h>

#include "thermodec/common/errors.h"

namespace thermodec {
namespace fs = std::filesystem;

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write,
                           const std::vector<fs::path>& protected_inputs) {
  for (const auto& in : protected_inputs)
    if (!in.empty() && same_file(path, in))
      throw InvalidInput("refusing to overwrite input file " + in.string() +
                         ": choose another output path");
  std::error_code ec;
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) throw IOError("cannot create folder " + parent.string() + ": " + ec.message());
  // note: the pid keeps concurrent writers (parallel trials) from sharing a temporary.
  const fs::path tmp = parent / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IOError("cannot write " + tmp.string());
    try {
      write(out);
    } catch (...) {
      out.close();
      fs::remove(tmp, ec);
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw IOError("write failed for " + path.string() + " (disk full?)");
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw IOError("cannot rename temporary onto " + path.string() + ": " + ec.message());
  }
}

void write_text_atomically(const fs::path& path, const std::string& text,
                           const std::vector<fs::path>& protected_inputs) {
  write_file_atomically(path, [&](std::ostream& o) { o << text; }, protected_inputs);
}

}  // namespace thermodec
