// Test helper: the colour of one pixel of a cairo image surface, as 0xRRGGBB.
#pragma once

#include <cairo.h>

#include <cstdint>

namespace partslam::plot {

inline std::uint32_t pixel(cairo_surface_t* s, int x, int y) {
  const unsigned char* data = cairo_image_surface_get_data(s);
  return reinterpret_cast<const std::uint32_t*>(data + y * cairo_image_surface_get_stride(s))[x] & 0xFFFFFFu;
}

}  // namespace partslam::plot
