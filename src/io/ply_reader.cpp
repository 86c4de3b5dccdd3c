#include "io/ply_reader.hpp"

// The body is walked row by row, element by element, through a cursor that reads one value of a given
// type (text tokens or binary, either byte order). Only the vertex and face elements are kept; other
// elements are read through and dropped, since binary rows have no markers to skip by. ASCII rows are
// one a line, as the format says: a row short of a value is refused with its line rather than completed
// from the next line, and so is one with values left over (issue 47). Data after the last element is
// refused too: the header's counts would then not describe the file.

#include <fmt/format.h>
#include <fmt/ranges.h>  // join

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>

#include "core/error.hpp"
#include "io/text_scan.hpp"

namespace poreshell::ply {
namespace {

// Thrown while reading rows; read_body turns them into InputErrors that say where the data went wrong.
struct EndOfData {};
struct BadValue {
  std::string what;
};

class AsciiCursor {
 public:
  AsciiCursor(std::string_view data, std::size_t first_line) : rest_(data), line_number_(first_line - 1) {}

  // Moves to the next line that holds a value (blank lines are passed over).
  void begin_row() {
    do {
      line_ = next_line();
    } while (blank(line_) && !rest_.empty());
  }
  double read(ScalarType /*type*/) {
    const std::string_view token = text::next_token(line_);
    if (token.empty()) {
      // The data's end is a truncated file; a line's end before the row's is a malformed row.
      if (blank(rest_)) throw EndOfData{};
      throw BadValue{
          fmt::format("line {} ends before the row does (the header's properties ask for more "
                      "values than the line has)",
                      line_number_)};
    }
    double value = 0.0;
    if (!text::parse_double(token, value))
      throw BadValue{fmt::format("'{}' is not a number (line {})", text::quote(token), line_number_)};
    return value;
  }
  void end_row() {
    const std::string_view extra = text::next_token(line_);
    if (!extra.empty())
      throw BadValue{fmt::format("line {} has values after the row's last property ('{}')", line_number_,
                                 text::quote(extra))};
  }
  // What is left after the last element: none, or where it starts.
  std::optional<std::string> leftover() {
    while (!rest_.empty() || !line_.empty()) {
      const std::string_view token = text::next_token(line_);
      if (!token.empty()) return fmt::format("'{}' on line {}", text::quote(token), line_number_);
      if (rest_.empty()) break;
      line_ = next_line();
    }
    return std::nullopt;
  }

 private:
  static bool blank(std::string_view text) { return text.find_first_not_of(" \t\r\n\v\f") == text.npos; }
  std::string_view next_line() {
    const std::size_t end = rest_.find('\n');
    const std::string_view line = rest_.substr(0, end);
    rest_.remove_prefix(end == std::string_view::npos ? rest_.size() : end + 1);
    ++line_number_;
    return line;
  }

  std::string_view rest_, line_;
  std::size_t line_number_;
};

class BinaryCursor {
 public:
  BinaryCursor(std::string_view data, bool big_endian)
      : rest_(data), swap_(big_endian != (std::endian::native == std::endian::big)) {}

  void begin_row() {}
  void end_row() {}
  std::optional<std::string> leftover() const {
    if (rest_.empty()) return std::nullopt;
    return fmt::format("{} bytes", rest_.size());
  }
  double read(ScalarType type) {
    const std::size_t n = scalar_bytes(type);
    if (rest_.size() < n) throw EndOfData{};
    unsigned char bytes[8];
    std::memcpy(bytes, rest_.data(), n);
    rest_.remove_prefix(n);
    if (swap_) std::reverse(bytes, bytes + n);
    switch (type) {
      case ScalarType::int8:
        return as<std::int8_t>(bytes);
      case ScalarType::uint8:
        return as<std::uint8_t>(bytes);
      case ScalarType::int16:
        return as<std::int16_t>(bytes);
      case ScalarType::uint16:
        return as<std::uint16_t>(bytes);
      case ScalarType::int32:
        return as<std::int32_t>(bytes);
      case ScalarType::uint32:
        return as<std::uint32_t>(bytes);
      case ScalarType::float32:
        return as<float>(bytes);
      case ScalarType::float64:
        return as<double>(bytes);
    }
    return 0.0;
  }

 private:
  template <class T>
  static double as(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof value);
    return static_cast<double>(value);
  }

  std::string_view rest_;
  bool swap_;
};

// Where the wanted properties sit in the rows of the vertex and face elements.
struct Layout {
  const Element* vertex = nullptr;
  const Element* face = nullptr;     // null without faces
  std::array<std::size_t, 3> xyz{};  // property positions in a vertex row
  std::optional<std::size_t> value;  // position of the requested property in a vertex row
  std::size_t indices = 0;           // position of the vertex index list in a face row
};

std::optional<std::size_t> position(const Element& element, const std::string& name) {
  for (std::size_t k = 0; k < element.properties.size(); ++k)
    if (element.properties[k].name == name && !element.properties[k].is_list) return k;
  return std::nullopt;
}

std::vector<std::string> scalar_names(const Element& element) {
  std::vector<std::string> names;
  for (const Property& p : element.properties)
    if (!p.is_list) names.push_back(text::quote(p.name));
  return names;
}

// Hints where the property is, when the file has it on another element (per-face quality, say).
std::string elsewhere(const Header& header, const std::string& property) {
  for (const Element& e : header.elements)
    if (e.name != "vertex" && e.find(property) != nullptr)
      return fmt::format(" (the file has it on its '{}' elements: transfer it to the vertices)",
                         text::quote(e.name));
  return "";
}

Layout find_layout(const Header& header, const std::string& name, const std::string& property) {
  Layout layout;
  layout.vertex = header.find("vertex");
  if (layout.vertex == nullptr || layout.vertex->count == 0)
    throw InputError(
        fmt::format("PLY file '{}' has no vertices (its header declares none): give a file "
                    "with an 'element vertex' of at least one row",
                    name));
  for (int a = 0; a < 3; ++a) {
    const std::string axis(1, static_cast<char>('x' + a));
    const auto k = position(*layout.vertex, axis);
    if (!k)
      throw InputError(fmt::format(
          "PLY file '{}': its vertices have no scalar '{}' coordinate; re-export the mesh", name, axis));
    layout.xyz[a] = *k;
  }
  if (!property.empty()) {
    layout.value = position(*layout.vertex, property);
    if (!layout.value)
      throw InputError(
          fmt::format("PLY file '{}' has no scalar vertex property '{}'{}; its scalar vertex properties are: "
                      "{}. Save the "
                      "field as a per-vertex property or name one of these",
                      name, text::quote(property), elsewhere(header, property),
                      fmt::join(scalar_names(*layout.vertex), ", ")));
  }
  layout.face = header.find("face");
  if (layout.face == nullptr || layout.face->count == 0) {
    layout.face = nullptr;
    return layout;
  }
  for (std::size_t k = 0; k < layout.face->properties.size(); ++k) {
    const Property& p = layout.face->properties[k];
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
      layout.indices = k;
      return layout;
    }
  }
  throw InputError(fmt::format(
      "PLY file '{}': its faces have no 'vertex_indices' list, so they cannot be read; re-export the mesh",
      name));
}

// The fewest bytes a row can take: binary, its scalars and list counts; ASCII, one character and one
// separator a value.
std::size_t min_row_bytes(const Element& element, Format format) {
  std::size_t bytes = 0;
  for (const Property& p : element.properties)
    bytes += format == Format::ascii ? 2 : scalar_bytes(p.is_list ? p.count_type : p.type);
  return bytes;
}

// A header that promises more rows than the data can hold is refused before anything is reserved, so a
// 200-byte file claiming 10^9 vertices costs nothing.
void check_counts(const Header& header, const Layout& layout, std::size_t data_bytes,
                  const std::string& name) {
  const Element* last = layout.face != nullptr && layout.face > layout.vertex ? layout.face : layout.vertex;
  double needed = 0.0;  // double: counts up to 2^31 times rows of a few hundred bytes
  for (const Element& element : header.elements) {
    needed += static_cast<double>(element.count) * static_cast<double>(min_row_bytes(element, header.format));
    // The last ASCII value needs no separator after it.
    if (needed > static_cast<double>(data_bytes) + 1.0)
      throw InputError(fmt::format(
          "PLY file '{}' is truncated or its header is wrong: the header promises {} '{}' entries, more than "
          "the {} bytes of data after it can hold; re-export the file",
          name, element.count, text::quote(element.name), data_bytes));
    if (&element == last) break;
  }
}

template <class Cursor>
std::size_t read_count(Cursor& cursor, ScalarType type) {
  const double n = cursor.read(type);
  if (!(n >= 0.0 && n <= INT32_MAX && n == std::floor(n)))
    throw BadValue{fmt::format("the list length {} is not a count", n)};
  return static_cast<std::size_t>(n);
}

// Reads a property and drops it. A lying list length ends in EndOfData: each item takes a byte at least.
template <class Cursor>
void skip(Cursor& cursor, const Property& p) {
  const std::size_t n = p.is_list ? read_count(cursor, p.count_type) : 1;
  for (std::size_t i = 0; i < n; ++i) cursor.read(p.type);
}

template <class Cursor>
void read_vertex(Cursor& cursor, const Layout& layout, Data& out) {
  Vec3 p = Vec3::Zero();
  double value = 0.0;
  const auto& properties = layout.vertex->properties;
  for (std::size_t k = 0; k < properties.size(); ++k) {
    if (properties[k].is_list) {
      skip(cursor, properties[k]);
      continue;
    }
    const double v = cursor.read(properties[k].type);
    for (int a = 0; a < 3; ++a)
      if (k == layout.xyz[a]) p[a] = v;
    if (k == layout.value) value = v;
  }
  out.vertices.push_back(p);
  if (layout.value) out.values.push_back(value);
}

template <class Cursor>
void read_face(Cursor& cursor, const Layout& layout, std::size_t row, const std::string& name, Data& out) {
  const auto& properties = layout.face->properties;
  for (std::size_t k = 0; k < properties.size(); ++k) {
    if (k != layout.indices) {
      skip(cursor, properties[k]);
      continue;
    }
    const std::size_t n = read_count(cursor, properties[k].count_type);
    if (n < 3)
      throw InputError(
          fmt::format("PLY file '{}': face {} (counting from 0) has {} vertices, and a face "
                      "needs at least 3; the file is corrupt, re-export it",
                      name, row, n));
    std::array<std::int32_t, 3> fan{};  // first, previous, current: a polygon becomes a fan
    for (std::size_t i = 0; i < n; ++i) {
      const double index = cursor.read(properties[k].type);
      const double vertices = static_cast<double>(layout.vertex->count);
      if (!(index >= 0.0 && index < vertices && index == std::floor(index)))
        throw InputError(fmt::format(
            "PLY file '{}': face {} (counting from 0) refers to vertex {}, but the file has {} vertices "
            "(0 to {}); the file is corrupt, re-export it",
            name, row, index, layout.vertex->count, layout.vertex->count - 1));
      fan[std::min<std::size_t>(i, 2)] = static_cast<std::int32_t>(index);
      if (i >= 2) {
        out.triangles.push_back(fan);
        fan[1] = fan[2];
      }
    }
  }
}

// Reads the elements in file order up to the last one needed.
template <class Cursor>
Data read_body(Cursor& cursor, const Header& header, const Layout& layout, const std::string& name) {
  Data out;
  out.vertices.reserve(layout.vertex->count);  // bounded by the data's size (check_counts)
  if (layout.value) out.values.reserve(layout.vertex->count);
  for (const Element& element : header.elements) {
    const bool is_vertex = &element == layout.vertex, is_face = &element == layout.face;
    std::size_t row = 0;
    try {
      // An element without properties has nothing to read, however many rows it claims.
      for (; row < element.count && !element.properties.empty(); ++row) {
        cursor.begin_row();
        if (is_vertex)
          read_vertex(cursor, layout, out);
        else if (is_face)
          read_face(cursor, layout, row, name, out);
        else
          for (const Property& p : element.properties) skip(cursor, p);
        cursor.end_row();
      }
    } catch (const EndOfData&) {
      throw InputError(fmt::format(
          "PLY file '{}' is truncated: its header promises {} '{}' entries, the data ends in entry {} "
          "(counting from 0); re-export the file",
          name, element.count, text::quote(element.name), row));
    } catch (const BadValue& bad) {
      throw InputError(fmt::format(
          "PLY file '{}', '{}' entry {} (counting from 0): {}; the data is malformed, re-export the file",
          name, text::quote(element.name), row, bad.what));
    }
  }
  if (const auto extra = cursor.leftover())
    throw InputError(
        fmt::format("PLY file '{}' has data after its last element ({}): its header's counts do "
                    "not describe the file; re-export the file",
                    name, *extra));
  return out;
}

}  // namespace

Data read(std::string_view bytes, const std::string& name, const std::string& property) {
  const Header header = read_header(bytes, name);
  const Layout layout = find_layout(header, name, property);
  const std::string_view data = bytes.substr(header.bytes);
  check_counts(header, layout, data.size(), name);
  if (header.format == Format::ascii) {
    // The data's first line: the header's lines plus one.
    AsciiCursor cursor(
        data, 1 + static_cast<std::size_t>(std::count(bytes.begin(), bytes.begin() + header.bytes, '\n')));
    return read_body(cursor, header, layout, name);
  }
  BinaryCursor cursor(data, header.format == Format::binary_big_endian);
  return read_body(cursor, header, layout, name);
}

std::vector<std::string> scalar_vertex_properties(std::string_view bytes, const std::string& name) {
  const Header header = read_header(bytes, name);
  const Element* vertex = header.find("vertex");
  return vertex != nullptr ? scalar_names(*vertex) : std::vector<std::string>{};
}

}  // namespace poreshell::ply
