#pragma once
//! Outputs are written atomically: into a temporary file beside the target, then renamed,
//! so a crash or a full disk never leaves a half-written file under the final name.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace thermodec {

//! Calls `write(stream)` on a temporary file next to `path`, flushes, then renames it to
//! `path`. Creates missing parent folders.
//! \throw IOError if the file cannot be written or renamed (the temporary is removed).
//! \throw InvalidInput if `path` is one of `protected_inputs` (inputs are never overwritten).
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write,
                           const std::vector<std::filesystem::path>& protected_inputs = {});

//! Same, for a string payload.
void write_text_atomically(const std::filesystem::path& path, const std::string& text,
                           const std::vector<std::filesystem::path>& protected_inputs = {});

//! True if both paths name the same existing file (or the same path once made absolute).
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

}  // namespace thermodec
