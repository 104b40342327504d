#include "output/jpeg_writer.h"

#include <turbojpeg.h>

#include <memory>
#include <stdexcept>

namespace capflow::output {

std::string encode_jpeg(int width, int height, const uint8_t* rgba, int quality) {
  if (width <= 0 || height <= 0 || !rgba) throw std::invalid_argument("encode_jpeg: empty image");
  struct Free {
    void operator()(void* h) const { tjDestroy(h); }
  };
  std::unique_ptr<void, Free> tj(tjInitCompress());
  if (!tj) throw std::runtime_error("JPEG: cannot start the encoder");
  unsigned char* buf = nullptr;
  unsigned long size = 0;
  if (tjCompress2(tj.get(), rgba, width, width * 4, height, TJPF_RGBA, &buf, &size, TJSAMP_420,
                  quality, TJFLAG_FASTDCT) != 0) {
    const std::string why = tjGetErrorStr2(tj.get());
    tjFree(buf);
    throw std::runtime_error("JPEG: " + why);
  }
  std::string out(reinterpret_cast<const char*>(buf), size);
  tjFree(buf);
  return out;
}

}  // namespace capflow::output
