#include "output/png_writer.h"

#include <cstdio>
#include <stdexcept>

#include "stb_image_write.h"

namespace capflow::output {

void write_png(const std::string& path, int width, int height, const uint8_t* rgba, int stride) {
  if (width <= 0 || height <= 0 || !rgba) throw std::invalid_argument("write_png: empty image");
  if (!stbi_write_png(path.c_str(), width, height, 4, rgba, stride ? stride : width * 4))
    throw std::runtime_error("cannot write PNG " + path);
}

void write_png_atomic(const std::string& path, int width, int height, const uint8_t* rgba,
                      int stride) {
  const std::string tmp = path + ".tmp";
  write_png(tmp, width, height, rgba, stride);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

}  // namespace capflow::output
