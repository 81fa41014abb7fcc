#include "plot/png_file.h"

#include "core/error.h"
#include "io/files/atomic_file.h"

namespace partslam::plot {

void write_png_atomically(const std::filesystem::path& path, cairo_surface_t* surface) {
  const std::filesystem::path tmp = io::temporary_sibling(path);
  const cairo_status_t status = cairo_surface_write_to_png(surface, tmp.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw InputError(path.string() + ": cannot write PNG: " + cairo_status_to_string(status));
  }
  io::commit_temporary(tmp, path);
}

}  // namespace partslam::plot
