// PNG writer: a written image reads back bit-exactly (stb_image from the same libstb).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <vector>

#include "output/png_writer.h"
#include "stb_image.h"

namespace capflow::output {
namespace {

TEST(PngWriter, RoundTripIsExactAndAtomicWriteReplaces) {
  const int w = 37, h = 19;
  std::vector<uint8_t> img(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < img.size(); ++i) img[i] = static_cast<uint8_t>((i * 7919) % 251);
  for (size_t i = 3; i < img.size(); i += 4) img[i] = 255;
  const std::string path = std::string(::testing::TempDir()) + "capflow_png_" +
                           std::to_string(::getpid()) + ".png";
  write_png_atomic(path, w, h, img.data());
  int rw = 0, rh = 0, comp = 0;
  unsigned char* back = stbi_load(path.c_str(), &rw, &rh, &comp, 4);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  EXPECT_TRUE(std::equal(img.begin(), img.end(), back));
  stbi_image_free(back);
  std::remove(path.c_str());
  EXPECT_THROW(write_png("/nonexistent-dir/x.png", w, h, img.data()), std::runtime_error);
}

}  // namespace
}  // namespace capflow::output
