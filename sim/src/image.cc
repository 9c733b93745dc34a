#include "ovpc/sim/image.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <stdexcept>

namespace ovpc::sim {
namespace {

/// The libpng part, free of C++ objects with destructors (libpng reports errors by longjmp).
/// Returns nullptr on success, else a static message.
const char* WritePngFile(std::FILE* file, const std::uint8_t* rgb, int width, int height) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (png == nullptr) return "png_create_write_struct failed";
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return "png_create_info_struct failed";
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return "libpng failed while writing";
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  // Fast compression: pictures are written every frame of a closed-loop run.
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    png_write_row(png, rgb + 3 * static_cast<std::size_t>(y) * static_cast<std::size_t>(width));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return nullptr;
}

}  // namespace

void WritePng(const Image& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * image.height) {
    throw std::invalid_argument("WritePng: image size and pixel buffer disagree");
  }
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw std::runtime_error("WritePng: cannot open '" + path + "' for writing");
  const char* error = WritePngFile(file, image.rgb.data(), image.width, image.height);
  const bool closed = std::fclose(file) == 0;
  if (error != nullptr) throw std::runtime_error("WritePng: " + std::string(error) + " ('" + path + "')");
  if (!closed) throw std::runtime_error("WritePng: cannot finish writing '" + path + "'");
}

}  // namespace ovpc::sim
