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

// Raised inside the engine when its cancellation flag is set.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace isocorr
