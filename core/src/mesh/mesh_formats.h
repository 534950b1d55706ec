#pragma once
// Private to core/src/mesh: one parser and one writer per format, plus the small text and
// number helpers they share. read_mesh/write_mesh (io.cpp) do the format-independent work:
// file access, welding, degenerate faces, atomic writes.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "thermodec/common/errors.h"
#include "thermodec/common/printable.h"
#include "thermodec/mesh/mesh.h"

namespace thermodec::mesh_formats {

// Parsers return triangles with every per-face vector sized #F (-1 = none), unwelded.
// `file` is only used in error messages.
Mesh parse_obj(std::string_view data, const std::string& file);
Mesh parse_ply(std::string_view data, const std::string& file);
Mesh parse_stl(std::string_view data, const std::string& file);
Mesh parse_bdf(std::string_view data, const std::string& file);  // NASTRAN bulk data (format_bdf.cpp)

void write_obj(std::ostream& out, const Mesh& mesh);
void write_ply(std::ostream& out, const Mesh& mesh, bool binary);
void write_stl(std::ostream& out, const Mesh& mesh, bool binary);

// Per-face attribute or -1 when the vector is absent (meshes built in code may leave them empty).
inline int face_attribute(const Eigen::VectorXi& values, int f) {
  return values.size() > f ? values[f] : -1;
}

// Splits `data` into lines, counting them from 1; handles \n, \r\n and \r.
class LineReader {
 public:
  explicit LineReader(std::string_view data) : data_(data) {}
  bool next(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    std::size_t end = pos_;
    while (end < data_.size() && data_[end] != '\n' && data_[end] != '\r') ++end;
    line = data_.substr(pos_, end - pos_);
    if (end < data_.size() && data_[end] == '\r' && end + 1 < data_.size() && data_[end + 1] == '\n') ++end;
    pos_ = std::min(end + 1, data_.size());
    ++line_number_;
    return true;
  }
  int line_number() const { return line_number_; }
  std::size_t position() const { return pos_; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  int line_number_ = 0;
};

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (is_space(s.front()) || s.front() == '\r' || s.front() == '\n')) s.remove_prefix(1);
  while (!s.empty() && (is_space(s.back()) || s.back() == '\r' || s.back() == '\n')) s.remove_suffix(1);
  return s;
}

inline void split_words_into(std::string_view s, std::vector<std::string_view>& words) {
  words.clear();
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    std::size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    if (j > i) words.push_back(s.substr(i, j - i));
    i = j;
  }
}

inline std::vector<std::string_view> split_words(std::string_view s) {
  std::vector<std::string_view> words;
  split_words_into(s, words);
  return words;
}

// Locale-independent number parsing (a Qt host may have set a decimal comma).
inline bool parse_double(std::string_view s, double& value) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range) {
    value = (!s.empty() && s.front() == '-') ? -HUGE_VAL : HUGE_VAL;  // reported as non-finite
    return ptr == s.data() + s.size();
  }
  return ec == std::errc() && ptr == s.data() + s.size();
}

inline bool parse_long(std::string_view s, long long& value) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// A word of the file quoted in a message: control bytes escaped, at most 40 bytes shown (a
// binary file or a 1 MB field must not reach the terminal as it is).
inline std::string field_text(std::string_view word) { return "'" + printable(word, 40) + "'"; }

inline InvalidInput line_error(const std::string& file, int line, const std::string& what) {
  return InvalidInput(file + ":" + std::to_string(line) + ": " + what);
}

inline InvalidInput file_error(const std::string& file, const std::string& what) {
  return InvalidInput(file + ": " + what);
}

// Names become whole OBJ lines or PLY comment tails, so they must be one trimmed line.
inline void check_name_writable(const std::string& name, const char* kind) {
  if (name.empty() || name.find_first_of("\r\n") != std::string::npos || trim(name) != name)
    throw InvalidInput(std::string("cannot write ") + kind + " name '" + name +
                       "': names must be non-empty, one line, without leading/trailing spaces");
}

}  // namespace thermodec::mesh_formats
