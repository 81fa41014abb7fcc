// Tested by: io/logs/ros2_bag_test.cc

#include "io/files/sqlite_salvage.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"

namespace partslam::io::sqlite {
namespace {

// A big-endian read of n bytes at p.
std::uint64_t be(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = v << 8 | p[i];
  return v;
}

// SQLite's varint (1-9 bytes) at p, within [p, end); false when it runs past end.
bool varint(const std::uint8_t*& p, const std::uint8_t* end, std::uint64_t& v) {
  v = 0;
  for (int i = 0; i < 9; ++i) {
    if (p >= end) return false;
    const std::uint8_t b = *p++;
    if (i == 8) {
      v = v << 8 | b;
      return true;
    }
    v = v << 7 | (b & 0x7f);
    if ((b & 0x80) == 0) return true;
  }
  return true;
}

class Salvage {
 public:
  Salvage(std::vector<std::uint8_t> file, std::size_t page, std::size_t usable)
      : file_(std::move(file)), page_(page), usable_(usable) {}

  void run(const std::function<void(std::int64_t, const std::vector<Value>&)>& on_row) {
    const std::size_t pages = file_.size() / page_;  // whole pages only
    for (std::size_t n = 1; n <= pages; ++n) {
      const std::uint8_t* base = file_.data() + (n - 1) * page_;
      const std::uint8_t* header = base + (n == 1 ? 100 : 0);
      if (header[0] != 0x0D) continue;  // a table leaf page
      const std::size_t cells = static_cast<std::size_t>(be(header + 3, 2));
      if (8 + 2 * cells > page_ - (n == 1 ? 100 : 0)) continue;
      for (std::size_t c = 0; c < cells; ++c) {
        const std::size_t offset = static_cast<std::size_t>(be(header + 8 + 2 * c, 2));
        if (offset < 8 || offset >= usable_) continue;
        cell(base, base + offset, on_row);
      }
    }
  }

 private:
  // One cell of a table leaf page: payload size, rowid, local payload, then the overflow chain.
  void cell(const std::uint8_t* page, const std::uint8_t* p,
            const std::function<void(std::int64_t, const std::vector<Value>&)>& on_row) {
    const std::uint8_t* end = page + usable_;
    std::uint64_t size = 0, rowid = 0;
    if (!varint(p, end, size) || !varint(p, end, rowid) || size > (1u << 30)) return;
    const std::size_t u = usable_, x = u - 35, m = (u - 12) * 32 / 255 - 23;
    std::size_t local = size;
    if (size > x) {
      const std::size_t k = m + (size - m) % (u - 4);
      local = k <= x ? k : m;
    }
    if (static_cast<std::size_t>(end - p) < local + (local < size ? 4 : 0)) return;
    payload_.assign(p, p + local);
    if (local < size) {
      std::uint64_t next = be(p + local, 4);
      for (std::size_t hops = 0; payload_.size() < size; ++hops) {
        if (next == 0 || next > file_.size() / page_ || hops > file_.size() / page_) return;  // past the cut
        const std::uint8_t* o = file_.data() + (next - 1) * page_;
        const std::size_t take = std::min<std::size_t>(size - payload_.size(), u - 4);
        payload_.insert(payload_.end(), o + 4, o + 4 + take);
        next = be(o, 4);
      }
    }
    if (record()) on_row(static_cast<std::int64_t>(rowid), values_);
  }

  // The record format: a header of serial types, then the values.
  bool record() {
    values_.clear();
    const std::uint8_t* p = payload_.data();
    const std::uint8_t* end = p + payload_.size();
    std::uint64_t header = 0;
    if (!varint(p, end, header) || header > payload_.size()) return false;
    const std::uint8_t* types = p;
    const std::uint8_t* types_end = payload_.data() + header;
    const std::uint8_t* body = types_end;
    while (types < types_end) {
      std::uint64_t t = 0;
      if (!varint(types, types_end, t)) return false;
      static constexpr int kIntBytes[] = {0, 1, 2, 3, 4, 6, 8};
      std::size_t n = 0;
      if (t >= 1 && t <= 6) n = static_cast<std::size_t>(kIntBytes[t]);
      else if (t == 7) n = 8;
      else if (t >= 12) n = static_cast<std::size_t>((t - 12) / 2);
      if (static_cast<std::size_t>(end - body) < n) return false;
      if (t == 0) values_.emplace_back(std::monostate{});
      else if (t <= 6) {
        std::uint64_t v = be(body, static_cast<int>(n));
        if (n < 8 && (v >> (8 * n - 1)) != 0) v |= ~std::uint64_t{0} << (8 * n);  // sign-extend
        values_.emplace_back(static_cast<std::int64_t>(v));
      } else if (t == 7) {
        const std::uint64_t bits = be(body, 8);
        double d;
        std::memcpy(&d, &bits, 8);
        values_.emplace_back(d);
      } else if (t == 8 || t == 9) {
        values_.emplace_back(static_cast<std::int64_t>(t - 8));
      } else if (t >= 12) {
        values_.emplace_back(std::span<const std::uint8_t>(body, n));
      } else {
        return false;  // 10, 11: reserved
      }
      body += n;
    }
    return true;
  }

  std::vector<std::uint8_t> file_;
  std::size_t page_, usable_;
  std::vector<std::uint8_t> payload_;
  std::vector<Value> values_;
};

// The header fields of a file's first 100 bytes; nullopt when they are not a SQLite header.
std::optional<FileHeader> parse_header(const std::uint8_t* h, std::size_t size) {
  if (size < 100 || std::memcmp(h, "SQLite format 3", 16) != 0) return std::nullopt;
  FileHeader out;
  out.page_size = h[16] == 0 && h[17] == 1 ? 65536 : static_cast<std::size_t>(be(h + 16, 2));
  out.reserved = h[20];
  out.page_count = be(h + 28, 4);
  return out;
}

}  // namespace

std::optional<FileHeader> read_file_header(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint8_t h[100];
  if (!in.read(reinterpret_cast<char*>(h), sizeof h)) return std::nullopt;
  return parse_header(h, sizeof h);
}

void salvage_rows(const std::filesystem::path& path,
                  const std::function<void(std::int64_t rowid, const std::vector<Value>& values)>& on_row) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)), {});
  const std::optional<FileHeader> header = parse_header(file.data(), file.size());
  if (!header) throw InputError(path.string() + ": not a SQLite file (it does not start with the SQLite header)");
  const std::size_t page = header->page_size, reserved = header->reserved;
  if (page < 512 || (page & (page - 1)) != 0 || reserved > page - 480)
    throw InputError(path.string() + ": a SQLite header with page size " + std::to_string(page));
  Salvage(std::move(file), page, page - reserved).run(on_row);
}

}  // namespace partslam::io::sqlite
