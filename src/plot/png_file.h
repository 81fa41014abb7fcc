// Writes a cairo image surface as a PNG, atomically (temporary file, then rename).
#pragma once

#include <cairo.h>

#include <filesystem>

namespace partslam::plot {

/// Writes and destroys the surface; throws InputError naming the path when the PNG cannot be written.
void write_png_atomically(const std::filesystem::path& path, cairo_surface_t* surface);

}  // namespace partslam::plot
