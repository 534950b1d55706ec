#pragma once
//! thermodec's error hierarchy. Every failure a user can cause is one of these, with a
//! one-line message naming the file, key, line or face at fault; `assert` guards internal
//! invariants only. The CLI maps them to exit code 1.
#include <stdexcept>
#include <string>

namespace thermodec {

//! Base of all thermodec errors.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

//! Bad user input: malformed file, NaN coordinate, unknown node or material, impossible
//! option (negative tolerance, rays_per_face < 1, ...).
struct InvalidInput : Error {
  using Error::Error;
};

//! A file could not be read or written.
struct IOError : Error {
  using Error::Error;
};

//! A solver did not converge or the problem has no solution (e.g. a node with no path to a
//! heat sink in a steady analysis). The message says why.
struct SolverError : Error {
  using Error::Error;
};

}  // namespace thermodec
