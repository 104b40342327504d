#include "render/gl.h"

#include <mutex>
#include <string_view>

namespace capflow::glfn {
#define CAPFLOW_GL_DEFINE(type, name) type name = nullptr;
CAPFLOW_GL_FUNCTIONS(CAPFLOW_GL_DEFINE)
#undef CAPFLOW_GL_DEFINE

bool load_gl_functions(ProcLoader loader, void* user, const char** missing) {
  // Serialised: two renderer threads of the same backend may load concurrently; they store
  // identical values, but unsynchronised stores would still be a data race.
  static std::mutex mu;
  std::lock_guard<std::mutex> lock(mu);
#define CAPFLOW_GL_LOAD(type, name)                                     \
  name = reinterpret_cast<type>(loader(#name, user));                   \
  if (!name && std::string_view(#name) != "glClipControl") {            \
    if (missing) *missing = #name;                                      \
    return false;                                                       \
  }
  CAPFLOW_GL_FUNCTIONS(CAPFLOW_GL_LOAD)
#undef CAPFLOW_GL_LOAD
  return true;
}
}  // namespace capflow::glfn
