// toolpoint: typed exceptions. The library throws these and never prints or exits; the CLI's
// main maps each type to a message and an exit code (see docs/files.md, "Exit codes").
#pragma once

#include <stdexcept>
#include <string>

namespace toolpoint {

// Base of every toolpoint error. what(): what is wrong, with the values involved.
// hint(): one sentence on how to fix it (may be empty).
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what, std::string hint = {}) : std::runtime_error(what), hint_(std::move(hint)) {}
  const std::string& hint() const noexcept { return hint_; }

 private:
  std::string hint_;
};

// A parameter value outside its valid range (a negative length, ν outside (−1, 0.5), …).
// what() names the parameter and the value. CLI exit code 2.
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

// Malformed or inconsistent input data: a file that cannot be parsed, a missing or misspelt
// key, NaN in data, mismatched frequency grids. what() names the file, line or key. Exit code 3.
class InputError : public Error {
 public:
  using Error::Error;
};

// A computation that cannot give a trustworthy answer: a singular inversion, a root finder that
// does not converge. what() gives the frequency and the quantity involved. Exit code 4.
class NumericalError : public Error {
 public:
  using Error::Error;
};

// A result that was computed but fails its own checks (an identified joint with negative stiffness,
// a forward check off by more than the fail threshold): refusing it beats printing it. Exit code 6.
class VerdictFailure : public Error {
 public:
  using Error::Error;
};

// A file that cannot be opened, read or written. Exit code 5.
class IoError : public Error {
 public:
  using Error::Error;
};

}  // namespace toolpoint
