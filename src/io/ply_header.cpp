#include "io/ply_header.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <sstream>
#include <utility>

#include "core/error.hpp"
#include "io/text_scan.hpp"

namespace poreshell::ply {
namespace {

// Both the names of the PLY paper and the sized aliases that numpy-based writers use.
std::optional<ScalarType> parse_scalar_type(const std::string& name) {
  static const std::array<std::pair<const char*, ScalarType>, 16> kTypes{{{"char", ScalarType::int8},
                                                                          {"int8", ScalarType::int8},
                                                                          {"uchar", ScalarType::uint8},
                                                                          {"uint8", ScalarType::uint8},
                                                                          {"short", ScalarType::int16},
                                                                          {"int16", ScalarType::int16},
                                                                          {"ushort", ScalarType::uint16},
                                                                          {"uint16", ScalarType::uint16},
                                                                          {"int", ScalarType::int32},
                                                                          {"int32", ScalarType::int32},
                                                                          {"uint", ScalarType::uint32},
                                                                          {"uint32", ScalarType::uint32},
                                                                          {"float", ScalarType::float32},
                                                                          {"float32", ScalarType::float32},
                                                                          {"double", ScalarType::float64},
                                                                          {"float64", ScalarType::float64}}};
  for (const auto& [text, type] : kTypes)
    if (name == text) return type;
  return std::nullopt;
}

// Throws for a malformed header line, with the line number: enough to find it in a text editor.
[[noreturn]] void bad_line(const std::string& path, std::size_t number, const std::string& what) {
  throw InputError(fmt::format(
      "PLY file '{}', header line {}: {}; the header is malformed, re-export the file", path, number, what));
}

ScalarType scalar_type(const std::string& name, const std::string& path, std::size_t number) {
  if (const auto type = parse_scalar_type(name)) return *type;
  bad_line(path, number, fmt::format("unknown property type '{}'", text::quote(name)));
}

Property parse_property(std::istringstream& words, const std::string& path, std::size_t number) {
  Property property;
  std::string type;
  words >> type;
  if (type == "list") {
    std::string count_type, item_type;
    words >> count_type >> item_type;
    property.is_list = true;
    property.count_type = scalar_type(count_type, path, number);
    property.type = scalar_type(item_type, path, number);
  } else {
    property.type = scalar_type(type, path, number);
  }
  if (!(words >> property.name)) bad_line(path, number, "a property without a name");
  return property;
}

Element parse_element(std::istringstream& words, const std::string& path, std::size_t number) {
  Element element;
  long long count = -1;
  if (!(words >> element.name >> count) || count < 0)
    bad_line(path, number, "expected 'element <name> <count>'");
  // Indices into the rows are 32-bit throughout poreshell.
  if (count > INT32_MAX)
    bad_line(path, number,
             fmt::format("{} rows of '{}' are more than poreshell reads (2^31 - 1)", count,
                         text::quote(element.name)));
  element.count = static_cast<std::size_t>(count);
  return element;
}

Format parse_format(std::istringstream& words, const std::string& path, std::size_t number) {
  std::string format;
  words >> format;
  if (format == "ascii") return Format::ascii;
  if (format == "binary_little_endian") return Format::binary_little_endian;
  if (format == "binary_big_endian") return Format::binary_big_endian;
  bad_line(path, number,
           fmt::format("unknown format '{}' (ascii, binary_little_endian or binary_big_endian)",
                       text::quote(format)));
}

}  // namespace

std::size_t scalar_bytes(ScalarType type) {
  switch (type) {
    case ScalarType::int8:
    case ScalarType::uint8:
      return 1;
    case ScalarType::int16:
    case ScalarType::uint16:
      return 2;
    case ScalarType::int32:
    case ScalarType::uint32:
    case ScalarType::float32:
      return 4;
    case ScalarType::float64:
      return 8;
  }
  return 0;
}

const Property* Element::find(const std::string& property) const {
  for (const Property& p : properties)
    if (p.name == property) return &p;
  return nullptr;
}

std::optional<std::size_t> Element::row_bytes() const {
  std::size_t bytes = 0;
  for (const Property& p : properties) {
    if (p.is_list) return std::nullopt;
    bytes += scalar_bytes(p.type);
  }
  return bytes;
}

const Element* Header::find(const std::string& element) const {
  for (const Element& e : elements)
    if (e.name == element) return &e;
  return nullptr;
}

Header read_header(std::string_view bytes, const std::string& path) {
  Header header;
  std::string line;
  const auto next_line = [&] {
    if (header.bytes >= bytes.size()) return false;
    const std::size_t end = bytes.find('\n', header.bytes);
    const std::size_t stop = end == std::string_view::npos ? bytes.size() : end;
    line.assign(bytes.substr(header.bytes, stop - header.bytes));
    header.bytes = end == std::string_view::npos ? bytes.size() : end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  if (!next_line() || line != "ply")
    throw InputError(fmt::format(
        "'{}' is not a PLY file (its first line is not 'ply'): give a PLY file, as Blender or MeshLab "
        "export it",
        path));
  bool has_format = false;
  for (std::size_t number = 2; next_line(); ++number) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") {
      if (!has_format) bad_line(path, number, "no 'format' line before end_header");
      return header;
    }
    if (keyword == "format") {
      header.format = parse_format(words, path, number);
      has_format = true;
    } else if (keyword == "element") {
      header.elements.push_back(parse_element(words, path, number));
    } else if (keyword == "property") {
      if (header.elements.empty()) bad_line(path, number, "a property before any element");
      header.elements.back().properties.push_back(parse_property(words, path, number));
    } else {
      bad_line(path, number, fmt::format("unexpected '{}'", text::quote(line, 60)));
    }
  }
  throw InputError(
      fmt::format("PLY file '{}' has no 'end_header' line: the file is truncated or its header is malformed; "
                  "re-export it",
                  path));
}

}  // namespace poreshell::ply
