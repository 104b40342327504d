// capflow/render/context: a headless OpenGL 3.3+ core context (no X display, no window).
//
// Backends, both loaded at run time with dlopen (see gl.h for why nothing is linked):
//   EGL    : libEGL.so.1, EGL_PLATFORM_SURFACELESS_MESA display, EGL_KHR_no_config_context,
//            core profile 3.3 (Mesa gives 4.5 on llvmpipe). Preferred.
//   OSMesa : libOSMesa.so.8, OSMesaCreateContextAttribs with a core profile 3.3, made current
//            on a 16x16 dummy buffer. Fallback (deprecated upstream).
// Auto tries EGL, then OSMesa, and keeps the reasons of failures in ContextInfo::log.
// The context has no default framebuffer to speak of: draw into FBOs only.
//
// Threads: the context is made current in the thread that calls create() and must be used
// and destroyed in that thread (the renderer thread).
// Failure: create() throws std::runtime_error naming the backend(s) and the error codes.
#pragma once

#include <memory>
#include <string>

namespace capflow::render {

enum class Backend { Auto, Egl, OSMesa };

const char* backend_name(Backend b);            // "auto", "egl", "osmesa"
bool parse_backend(const std::string& s, Backend* out);

struct ContextInfo {
  Backend backend = Backend::Auto;  // the backend actually in use (Egl or OSMesa)
  std::string vendor, renderer, version, glsl_version;  // GL_VENDOR, GL_RENDERER, ...
  std::string log;  // what was tried, e.g. "egl: ok" or "egl: eglInitialize failed 0x3001"
  std::string summary() const;  // one line for the run log
};

class GlContext {
 public:
  virtual ~GlContext() = default;
  static std::unique_ptr<GlContext> create(Backend requested);
  const ContextInfo& info() const { return info_; }

 protected:
  ContextInfo info_;
};

}  // namespace capflow::render
