#pragma once
//! Outputs are written atomically: into a temporary file beside the target, then renamed,
//! so a crash or a full disk never leaves a half-written file under the final name.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace thermodec {

class TemporaryPath;

//! Calls `write(stream)` on a temporary file next to `path`, flushes it to disk, then renames
//! it to `path`. Creates missing parent folders. The temporary `.NAME.tmp-XXXXXX` is created
//! exclusively under an unpredictable name (mkstemp: a planted symlink is never followed) and
//! removed on failure and on SIGINT/SIGTERM (common/interrupt_cleanup.h). An existing output
//! keeps its permission bits; a new one gets 0666 minus the umask.
//! \throw IOError if the file cannot be written or renamed (the temporary is removed).
//! \throw InvalidInput if `path` is one of `protected_inputs` (inputs are never overwritten),
//! or exists and is not a regular file (check_replaceable_output).
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write,
                           const std::vector<std::filesystem::path>& protected_inputs = {});

//! Refuses an existing `path` that is a folder, a device, a FIFO or a socket (a symlink is
//! judged by its target): renaming over it would replace it by a regular file.
//! \throw InvalidInput naming the path.
void check_replaceable_output(const std::filesystem::path& path);

//! Same, for a string payload.
void write_text_atomically(const std::filesystem::path& path, const std::string& text,
                           const std::vector<std::filesystem::path>& protected_inputs = {});

//! Files that belong together (a CSV export's three tables, a VTK series) written as one: each
//! is written in full to its temporary by `add`; `commit` renames them all into place, so an
//! earlier set is replaced only once every new file is complete. Temporaries not committed are
//! removed.
class AtomicFileSet {
 public:
  AtomicFileSet();
  ~AtomicFileSet();
  AtomicFileSet(const AtomicFileSet&) = delete;
  AtomicFileSet& operator=(const AtomicFileSet&) = delete;
  //! As write_file_atomically, without the rename. \throw as write_file_atomically.
  void add(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write,
           const std::vector<std::filesystem::path>& protected_inputs = {});
  //! Renames every added file into place, in the order added; returns their paths.
  //! \throw IOError if a rename fails.
  std::vector<std::filesystem::path> commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::unique_ptr<TemporaryPath>>> staged_;
};

//! True if both paths name the same existing file (or the same path once made absolute).
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace thermodec
