// capflow/output/jpeg_writer: JPEG in memory via libjpeg-turbo (TurboJPEG API), for the live
// console's frames (a 1280x720 frame: ~100 KB and a few ms, against ~9 ms and ~1 MB as PNG).
// Pixels are 8-bit RGBA, rows top-down, width*4 bytes apart; 4:2:0 chroma, quality 1..100.
// Failure: std::runtime_error with TurboJPEG's message.
#pragma once

#include <cstdint>
#include <string>

namespace capflow::output {

std::string encode_jpeg(int width, int height, const uint8_t* rgba, int quality = 85);

}  // namespace capflow::output
