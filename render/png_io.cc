#include "render/png_io.h"

#include <png.h>

#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {

namespace {

// libpng's description of `image` for writing (RGBA, 8 bits a channel); `caller` names the
// function refusing an empty image.
png_image PngOf(const Image& image, const char* caller) {
  if (image.empty()) throw std::invalid_argument(fmt::format("{}: the image is empty", caller));
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width());
  png.height = static_cast<png_uint_32>(image.height());
  png.format = PNG_FORMAT_RGBA;
  return png;
}

}  // namespace

Status WritePng(const Image& image, const std::string& path) {
  png_image png = PngOf(image, "WritePng");
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.bytes().data(), 0, nullptr)) {
    Error e{fmt::format("cannot write PNG {}: {}", path, png.message)};
    png_image_free(&png);
    return e;
  }
  return Status::Ok();
}

Result<std::string> EncodePng(const Image& image) {
  png_image png = PngOf(image, "EncodePng");
  png_alloc_size_t size = 0;
  const auto write = [&](void* bytes) -> Status {
    if (!png_image_write_to_memory(&png, bytes, &size, 0, image.bytes().data(), 0, nullptr)) {
      Error e{fmt::format("cannot encode a {} x {} px PNG: {}", image.width(), image.height(),
                          png.message)};
      png_image_free(&png);
      return e;
    }
    return Status::Ok();
  };
  // First the size, then the bytes (libpng's two-call form).
  if (Status s = write(nullptr); !s) return s.error();
  std::string out(size, '\0');
  if (Status s = write(out.data()); !s) return s.error();
  out.resize(size);
  return out;
}

Result<Image> ReadPng(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    Error e{fmt::format("cannot read PNG {}: {}", path, png.message)};
    png_image_free(&png);
    return e;
  }
  if (png.width == 0 || png.height == 0 || png.width > Image::kMaxSidePx ||
      png.height > Image::kMaxSidePx) {
    Error e{fmt::format("PNG {} is {} x {} px, outside 1..{}", path, png.width, png.height,
                        Image::kMaxSidePx)};
    png_image_free(&png);
    return e;
  }
  png.format = PNG_FORMAT_RGBA;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  if (!png_image_finish_read(&png, nullptr, image.bytes().data(), 0, nullptr)) {
    Error e{fmt::format("cannot decode PNG {}: {}", path, png.message)};
    png_image_free(&png);
    return e;
  }
  return image;
}

}  // namespace dt
