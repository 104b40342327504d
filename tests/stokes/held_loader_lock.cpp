// A library whose constructor holds the dynamic loader's lock until the test lets it go: dlopen
// runs constructors with dl_load_lock held, as it does while it relocates a large library (the
// renderer's llvmpipe). The file descriptors come from the environment (test_thread_buffers.cpp):
// the constructor writes one byte to CAPFLOW_TEST_CTOR_STARTED, then waits for one byte on
// CAPFLOW_TEST_CTOR_RELEASE.
#include <unistd.h>

#include <cstdlib>

namespace {
__attribute__((constructor)) void hold_loader_lock() {
  const char* started = std::getenv("CAPFLOW_TEST_CTOR_STARTED");
  const char* release = std::getenv("CAPFLOW_TEST_CTOR_RELEASE");
  if (!started || !release) return;
  char c = 1;
  if (write(std::atoi(started), &c, 1) != 1) return;
  while (read(std::atoi(release), &c, 1) < 0) {
  }
}
}  // namespace
