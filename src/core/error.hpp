#pragma once
// The library's errors inside: all are poreshell::Error (include/poreshell/error.hpp). InputError:
// the input cannot be used; OptionError: an option is out of range, named by its API name. Anything
// else thrown is a failure of the program, reported as ErrorCode::internal.

#include <string>

#include "poreshell/error.hpp"

namespace poreshell {

class InputError : public Error {
 public:
  explicit InputError(const std::string& message) : Error(ErrorCode::invalid_input, message) {}
};

class OptionError : public Error {
 public:
  OptionError(const std::string& option, const std::string& message)
      : Error(ErrorCode::invalid_option, message, option) {}
};

class Cancelled : public Error {
 public:
  Cancelled() : Error(ErrorCode::cancelled, "the run was cancelled; nothing was written") {}
};

}  // namespace poreshell
