// PNG files: write an Image as an 8-bit RGBA PNG and read one back (libpng).
#pragma once

#include <string>

#include "base/result.h"
#include "render/image.h"

namespace dt {

// Writes the image; the bytes depend only on the pixels (no time stamp). An unwritable path is
// an expected failure. An empty image is misuse and throws std::invalid_argument.
Status WritePng(const Image& image, const std::string& path);

// The same PNG as WritePng writes, in memory. Throws like WritePng.
Result<std::string> EncodePng(const Image& image);
// Reads any PNG libpng understands, converted to 8-bit RGBA.
Result<Image> ReadPng(const std::string& path);

}  // namespace dt
