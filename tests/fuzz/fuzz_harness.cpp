#include "fuzz_harness.h"

#include "common/scratch_dir.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <typeinfo>

#include "thermodec/common/errors.h"
#include "thermodec/common/printable.h"
#include "thermodec/mesh/geometry_range.h"

namespace thermodec::fuzz {
namespace fs = std::filesystem;

std::uint64_t Rng::next() {
  std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

namespace {

// Inputs never grow past this: a reader's cost on a big file is not what the fuzzer looks at.
constexpr std::size_t kMaxInputBytes = 1 << 20;

// Tokens spliced in or replacing a number: what a number parser, an index check or a size
// check can get wrong.
const std::vector<std::string>& tokens() {
  static const std::vector<std::string> t = {
      "nan", "-nan", "NaN", "inf", "-inf", "Infinity", "1e308", "-1e308", "1e309", "1e-400", "4.9e-324",
      "99999999999999999999", "2147483647", "2147483648", "-2147483648", "-2147483649", "4294967295",
      "4294967296", "9223372036854775807", "-9223372036854775808", "18446744073709551616", "0", "-0", "-1",
      "1", "3", "0x1p3", "1.5-3", "7.+2", "1D5", "+", "-", ".", "e", "", " ", "\n", "\r\n", "\r", "\t",
      "/", "//", ",", ",,", "*", "$", "\"", "\\", "{", "}", "[", "]", ":", "null", "true", "\\u0000",
      std::string(1, '\0'), std::string(300, '9'), std::string(5000, ' '), "f 1 2 3\n", "f -1 -2 -3\n",
      "f 0 0 0\n", "v 0 0 0\n", "v 1e308 1e308 1e308\n", "g \n", "o x\n", "usemtl\n", "#thermodec back_material x\n",
      "element vertex 4294967295\n", "element face 2147483647\n", "property list uchar int vertex_indices\n",
      "property list int int vertex_indices\n", "property double quality\n", "format binary_big_endian 1.0\n",
      "end_header\n", "solid x\n", "facet normal 0 0 0\n", "outer loop\n", "vertex 1 2 3\n", "endloop\n",
      "endfacet\n", "endsolid\n", "GRID", "GRID*", "CTRIA3", "CQUAD4", "PSHELL", "RADM", "INCLUDE 'x'\n",
      "BEGIN BULK\n", "ENDDATA\n", "GRID,1,,0.,0.,0.\n", "CTRIA3,9,1,1,2,3\n", "$ thermodec node 1 \n",
  };
  return t;
}

bool is_number_char(char c) { return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+'; }

// Start and end (past the newline) of the line holding byte i.
std::pair<std::size_t, std::size_t> line_at(const std::string& s, std::size_t i) {
  std::size_t a = s.rfind('\n', i == 0 ? 0 : i - 1);
  a = (a == std::string::npos || i == 0) ? 0 : a + 1;
  std::size_t b = s.find('\n', i);
  b = b == std::string::npos ? s.size() : b + 1;
  return {a, b};
}

void mutate_once(std::string& s, const std::vector<std::string>& corpus, Rng& rng) {
  const std::size_t n = s.size();
  const std::size_t i = rng.below(n + 1);
  switch (rng.below(13)) {
    case 0:  // bit flip
      if (n) s[rng.below(n)] ^= static_cast<char>(1u << rng.below(8));
      break;
    case 1:  // a byte that matters to a text parser
      if (n) s[rng.below(n)] = "\0\xff\n\r\t ,/-.#*+$e"[rng.below(15)];
      break;
    case 2:  // cut a span
      if (i < n) s.erase(i, 1 + rng.below(64));
      break;
    case 3:  // truncate
      s.resize(i);
      break;
    case 4:  // insert a token
      s.insert(i, tokens()[rng.below(tokens().size())]);
      break;
    case 5: {  // replace the number at or after i with a token
      std::size_t a = i;
      while (a < n && !is_number_char(s[a])) ++a;
      std::size_t b = a;
      while (b < n && is_number_char(s[b])) ++b;
      if (a < n) s.replace(a, b - a, tokens()[rng.below(30)]);
      break;
    }
    case 6: {  // duplicate a line, elsewhere
      if (!n) break;
      const auto [a, b] = line_at(s, rng.below(n));
      const std::string line = s.substr(a, b - a);
      s.insert(line_at(s, rng.below(n)).first, line);
      break;
    }
    case 7: {  // delete a line
      if (!n) break;
      const auto [a, b] = line_at(s, rng.below(n));
      s.erase(a, b - a);
      break;
    }
    case 8: {  // swap two lines
      if (!n) break;
      auto [a1, b1] = line_at(s, rng.below(n));
      auto [a2, b2] = line_at(s, rng.below(n));
      if (a1 > a2) std::swap(a1, a2), std::swap(b1, b2);
      if (b1 > a2) break;
      const std::string l1 = s.substr(a1, b1 - a1), l2 = s.substr(a2, b2 - a2);
      s.replace(a2, b2 - a2, l1);
      s.replace(a1, b1 - a1, l2);
      break;
    }
    case 9: {  // an extreme 32-bit integer (binary counts and indices)
      static const std::uint32_t values[] = {0u, 1u, 3u, 0x7fffffffu, 0x80000000u, 0xffffffffu, 0x40000000u, 0xfffffffeu, 0x01000000u};
      const std::uint32_t v = values[rng.below(sizeof values / sizeof values[0])];
      if (n >= 4) std::memcpy(&s[rng.below(n - 3)], &v, 4);
      break;
    }
    case 10: {  // a non-finite or extreme float / double (binary coordinates)
      if (rng.chance(0.5) && n >= 4) {
        const float values[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -3.4e38f, 1e-45f};
        std::memcpy(&s[rng.below(n - 3)], &values[rng.below(4)], 4);
      } else if (n >= 8) {
        const double values[] = {std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity(), 1.7e308, 5e-324};
        std::memcpy(&s[rng.below(n - 7)], &values[rng.below(4)], 8);
      }
      break;
    }
    case 11: {  // splice: this input's head, another's tail
      const std::string& other = corpus[rng.below(corpus.size())];
      s = s.substr(0, i) + other.substr(rng.below(other.size() + 1));
      break;
    }
    default: {  // repeat a span
      if (i >= n) break;
      const std::string span = s.substr(i, 1 + rng.below(128));
      std::string rep;
      for (std::size_t k = 2 + rng.below(63); k > 0; --k) rep += span;
      s.insert(i, rep);
      break;
    }
  }
  if (s.size() > kMaxInputBytes) s.resize(kMaxInputBytes);
}

double env_number(const char* name, double fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* end = nullptr;
  const double x = std::strtod(v, &end);
  return end && *end == '\0' && x > 0.0 ? x : fallback;
}

// std::cerr silenced for the lifetime of the object.
class QuietCerr {
 public:
  QuietCerr() : old_(std::cerr.rdbuf(null_.rdbuf())) {}
  ~QuietCerr() { std::cerr.rdbuf(old_); }

 private:
  std::ostringstream null_;
  std::streambuf* old_;
};

}  // namespace

std::string mutate(const std::string& input, const std::vector<std::string>& corpus, Rng& rng) {
  std::string s = input;
  for (std::size_t k = 1 + rng.below(4); k > 0; --k) mutate_once(s, corpus, rng);
  return s;
}

FuzzRun fuzz_reader(const std::vector<std::string>& corpus, const fs::path& dir, const std::string& file_name,
                    int iterations, std::uint64_t seed, const Reader& reader) {
  FuzzRun run;
  Rng rng(seed);
  const int total = static_cast<int>(std::lround(iterations * env_number("THERMODEC_FUZZ_SCALE", 1.0)));
  const double budget_s = env_number("THERMODEC_FUZZ_SECONDS", 20.0);
  const auto start = std::chrono::steady_clock::now();
  const fs::path path = dir / file_name;
  QuietCerr quiet;
  for (int it = 0; it < total && run.failures.size() < 5; ++it) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > budget_s) break;
    // Every 16th input is a corpus file as it is: the valid ones must read.
    const std::string& base = corpus[rng.below(corpus.size())];
    const std::string input = it % 16 == 0 ? base : mutate(base, corpus, rng);
    write_bytes(path, input);
    ++run.iterations;
    std::string failure;
    try {
      const std::string problem = reader(path, it);
      if (problem.empty()) ++run.parsed;
      else failure = "read but invalid: " + problem;
    } catch (const thermodec::Error&) {
      ++run.refused;
    } catch (const std::exception& e) {
      failure = std::string("threw ") + typeid(e).name() + ": " + e.what();
    } catch (...) {
      failure = "threw a non-standard exception";
    }
    if (failure.empty()) continue;
    const fs::path kept = dir / ("failure_" + std::to_string(it) + "_" + file_name);
    write_bytes(kept, read_bytes(path));  // what the reader read (it may write its own input)
    run.failures.push_back("iteration " + std::to_string(it) + ": " + failure + " (input kept at " + kept.string() + ")");
  }
  return run;
}

std::vector<std::string> corpus_failures(const std::vector<std::string>& corpus, const fs::path& dir,
                                         const std::string& file_name, const Reader& reader) {
  QuietCerr quiet;
  std::vector<std::string> out;
  for (std::size_t k = 0; k < corpus.size(); ++k) {
    write_bytes(dir / file_name, corpus[k]);
    try {
      const std::string problem = reader(dir / file_name, 3);
      if (!problem.empty()) out.push_back("corpus file " + std::to_string(k) + " is invalid: " + problem);
    } catch (const std::exception& e) {
      out.push_back("corpus file " + std::to_string(k) + " is refused: " + e.what());
    }
  }
  return out;
}

std::string mesh_problem(const Mesh& m) {
  const int nv = m.num_vertices(), nf = m.num_faces();
  if (nv > 0 && m.V.cols() != 3) return "V has " + std::to_string(m.V.cols()) + " columns";
  if (nf > 0 && m.F.cols() != 3) return "F has " + std::to_string(m.F.cols()) + " columns";
  if (!m.V.allFinite()) return "a non-finite coordinate";
  if (m.V.size() > 0 && m.V.cwiseAbs().maxCoeff() > kMaxCoordinate) return "a coordinate beyond ±1e12 (areas overflow)";
  for (const auto* names : {&m.node_names, &m.material_names})
    for (const auto& n : *names)
      if (has_control_characters(n)) return "a name with control characters: " + printable(n);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (m.F(f, k) < 0 || m.F(f, k) >= nv) return "face " + std::to_string(f) + " has vertex " + std::to_string(m.F(f, k));
  if (m.face_node.size() != nf || m.face_material.size() != nf || m.face_back_material.size() != nf)
    return "per-face attributes are not sized #F";
  const int nodes = static_cast<int>(m.node_names.size()), materials = static_cast<int>(m.material_names.size());
  for (int f = 0; f < nf; ++f) {
    if (m.face_node[f] < -1 || m.face_node[f] >= nodes) return "face " + std::to_string(f) + " has node " + std::to_string(m.face_node[f]);
    if (m.face_material[f] < -1 || m.face_material[f] >= materials || m.face_back_material[f] < -1 ||
        m.face_back_material[f] >= materials)
      return "face " + std::to_string(f) + " has a material out of range";
  }
  return {};
}

fs::path work_dir(const std::string& name) {
  // Memory-backed when there is one: every input is a file written and read back.
  std::error_code ec;
  const char* tmpdir = std::getenv("TMPDIR");
  const fs::path base = (!tmpdir || !*tmpdir) && fs::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0
                            ? fs::path("/dev/shm")
                            : fs::temp_directory_path();
  return thermodec::test::scratch_dir_in(base, "thermodec_fuzz", name);
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string report(const FuzzRun& run) {
  std::string s = std::to_string(run.iterations) + " inputs: " + std::to_string(run.parsed) + " read, " +
                  std::to_string(run.refused) + " refused";
  for (const auto& f : run.failures) s += "\n  " + f;
  return s;
}

}  // namespace thermodec::fuzz
