#include "io/zip_writer.hpp"

#include <tbb/parallel_pipeline.h>
#include <zlib.h>

#include <cstdint>
#include <stdexcept>

namespace poreshell {
namespace {

constexpr std::uint16_t kZip64Version = 45;
constexpr std::uint16_t kDeflated = 8;
constexpr std::uint16_t kZip64Tag = 1;
constexpr std::uint32_t kUnknown32 = 0xFFFFFFFFu;  // the size or offset is in the ZIP64 field
constexpr std::size_t kChunksInFlight = 8;

// Little-endian fields, as ZIP stores them.
template <class Unsigned>
void put(std::string& s, Unsigned v) {
  for (std::size_t b = 0; b < sizeof v; ++b) s.push_back(static_cast<char>((v >> (8 * b)) & 0xFFu));
}
void put16(std::string& s, std::uint16_t v) {
  put(s, v);
}
void put32(std::string& s, std::uint32_t v) {
  put(s, v);
}
void put64(std::string& s, std::uint64_t v) {
  put(s, v);
}

struct Deflated {
  std::string bytes;
  std::uint64_t raw = 0;
  uLong crc = 0;
};

Deflated deflate_chunk(const std::string& text, bool last) {
  z_stream z{};
  if (deflateInit2(&z, Z_BEST_SPEED, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib could not start a deflate stream");
  Deflated d;
  d.raw = text.size();
  d.crc = crc32_z(crc32_z(0, nullptr, 0), reinterpret_cast<const Bytef*>(text.data()), text.size());
  // The bound covers Z_FINISH; a sync flush adds a few bytes, and the loop grows the buffer if needed.
  d.bytes.resize(deflateBound(&z, static_cast<uLong>(text.size())) + 64);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  for (;;) {
    z.next_out = reinterpret_cast<Bytef*>(d.bytes.data() + z.total_out);
    z.avail_out = static_cast<uInt>(d.bytes.size() - z.total_out);
    const int rc = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
    if (rc == Z_STREAM_ERROR) {
      deflateEnd(&z);
      throw std::runtime_error("zlib failed to deflate a chunk");
    }
    if (last ? rc == Z_STREAM_END : (z.avail_in == 0 && z.avail_out > 0)) break;
    d.bytes.resize(2 * d.bytes.size());
  }
  d.bytes.resize(z.total_out);
  deflateEnd(&z);
  return d;
}

struct Written {
  std::uint64_t offset = 0, raw = 0, packed = 0;
  uLong crc = 0;
};

// The fields a local header and its central directory entry share, from the version needed on: version,
// flags, method, time, date (1980-01-01, the earliest a ZIP can say: reproducible bytes), CRC, both
// sizes (in the ZIP64 field), the name's length and the extra field's.
void shared_fields(std::string& h, const std::string& name, const Written& w, std::uint16_t extra) {
  put16(h, kZip64Version);
  put16(h, 0);
  put16(h, kDeflated);
  put16(h, 0);
  put16(h, 0x21);
  put32(h, static_cast<std::uint32_t>(w.crc));
  put32(h, kUnknown32);
  put32(h, kUnknown32);
  put16(h, static_cast<std::uint16_t>(name.size()));
  put16(h, extra);
}

std::string local_header(const std::string& name, const Written& w) {
  std::string h;
  put32(h, 0x04034b50u);
  shared_fields(h, name, w, 20);
  h += name;
  put16(h, kZip64Tag);
  put16(h, 16);
  put64(h, w.raw);
  put64(h, w.packed);
  return h;
}

std::string central_header(const std::string& name, const Written& w) {
  std::string h;
  put32(h, 0x02014b50u);
  put16(h, kZip64Version);  // made by
  shared_fields(h, name, w, 28);
  put16(h, 0);  // comment
  put16(h, 0);  // disk
  put16(h, 0);  // internal attributes
  put32(h, 0);  // external attributes
  put32(h, kUnknown32);
  h += name;
  put16(h, kZip64Tag);
  put16(h, 24);
  put64(h, w.raw);
  put64(h, w.packed);
  put64(h, w.offset);
  return h;
}

// A failed write leaves `out` failed, for the caller to report (write_atomically: "disk full?").
std::uint64_t position(std::ostream& out) {
  const auto p = out.tellp();
  if (p < 0 && out) throw std::runtime_error("the ZIP writer needs a seekable stream");
  return p < 0 ? 0 : static_cast<std::uint64_t>(p);
}

}  // namespace

void write_zip(std::ostream& out, const std::vector<ZipEntry>& entries) {
  std::vector<Written> written(entries.size());
  for (std::size_t e = 0; e < entries.size() && out; ++e) {
    const ZipEntry& entry = entries[e];
    if (entry.name.size() > 0xFFFFu || entry.chunks == 0) throw std::invalid_argument("zip: bad entry");
    Written& w = written[e];
    w.offset = position(out);
    w.crc = crc32_z(0, nullptr, 0);
    const std::string placeholder = local_header(entry.name, w);
    out.write(placeholder.data(), static_cast<std::streamsize>(placeholder.size()));
    std::size_t next = 0;
    tbb::parallel_pipeline(
        kChunksInFlight,
        tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                            [&](tbb::flow_control& control) -> std::size_t {
                                              if (next == entry.chunks) control.stop();
                                              return next++;
                                            }) &
            tbb::make_filter<std::size_t, Deflated>(tbb::filter_mode::parallel,
                                                    [&](std::size_t chunk) {
                                                      std::string text;
                                                      entry.text(chunk, text);
                                                      return deflate_chunk(text, chunk + 1 == entry.chunks);
                                                    }) &
            tbb::make_filter<Deflated, void>(tbb::filter_mode::serial_in_order, [&](const Deflated& d) {
              out.write(d.bytes.data(), static_cast<std::streamsize>(d.bytes.size()));
              w.crc = crc32_combine(w.crc, d.crc, static_cast<z_off_t>(d.raw));
              w.raw += d.raw;
              w.packed += d.bytes.size();
            }));
    const std::uint64_t end = position(out);
    const std::string header = local_header(entry.name, w);
    out.seekp(static_cast<std::streamoff>(w.offset));
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.seekp(static_cast<std::streamoff>(end));
  }

  if (!out) return;
  const std::uint64_t directory = position(out);
  std::string tail;
  for (std::size_t e = 0; e < entries.size(); ++e) tail += central_header(entries[e].name, written[e]);
  const std::uint64_t directory_size = tail.size();
  const std::uint64_t zip64_end = directory + directory_size;
  put32(tail, 0x06064b50u);  // ZIP64 end of central directory
  put64(tail, 44);
  put16(tail, kZip64Version);
  put16(tail, kZip64Version);
  put32(tail, 0);
  put32(tail, 0);
  put64(tail, entries.size());
  put64(tail, entries.size());
  put64(tail, directory_size);
  put64(tail, directory);
  put32(tail, 0x07064b50u);  // its locator
  put32(tail, 0);
  put64(tail, zip64_end);
  put32(tail, 1);
  put32(tail, 0x06054b50u);  // end of central directory
  put16(tail, 0);
  put16(tail, 0);
  put16(tail, static_cast<std::uint16_t>(entries.size()));
  put16(tail, static_cast<std::uint16_t>(entries.size()));
  // As lib3mf writes it (and slicers read it): the directory's size here, its offset only in ZIP64.
  put32(tail, directory_size < kUnknown32 ? static_cast<std::uint32_t>(directory_size) : kUnknown32);
  put32(tail, kUnknown32);
  put16(tail, 0);
  out.write(tail.data(), static_cast<std::streamsize>(tail.size()));
}

}  // namespace poreshell
