#pragma once
// A deterministic mutation fuzzer for the file readers (gcc has no libFuzzer): seeded byte
// mutations of a corpus of valid files (bit flips, cuts, truncations, huge and non-finite
// numbers, duplicated and swapped lines, extreme binary counts, splices of two files) are
// written to a file and handed to a reader in-process. Every outcome must be a valid result or
// a thermodec::Error; anything else (another exception type, a result that breaks its own
// invariants) fails the test and keeps the input for replay. A crash fails the test too, and
// under the sanitizers (tests/sanitize) so does any memory error or undefined behaviour.
//
// THERMODEC_FUZZ_SCALE (environment, default 1) multiplies the iterations; a run also stops
// after THERMODEC_FUZZ_SECONDS (default 20) so that a slow build stays bounded.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "thermodec/mesh/mesh.h"

namespace thermodec::fuzz {

//! SplitMix64: tiny, fast, and the same sequence on every platform (unlike std distributions).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  std::size_t below(std::size_t n) { return n ? static_cast<std::size_t>(next() % n) : 0; }
  bool chance(double p) { return (next() >> 11) * 0x1.0p-53 < p; }

 private:
  std::uint64_t state_;
};

//! 1 to 4 mutations of `input`; `corpus` supplies splices. Binary-aware mutations (extreme
//! 32-bit counts, NaN floats) apply to every input: text readers must survive them too.
std::string mutate(const std::string& input, const std::vector<std::string>& corpus, Rng& rng);

//! A reader under test: reads `path`, throws thermodec::Error to refuse it, and returns an
//! empty string if what it read is valid, else what is wrong with it.
using Reader = std::function<std::string(const std::filesystem::path& path, int iteration)>;

struct FuzzRun {
  int iterations = 0;  //!< inputs tried
  int parsed = 0;      //!< read as valid
  int refused = 0;     //!< refused with a thermodec::Error
  std::vector<std::string> failures;  //!< one line each: iteration, what happened, input kept at
};

//! Runs `reader` on `iterations` x THERMODEC_FUZZ_SCALE mutated inputs (seeded by `seed`), each
//! written to `work_dir / file_name` (the extension picks the format; `reader` may overwrite it with
//! an input of its own), stopping early after
//! THERMODEC_FUZZ_SECONDS or 5 failures. Failing inputs are kept in `work_dir`. std::cerr is
//! silenced meanwhile (readers warn about skipped cards and dropped faces).
FuzzRun fuzz_reader(const std::vector<std::string>& corpus, const std::filesystem::path& work_dir,
                    const std::string& file_name, int iterations, std::uint64_t seed, const Reader& reader);

//! What goes wrong reading each corpus file as it is (they must all be valid), quietly.
std::vector<std::string> corpus_failures(const std::vector<std::string>& corpus, const std::filesystem::path& work_dir,
                                         const std::string& file_name, const Reader& reader);

//! Empty if `mesh` is consistent (3 columns, indices in range, finite coordinates within
//! ±kMaxCoordinate, names without control characters, per-face
//! attributes sized #F and indexing their name tables), else the first problem found.
std::string mesh_problem(const Mesh& mesh);

//! A fresh folder under $TMPDIR, else /dev/shm, else the system temp folder.
std::filesystem::path work_dir(const std::string& name);

std::string read_bytes(const std::filesystem::path& path);
void write_bytes(const std::filesystem::path& path, const std::string& bytes);

//! A gtest message for `run`: the counts and the failures.
std::string report(const FuzzRun& run);

}  // namespace thermodec::fuzz
