#pragma once
//! Output paths checked before any work: a command that would fail to write its result after
//! a long run (an existing folder where a file goes, an unknown extension, an input in the
//! way) says so at once instead.
#include <filesystem>
#include <string>
#include <vector>

namespace thermodec {

//! Checks that `path` can receive an output file: its extension (lower case, with the dot) is
//! one of `extensions` (empty = any, but there must be one), it is not an existing folder,
//! device, FIFO or socket (check_replaceable_output), its parent is a folder
//! (or can be created: missing parents are created by the atomic writers) that is writable,
//! and it is none of `inputs`. `what` names the output in messages ("--json", "-o").
//! \throw InvalidInput naming the path and what is wrong.
void check_output_file(const std::filesystem::path& path, const std::string& what,
                       const std::vector<std::string>& extensions,
                       const std::vector<std::filesystem::path>& inputs);

//! Checks that `dir` can receive a command's outputs, whose file names are `own_files`: it
//! does not exist, or is an empty folder, or a folder holding only files of `own_files`
//! (an earlier run's outputs). Any input among `own_files` in `dir` is refused. Its parent must
//! be writable too: the result is staged beside it (common/staged_folder.h).
//! \throw InvalidInput naming the folder and the first foreign entry.
void check_output_folder(const std::filesystem::path& dir, const std::vector<std::string>& own_files,
                         const std::vector<std::filesystem::path>& inputs);

//! Removes the files of `own_files` present in `dir` (an earlier run's outputs), so a new run
//! never leaves stale results beside its own (e.g. old plots after `--no-plots`).
//! \throw IOError if one cannot be removed.
void clear_own_outputs(const std::filesystem::path& dir, const std::vector<std::string>& own_files);

}  // namespace thermodec
