#include "io/formats/map_server.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/files/atomic_file.h"
#include "io/files/yaml_text.h"

namespace partslam::io {
namespace {

constexpr std::uint8_t kOccupiedPixel = 0, kFreePixel = 254, kUnknownPixel = 205;
constexpr long kMaxPixels = 1L << 28;

struct Pgm {
  int width = 0, height = 0, max_value = 255;
  std::vector<std::uint16_t> pixels;  // row-major, first row on top
};

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw InputError(path.string() + ": " + what);
}

// The next header token of a PGM, skipping whitespace and # comments.
std::string pgm_token(std::istream& in, const std::filesystem::path& path, const char* field) {
  std::string token;
  int c;
  while ((c = in.get()) != EOF) {
    if (c == '#') {
      while ((c = in.get()) != EOF && c != '\n') {
      }
    } else if (!std::isspace(c)) {
      token.push_back(static_cast<char>(c));
      while ((c = in.peek()) != EOF && !std::isspace(c) && c != '#') token.push_back(static_cast<char>(in.get()));
      return token;
    }
  }
  fail(path, std::string("truncated PGM header: no ") + field);
}

int pgm_number(std::istream& in, const std::filesystem::path& path, const char* field, int lo, long hi) {
  const std::string token = pgm_token(in, path, field);
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (token.empty() || *end != '\0' || v < lo || v > hi)
    fail(path, std::string("PGM ") + field + " must be an integer in [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "], got '" + token + "'");
  return static_cast<int>(v);
}

Pgm read_pgm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the map image");
  const std::string magic = pgm_token(in, path, "magic number");
  if (magic != "P5" && magic != "P2")
    fail(path, "not a PGM image (magic '" + magic.substr(0, 8) + "', expected P5 or P2): convert it, e.g. "
               "'convert map.png map.pgm'");
  Pgm pgm;
  pgm.width = pgm_number(in, path, "width", 1, 1 << 20);
  pgm.height = pgm_number(in, path, "height", 1, 1 << 20);
  if (static_cast<long>(pgm.width) * pgm.height > kMaxPixels)
    fail(path, std::to_string(pgm.width) + " x " + std::to_string(pgm.height) + " pixels is more than 2^28");
  pgm.max_value = pgm_number(in, path, "max value", 1, 65535);
  const std::size_t n = static_cast<std::size_t>(pgm.width) * static_cast<std::size_t>(pgm.height);
  const std::size_t bytes = pgm.max_value > 255 ? 2 : 1;
  // The pixels must be in the file before they are allocated, so that a header claiming more pixels than the file
  // holds allocates nothing (docs/NOTES.md, "Limits"). P5: one whitespace, then n pixels of `bytes`
  // bytes; P2: at least one digit and one separator per pixel but the last.
  const std::streamoff here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff left = in.tellg() - here;
  in.seekg(here);
  const std::size_t needed = magic == "P5" ? 1 + n * bytes : 2 * n - 1;
  if (here < 0 || left < 0 || static_cast<std::size_t>(left) < needed)
    fail(path, "truncated PGM: the header says " + std::to_string(pgm.width) + " x " + std::to_string(pgm.height) +
                   " pixels (at least " + std::to_string(needed) + " bytes) but " + std::to_string(std::max<std::streamoff>(left, 0)) +
                   " bytes follow");
  pgm.pixels.resize(n);
  if (magic == "P5") {
    in.get();  // the single whitespace after the header
    std::vector<unsigned char> raw(n * bytes);
    in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size()));
    if (static_cast<std::size_t>(in.gcount()) != raw.size())
      fail(path, "truncated PGM: the header says " + std::to_string(pgm.width) + " x " + std::to_string(pgm.height) +
                     " pixels (" + std::to_string(raw.size()) + " bytes) but " + std::to_string(in.gcount()) +
                     " bytes follow");
    for (std::size_t k = 0; k < n; ++k)
      pgm.pixels[k] = static_cast<std::uint16_t>(bytes == 2 ? raw[2 * k] << 8 | raw[2 * k + 1] : raw[k]);
  } else {
    for (std::size_t k = 0; k < n; ++k)
      pgm.pixels[k] = static_cast<std::uint16_t>(pgm_number(in, path, "pixel", 0, pgm.max_value));
  }
  for (const std::uint16_t p : pgm.pixels) {
    if (p > pgm.max_value) fail(path, "a pixel exceeds the PGM's max value " + std::to_string(pgm.max_value));
  }
  return pgm;
}

// A field of the YAML, with the file and line in every error.
template <typename T>
T field(const YAML::Node& root, const std::filesystem::path& path, const char* name, const T* fallback = nullptr) {
  const YAML::Node node = root[name];
  if (!node) {
    if (fallback) return *fallback;
    fail(path, std::string("missing field '") + name + "'");
  }
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    fail(path, "line " + std::to_string(node.Mark().line + 1) + ": field '" + name + "' has the wrong type");
  }
}

}  // namespace

GridMap read_map_yaml(const std::filesystem::path& yaml_path) {
  std::error_code folder_ec;
  if (std::filesystem::is_directory(yaml_path, folder_ec)) fail(yaml_path, "a folder, not a map YAML file");
  if (holds_binary_data(yaml_path))
    fail(yaml_path, "binary data, not a map YAML file (the image? give the map's .yaml, which names its image)");
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path.string());
  } catch (const YAML::BadFile&) {
    fail(yaml_path, "cannot open the map YAML");
  } catch (const YAML::Exception& e) {
    fail(yaml_path, "line " + std::to_string(e.mark.line + 1) + ": not valid YAML (" + e.msg + ")");
  }
  if (!root.IsMap()) fail(yaml_path, "not a map_server YAML (expected 'image:', 'resolution:', 'origin:')");
  const std::string image = field<std::string>(root, yaml_path, "image");
  const double resolution = field<double>(root, yaml_path, "resolution");
  const std::vector<double> origin = field<std::vector<double>>(root, yaml_path, "origin");
  const double default_occupied = 0.65, default_free = 0.196;
  const int default_negate = 0;
  const std::string default_mode = "trinary";
  const double occupied = field<double>(root, yaml_path, "occupied_thresh", &default_occupied);
  const double free = field<double>(root, yaml_path, "free_thresh", &default_free);
  const int negate = field<int>(root, yaml_path, "negate", &default_negate);
  const std::string mode = field<std::string>(root, yaml_path, "mode", &default_mode);
  if (!(resolution >= 0.001 && resolution <= 100.0)) fail(yaml_path, "field 'resolution' must be in [0.001, 100] m");
  if (origin.size() != 3) fail(yaml_path, "field 'origin' must be [x, y, yaw]");
  if (!(occupied >= 0.0 && occupied <= 1.0) || !(free >= 0.0 && free <= occupied))
    fail(yaml_path, "fields 'occupied_thresh' and 'free_thresh' must satisfy 0 <= free_thresh <= occupied_thresh <= 1");
  if (negate != 0 && negate != 1) fail(yaml_path, "field 'negate' must be 0 or 1");
  if (mode != "trinary" && mode != "scale" && mode != "raw")
    fail(yaml_path, "field 'mode' must be trinary, scale or raw, got '" + mode + "'");
  std::filesystem::path image_path(image);
  if (image_path.is_relative()) image_path = yaml_path.parent_path() / image_path;
  // The error_code forms: an image path the file system refuses (e.g. too long) is bad input, not a filesystem_error
  // (fuzz_map_server_yaml).
  std::error_code ec;
  const std::filesystem::file_status image_status = std::filesystem::status(image_path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    fail(yaml_path, "field 'image': " + image_path.string().substr(0, 200) + ": " + ec.message());
  if (!std::filesystem::exists(image_status))
    fail(yaml_path, "field 'image': " + image_path.string() + " does not exist");
  if (!std::filesystem::is_regular_file(image_status))  // a folder, a FIFO or a device (/dev/zero never ends)
    fail(yaml_path, "field 'image': " + image_path.string() + " is not a regular file");
  const Pgm pgm = read_pgm(image_path);

  GridMap map;
  map.resolution = resolution;
  map.origin = {origin[0], origin[1], origin[2]};
  map.width = pgm.width;
  map.height = pgm.height;
  map.cells.assign(static_cast<std::size_t>(map.width) * map.height, CellState::kUnknown);
  try {
    validate(map);
  } catch (const InputError& e) {
    fail(yaml_path, std::string(e.what()) + " (fields 'origin', 'resolution' and the image size)");
  }
  for (int row = 0; row < map.height; ++row) {
    for (int column = 0; column < map.width; ++column) {
      const int p = pgm.pixels[static_cast<std::size_t>(map.height - 1 - row) * map.width + column];
      CellState state = CellState::kUnknown;
      if (mode == "raw") {
        if (p <= 100) state = p > occupied * 100 ? CellState::kOccupied : p < free * 100 ? CellState::kFree
                                                                                          : CellState::kUnknown;
      } else {
        const double value = static_cast<double>(p) / pgm.max_value;
        const double occupancy = negate ? value : 1.0 - value;
        state = occupancy > occupied ? CellState::kOccupied : occupancy < free ? CellState::kFree : CellState::kUnknown;
      }
      map.cells[static_cast<std::size_t>(row) * map.width + column] = state;
    }
  }
  return map;
}

void write_map_yaml(const std::filesystem::path& yaml_path, const GridMap& map) {
  validate(map);
  std::filesystem::path image_path = yaml_path;
  image_path.replace_extension(".pgm");
  check_writable(yaml_path);
  check_writable(image_path);
  write_atomically(image_path, [&](std::ostream& out) {
    out << "P5\n# partslam export-map\n" << map.width << ' ' << map.height << "\n255\n";
    std::vector<char> row(static_cast<std::size_t>(map.width));
    for (int r = map.height - 1; r >= 0; --r) {
      for (int c = 0; c < map.width; ++c) {
        const CellState s = map.at(c, r);
        row[static_cast<std::size_t>(c)] = static_cast<char>(
            s == CellState::kOccupied ? kOccupiedPixel : s == CellState::kFree ? kFreePixel : kUnknownPixel);
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
  });
  write_atomically(yaml_path, [&](std::ostream& out) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "resolution: %.6f\norigin: [%.6f, %.6f, %.6f]\nnegate: 0\noccupied_thresh: 0.65\n"
                  "free_thresh: 0.196\nmode: trinary\n",
                  map.resolution, map.origin.x, map.origin.y, map.origin.theta);
    // Quoted: a file name such as "map: 2.pgm" or "#1.pgm" is no plain YAML scalar.
    out << "image: " << yaml_double_quoted(image_path.filename().string()) << "\n" << text;
  });
}

}  // namespace partslam::io
