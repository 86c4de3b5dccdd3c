#pragma once
// Error types. InputError: the user can fix it (bad parameter, bad file); the CLI maps it to a
// clear message. Anything else is a failure of the program.

#include <stdexcept>
#include <string>

namespace poreshell {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace poreshell
