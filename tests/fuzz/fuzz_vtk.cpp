// libFuzzer target for the ParaView readers (output/vtk.h): parse_vtp and PvdCollection::parse on
// the input. Every input returns a surface (valid: VtkSurface::IsValid) or a collection, or throws
// std::runtime_error naming the file; anything else is a bug. Built by scripts/fuzz; replayed over
// tests/fuzz/corpus_vtk by CTest.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "output/vtk.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1u << 20)) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const capflow::output::VtkSurface s = capflow::output::parse_vtp(text, "fuzz.vtp");
    std::string err;
    if (!s.IsValid(&err)) {
      std::fprintf(stderr, "parse_vtp returned an invalid surface: %s\n", err.c_str());
      std::abort();
    }
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("fuzz.vtp") == std::string::npos) {
      std::fprintf(stderr, "message does not name the file: %s\n", e.what());
      std::abort();
    }
  }
  try {
    (void)capflow::output::PvdCollection::parse(text, "fuzz.pvd");
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("fuzz.pvd") == std::string::npos) {
      std::fprintf(stderr, "message does not name the file: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
