#include "output/png_writer.h"

#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "stb_image_write.h"

namespace capflow::output {

namespace {
// stb's defaults (zlib level 8, the best of five filters tried on every row) take ~75 ms for a
// 1280x720 frame; the "up" filter at level 5 writes the same pixels in ~45 % of that time, and
// a smaller file (docs/performance.md, "PNG writing"). The settings are libstb globals, set
// once before the first write.
void configure_stb() {
  static std::once_flag once;
  std::call_once(once, [] {
    stbi_write_png_compression_level = 5;
    stbi_write_force_png_filter = 2;  // "up"
  });
}
}  // namespace

void write_png(const std::string& path, int width, int height, const uint8_t* rgba, int stride) {
  if (width <= 0 || height <= 0 || !rgba) throw std::invalid_argument("write_png: empty image");
  configure_stb();
  if (stride == 0) stride = width * 4;
  // An opaque image (every rendered frame) is written as RGB: a quarter less data to filter
  // and compress; the pixels read back the same.
  bool opaque = true;
  for (int y = 0; y < height && opaque; ++y) {
    const uint8_t* row = rgba + static_cast<size_t>(y) * stride;
    for (int x = 0; x < width; ++x)
      if (row[4 * x + 3] != 255) {
        opaque = false;
        break;
      }
  }
  int ok = 0;
  if (opaque) {
    thread_local std::vector<uint8_t> rgb;  // kept: a frame's 1.5-6 MB, every frame
    rgb.resize(static_cast<size_t>(width) * height * 3);
    for (int y = 0; y < height; ++y) {
      const uint8_t* row = rgba + static_cast<size_t>(y) * stride;
      uint8_t* out = rgb.data() + static_cast<size_t>(y) * width * 3;
      for (int x = 0; x < width; ++x)
        for (int c = 0; c < 3; ++c) out[3 * x + c] = row[4 * x + c];
    }
    ok = stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3);
  } else {
    ok = stbi_write_png(path.c_str(), width, height, 4, rgba, stride);
  }
  if (!ok) throw std::runtime_error("cannot write PNG " + path);
}

void write_png_atomic(const std::string& path, int width, int height, const uint8_t* rgba,
                      int stride) {
  const std::string tmp = path + ".tmp";
  write_png(tmp, width, height, rgba, stride);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

}  // namespace capflow::output
