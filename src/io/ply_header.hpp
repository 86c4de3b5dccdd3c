#pragma once
// The header of a PLY file: format, elements and their properties (the body is read by ply_reader.hpp).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace poreshell::ply {

enum class Format : std::uint8_t { ascii, binary_little_endian, binary_big_endian };

enum class ScalarType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

// Size in a binary file.
std::size_t scalar_bytes(ScalarType type);

struct Property {
  std::string name;
  ScalarType type = ScalarType::float32;  // of the items, for a list
  bool is_list = false;
  ScalarType count_type = ScalarType::uint8;  // lists only
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;

  const Property* find(const std::string& property) const;
  // Bytes of one row in a binary file; nothing when a list makes rows vary.
  std::optional<std::size_t> row_bytes() const;
};

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;  // in file order, which is the order of the data
  std::size_t bytes = 0;          // length of the header, up to and including the end_header line

  const Element* find(const std::string& element) const;
};

// Reads the header at the start of `bytes`; `bytes` is the offset of the first byte of data. Throws
// InputError, naming the file `name`, for a file that is not PLY or whose header is malformed.
Header read_header(std::string_view bytes, const std::string& name);

}  // namespace poreshell::ply
