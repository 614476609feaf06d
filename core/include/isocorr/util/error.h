// Exceptions the engine throws; the CLI and the service map them to exit codes and statuses.
#pragma once

#include <stdexcept>
#include <string>

namespace isocorr {

// The input (a mesh file, a ground-truth file, a setting) is unusable; the message names
// the problem so that a user can fix it.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A computation met a value it cannot go on from (a non-finite intermediate, a solver that
// lost its footing). Raised instead of looping. An input the engine cannot compute with is
// unusable input, so it is an InputError to every caller.
class NumericalError : public InputError {
 public:
  using InputError::InputError;
};

// Raised inside the engine when its cancellation flag is set.
class Cancelled : public std::runtime_error {
 public:
  explicit Cancelled(const std::string& what = "cancelled") : std::runtime_error(what) {}
};

// Raised inside the engine when its deadline has passed: a cancellation nobody asked for, so
// the caller reports it as a failure of its own kind.
class DeadlineExceeded : public Cancelled {
 public:
  DeadlineExceeded() : Cancelled("the time limit ran out") {}
};

}  // namespace isocorr
