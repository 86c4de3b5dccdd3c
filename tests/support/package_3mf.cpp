#include "package_3mf.hpp"

#include <cstdint>

namespace poreshell::test_support {
namespace {

std::uint32_t crc32(const std::string& data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char ch : data) {
    crc ^= ch;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string u16(std::uint32_t n) {
  return {static_cast<char>(n & 0xFF), static_cast<char>((n >> 8) & 0xFF)};
}
std::string u32(std::uint32_t n) {
  return u16(n & 0xFFFF) + u16(n >> 16);
}

}  // namespace

std::string stored_zip(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::string local, central;
  for (const auto& [name, data] : entries) {
    const auto size = static_cast<std::uint32_t>(data.size());
    const auto name_size = static_cast<std::uint32_t>(name.size());
    const std::string sizes = u32(crc32(data)) + u32(size) + u32(size);
    const auto offset = static_cast<std::uint32_t>(local.size());
    // version 2.0, no flags, stored, a fixed time and date
    local += u32(0x04034b50) + u16(20) + u16(0) + u16(0) + u16(0) + u16(0x21) + sizes + u16(name_size) +
             u16(0) + name + data;
    central += u32(0x02014b50) + u16(20) + u16(20) + u16(0) + u16(0) + u16(0) + u16(0x21) + sizes +
               u16(name_size) + u16(0) + u16(0) + u16(0) + u16(0) + u32(0) + u32(offset) + name;
  }
  const auto n = static_cast<std::uint32_t>(entries.size());
  return local + central + u32(0x06054b50) + u16(0) + u16(0) + u16(n) + u16(n) +
         u32(static_cast<std::uint32_t>(central.size())) + u32(static_cast<std::uint32_t>(local.size())) +
         u16(0);
}

std::string package_3mf(const std::string& model_xml) {
  const std::string types =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types "
      "xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default Extension=\"rels\" "
      "ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/><Default "
      "Extension=\"model\" "
      "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>\n";
  const std::string rels =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships "
      "xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship "
      "Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
      "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";
  return stored_zip({{"[Content_Types].xml", types}, {"_rels/.rels", rels}, {"3D/3dmodel.model", model_xml}});
}

}  // namespace poreshell::test_support
