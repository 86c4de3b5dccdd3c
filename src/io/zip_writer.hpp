#pragma once
// A ZIP archive written in one pass, for 3MF. Each entry's text comes in chunks that are made and
// deflated in parallel and written in order: zlib's raw deflate at level 1 (what lib3mf uses), each
// chunk but the last ending on a byte boundary (Z_SYNC_FLUSH), so the chunks concatenate into one
// deflate stream, and their CRCs combine (crc32_combine). Always ZIP64, as lib3mf writes it, so no size
// needs knowing in advance. lib3mf writes the same container on one thread: the bunny's 2.1 M
// triangles took it 2.5 s (docs/benchmarks.md, "3MF written in parallel").

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace poreshell {

struct ZipEntry {
  std::string name;
  std::size_t chunks = 1;
  // Appends chunk `chunk`'s text to `text` (called from several threads, each chunk once).
  std::function<void(std::size_t chunk, std::string& text)> text;
};

// Writes the archive to `out`, which must be seekable (each local header's sizes are filled in after
// its data).
void write_zip(std::ostream& out, const std::vector<ZipEntry>& entries);

}  // namespace poreshell
