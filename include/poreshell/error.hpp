#pragma once
// The one error type of the library. Its message says what is wrong and what to do; an option is
// named by its API name in backquotes (`hole_diameter`), which front ends may map to their own names
// (the CLI writes --hole-diameter).

#include <stdexcept>
#include <string>
#include "poreshell/export.hpp"

namespace poreshell {

enum class ErrorCode {
  invalid_option,  // an option out of range or inconsistent with another: option() names it
  invalid_input,   // the input mesh, point cloud or file cannot be used
  too_large,       // the run would not fit in memory or the grid limits
  cancelled,       // the cancel flag was set or the progress callback threw
  out_of_time,     // the run passed RunControl::max_seconds
  io,              // a file could not be read or written
  internal,        // a failure of the program (please report it)
};

class PORESHELL_API Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message, std::string option = {})
      : std::runtime_error(message), code_(code), option_(std::move(option)) {}
  ErrorCode code() const { return code_; }
  // The API name of the option at fault (empty when no single option is).
  const std::string& option() const { return option_; }

 private:
  ErrorCode code_;
  std::string option_;
};

}  // namespace poreshell
