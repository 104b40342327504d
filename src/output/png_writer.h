// capflow/output/png_writer: PNG files via libspng (Debian's libspng, zlib level 1). No GL, no
// numerics. Pixels are 8-bit RGBA, rows top-down, `stride` bytes apart (0: width*4); an image
// whose alpha is 255 everywhere is stored as RGB (the same pixels, a smaller, faster file).
// Files are replaced atomically (files/atomic_write.h): a reader - or a crash - never sees half
// an image.
// Failure: std::runtime_error naming the path and the cause.
#pragma once

#include <cstdint>
#include <string>

namespace capflow::output {

void write_png(const std::string& path, int width, int height, const uint8_t* rgba,
               int stride = 0);
// The same PNG in memory (the live console's frames).
std::string encode_png(int width, int height, const uint8_t* rgba, int stride = 0);

}  // namespace capflow::output
