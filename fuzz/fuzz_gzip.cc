// libFuzzer target: gzip-compressed text through io/files/line_reader.h, read as a CARMEN log and as a relations
// file. The first input byte chooses how the rest becomes the file: even, the rest is the file's bytes as they are (a
// gzip stream, truncated, corrupt or not gzip at all); odd, the rest is gzip-compressed first, so the mutations of
// the text reach the readers through a valid stream (zlib's deflate, gzip header and trailer).
#include <zlib.h>

#include <vector>

#include "fuzz/fuzz_common.h"
#include "io/logs/carmen_log.h"
#include "io/logs/relations.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  if (size < 1) return 0;
  const bool compress = (data[0] & 1) != 0;
  ++data, --size;
  std::filesystem::path path;
  if (compress) {
    std::vector<std::uint8_t> out(compressBound(static_cast<uLong>(size)) + 32);
    z_stream z{};
    // windowBits 15 + 16: a gzip header and trailer; level 1 keeps it quick.
    if (deflateInit2(&z, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) std::abort();
    z.next_in = const_cast<Bytef*>(data);
    z.avail_in = static_cast<uInt>(size);
    z.next_out = out.data();
    z.avail_out = static_cast<uInt>(out.size());
    if (deflate(&z, Z_FINISH) != Z_STREAM_END) std::abort();
    out.resize(z.total_out);
    deflateEnd(&z);
    path = fuzz::write_file("log.gz", out.data(), out.size());
  } else {
    path = fuzz::write_file("log.gz", data, size);
  }
  io::LogReadOptions options;
  options.max_points = 200000;
  fuzz::expect_input_error([&] {
    const io::CarmenLog log = io::read_carmen_log(path, options);
    for (const Scan& s : log.scans) {
      for (const Vec2& p : s.points_laser) fuzz::check(fuzz::finite(p), "scan point finite");
    }
  });
  fuzz::expect_input_error([&] {
    for (const io::Relation& r : io::read_relations(path)) {
      fuzz::check(std::isfinite(r.t1) && std::isfinite(r.t2) && fuzz::finite(r.T_1_2), "relation finite");
    }
  });
  return 0;
}
