#include "output/png_writer.h"

#include "files/atomic_write.h"

#include <spng.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <vector>

namespace capflow::output {

namespace {

// libspng with zlib at level 1 and the "up" filter on every row: a rendered 1280x720 frame in
// ~9 ms (stb_image_write at level 5 with the same filter: 30-45 ms) and a file of the same size
// (docs/performance.md, "Movie runs", "PNG").
constexpr int kLevel = 1;

struct CtxFree {
  void operator()(spng_ctx* c) const { spng_ctx_free(c); }
};

// The encoded PNG of `pixels` (rows of width * channels bytes, contiguous) in a malloc'ed
// buffer owned by the returned pointer.
std::unique_ptr<void, decltype(&std::free)> encode(int width, int height, int channels,
                                                   const uint8_t* pixels, size_t* length,
                                                   const std::string& path) {
  std::unique_ptr<spng_ctx, CtxFree> ctx(spng_ctx_new(SPNG_CTX_ENCODER));
  if (!ctx) throw std::runtime_error("cannot write PNG " + path + ": out of memory");
  spng_ihdr ihdr{};
  ihdr.width = static_cast<uint32_t>(width);
  ihdr.height = static_cast<uint32_t>(height);
  ihdr.bit_depth = 8;
  ihdr.color_type = channels == 3 ? SPNG_COLOR_TYPE_TRUECOLOR : SPNG_COLOR_TYPE_TRUECOLOR_ALPHA;
  int err = spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  if (!err) err = spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, kLevel);
  if (!err) err = spng_set_option(ctx.get(), SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_UP);
  if (!err) err = spng_set_ihdr(ctx.get(), &ihdr);
  if (!err)
    err = spng_encode_image(ctx.get(), pixels, static_cast<size_t>(width) * height * channels,
                            SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  void* buf = nullptr;
  if (!err) buf = spng_get_png_buffer(ctx.get(), length, &err);
  if (err || !buf) throw std::runtime_error("cannot write PNG " + path + ": " + spng_strerror(err));
  return {buf, &std::free};
}

}  // namespace

namespace {

// The pixels packed as RGB when opaque (every rendered frame: a quarter less data to filter and
// compress; the pixels read back the same), else RGBA; *channels says which.
const std::vector<uint8_t>& pack(int width, int height, const uint8_t* rgba, int stride,
                                 int* channels) {
  if (width <= 0 || height <= 0 || !rgba) throw std::invalid_argument("write_png: empty image");
  if (stride == 0) stride = width * 4;
  bool opaque = true;
  for (int y = 0; y < height && opaque; ++y) {
    const uint8_t* row = rgba + static_cast<size_t>(y) * stride;
    for (int x = 0; x < width; ++x)
      if (row[4 * x + 3] != 255) {
        opaque = false;
        break;
      }
  }
  *channels = opaque ? 3 : 4;
  thread_local std::vector<uint8_t> packed;  // kept: a frame's 1.5-6 MB, every frame
  packed.resize(static_cast<size_t>(width) * height * *channels);
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = rgba + static_cast<size_t>(y) * stride;
    uint8_t* out = packed.data() + static_cast<size_t>(y) * width * *channels;
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < *channels; ++c) out[*channels * x + c] = row[4 * x + c];
  }
  return packed;
}

}  // namespace

std::string encode_png(int width, int height, const uint8_t* rgba, int stride) {
  int channels = 0;
  const std::vector<uint8_t>& packed = pack(width, height, rgba, stride, &channels);
  size_t length = 0;
  const auto png = encode(width, height, channels, packed.data(), &length, "(in memory)");
  return std::string(reinterpret_cast<const char*>(png.get()), length);
}

void write_png(const std::string& path, int width, int height, const uint8_t* rgba, int stride) {
  int channels = 0;
  const std::vector<uint8_t>& packed = pack(width, height, rgba, stride, &channels);
  size_t length = 0;
  const auto png = encode(width, height, channels, packed.data(), &length, path);
  try {
    files::write_atomically(path, std::string_view(reinterpret_cast<const char*>(png.get()), length));
  } catch (const files::WriteError& e) {
    throw std::runtime_error(std::string("PNG: ") + e.what());
  }
}

}  // namespace capflow::output
