// libFuzzer target for the checkpoint container (output/checkpoint.h): Checkpoint::parse on the
// input as it is, and again with its checksum and end marker made right, so that the record
// parser behind the CRC is reached too. Every input returns a checkpoint or throws
// CheckpointError naming the source; anything else (a crash, a huge allocation, another
// exception) is a bug. Built by scripts/fuzz; replayed over tests/fuzz/corpus_checkpoint by CTest.
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "output/checkpoint.h"

namespace {

void parse(const std::string& bytes) {
  try {
    const capflow::output::Checkpoint c = capflow::output::Checkpoint::parse(bytes, "fuzz.ckpt");
    (void)c;
  } catch (const capflow::output::CheckpointError& e) {
    if (std::string(e.what()).rfind("fuzz.ckpt", 0) != 0) {
      std::fprintf(stderr, "message does not name the file: %s\n", e.what());
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1u << 20)) return 0;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  parse(bytes);
  // the same body behind a valid header, checksum and end marker
  std::string b = "CAPFLOWC";
  const uint32_t version = capflow::output::Checkpoint::kFormatVersion;
  b.append(reinterpret_cast<const char*>(&version), 4);
  b += bytes;
  const uint32_t crc =
      static_cast<uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(b.data()), b.size()));
  b.append(reinterpret_cast<const char*>(&crc), 4);
  b.append("CKPTEND\0", 8);
  parse(b);
  return 0;
}
