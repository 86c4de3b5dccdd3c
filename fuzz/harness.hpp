#pragma once
// What every harness shares: the fuzz input as bytes, and a rejection (InputError, or any
// std::runtime_error a reader lets through) counted as the normal answer to a bad file. Anything else,
// a crash, a sanitizer report, a leak, a timeout or running out of memory, is a finding.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "core/error.hpp"

namespace poreshell::fuzz {

template <class Read>
int run(const std::uint8_t* data, std::size_t size, Read read) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    read(bytes);
  } catch (const InputError&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}

}  // namespace poreshell::fuzz
