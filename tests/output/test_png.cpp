// PNG writer: a written image reads back bit-exactly (stb_image from the same libstb), opaque
// ones as RGB, translucent ones with their alpha; a stride longer than the row is honoured.
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
  write_png(path, w, h, img.data());
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

TEST(PngWriter, OpaqueImagesAreStoredAsRgbOthersKeepAlpha) {
  const int w = 23, h = 11, stride = w * 4 + 12;  // rows padded: only w pixels of each are read
  std::vector<uint8_t> img(static_cast<size_t>(stride) * h, 7);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < 4 * w; ++x)
      img[static_cast<size_t>(y) * stride + x] =
          (x % 4 == 3) ? 255 : static_cast<uint8_t>((x * 31 + y * 17) % 256);
  const std::string path = std::string(::testing::TempDir()) + "capflow_png_alpha_" +
                           std::to_string(::getpid()) + ".png";
  auto check = [&](int expect_comp) {
    write_png(path, w, h, img.data(), stride);
    int rw = 0, rh = 0, comp = 0;
    unsigned char* back = stbi_load(path.c_str(), &rw, &rh, &comp, 4);
    ASSERT_NE(back, nullptr);
    EXPECT_EQ(comp, expect_comp);
    ASSERT_EQ(rw, w);
    ASSERT_EQ(rh, h);
    for (int y = 0; y < h; ++y)
      EXPECT_TRUE(std::equal(img.begin() + static_cast<long>(y) * stride,
                             img.begin() + static_cast<long>(y) * stride + 4 * w,
                             back + static_cast<size_t>(y) * w * 4))
          << "row " << y;
    stbi_image_free(back);
  };
  check(3);
  img[static_cast<size_t>(h - 1) * stride + 4 * (w - 1) + 3] = 128;  // last pixel translucent
  check(4);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace capflow::output
