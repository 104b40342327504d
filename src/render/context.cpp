#include "render/context.h"

#include <dlfcn.h>

#define EGL_NO_X11 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "render/gl.h"

// OSMesa's header pulls in <GL/gl.h> prototypes, which must not meet gl.h; the few constants
// and signatures needed are restated here (values from GL/osmesa.h, Mesa 22).
namespace {
constexpr int kOSMesaFormat = 0x22, kOSMesaDepthBits = 0x30, kOSMesaStencilBits = 0x31,
              kOSMesaAccumBits = 0x32, kOSMesaProfile = 0x33, kOSMesaCoreProfile = 0x34,
              kOSMesaMajor = 0x36, kOSMesaMinor = 0x37;
using OSMesaContext = void*;
using PFNOSMESACREATECONTEXTATTRIBS = OSMesaContext (*)(const int*, OSMesaContext);
using PFNOSMESAMAKECURRENT = unsigned char (*)(OSMesaContext, void*, unsigned, int, int);
using PFNOSMESADESTROYCONTEXT = void (*)(OSMesaContext);
using PFNOSMESAGETPROCADDRESS = void* (*)(const char*);
}  // namespace

namespace capflow::render {

std::string ContextInfo::summary() const {
  return std::string("render: backend ") + backend_name(backend) + ", GL_RENDERER \"" +
         renderer + "\", GL_VERSION \"" + version + "\"";
}

namespace {

std::string hex(unsigned v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%04X", v);
  return b;
}

void* open_lib(const char* name, std::string* err) {
  // Libraries stay loaded for the life of the process: Mesa does not support unloading.
  void* h = dlopen(name, RTLD_NOW | RTLD_LOCAL);
  if (!h) *err = std::string("cannot load ") + name + " (" + dlerror() + ")";
  return h;
}

void fill_gl_info(ContextInfo* info) {
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  info->vendor = str(GL_VENDOR);
  info->renderer = str(GL_RENDERER);
  info->version = str(GL_VERSION);
  info->glsl_version = str(GL_SHADING_LANGUAGE_VERSION);
  if (info->renderer.empty())
    throw std::runtime_error("glGetString(GL_RENDERER) returned NULL: context is not usable");
}

// ---------------------------------------------------------------------------------- EGL
struct EglApi {
  PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
  PFNEGLGETPLATFORMDISPLAYPROC GetPlatformDisplay = nullptr;
  PFNEGLINITIALIZEPROC Initialize = nullptr;
  PFNEGLTERMINATEPROC Terminate = nullptr;
  PFNEGLBINDAPIPROC BindAPI = nullptr;
  PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
  PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
  PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
  PFNEGLGETERRORPROC GetError = nullptr;
  PFNEGLRELEASETHREADPROC ReleaseThread = nullptr;
};

const EglApi* egl_api(std::string* err) {
  static std::mutex mu;
  static EglApi api;
  static bool loaded = false;
  static std::string load_err;
  std::lock_guard<std::mutex> lock(mu);
  if (!loaded) {
    loaded = true;
    void* h = open_lib("libEGL.so.1", &load_err);
    if (h) {
      api.GetProcAddress =
          reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(dlsym(h, "eglGetProcAddress"));
      auto get = [&](const char* n) {
        void* p = dlsym(h, n);
        if (!p && api.GetProcAddress) p = reinterpret_cast<void*>(api.GetProcAddress(n));
        if (!p && load_err.empty()) load_err = std::string("libEGL lacks ") + n;
        return p;
      };
      api.GetPlatformDisplay =
          reinterpret_cast<PFNEGLGETPLATFORMDISPLAYPROC>(get("eglGetPlatformDisplay"));
      api.Initialize = reinterpret_cast<PFNEGLINITIALIZEPROC>(get("eglInitialize"));
      api.Terminate = reinterpret_cast<PFNEGLTERMINATEPROC>(get("eglTerminate"));
      api.BindAPI = reinterpret_cast<PFNEGLBINDAPIPROC>(get("eglBindAPI"));
      api.CreateContext = reinterpret_cast<PFNEGLCREATECONTEXTPROC>(get("eglCreateContext"));
      api.DestroyContext = reinterpret_cast<PFNEGLDESTROYCONTEXTPROC>(get("eglDestroyContext"));
      api.MakeCurrent = reinterpret_cast<PFNEGLMAKECURRENTPROC>(get("eglMakeCurrent"));
      api.GetError = reinterpret_cast<PFNEGLGETERRORPROC>(get("eglGetError"));
      api.ReleaseThread = reinterpret_cast<PFNEGLRELEASETHREADPROC>(get("eglReleaseThread"));
    }
  }
  if (!load_err.empty()) {
    *err = load_err;
    return nullptr;
  }
  return &api;
}

// eglTerminate is per display, not per context: count the live contexts.
std::mutex g_egl_mu;
int g_egl_users = 0;

class EglContext final : public GlContext {
 public:
  EglContext() {
    std::string err;
    api_ = egl_api(&err);
    if (!api_) throw std::runtime_error("egl: " + err);
    std::lock_guard<std::mutex> lock(g_egl_mu);
    dpy_ = api_->GetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy_ == EGL_NO_DISPLAY)
      throw std::runtime_error("egl: no surfaceless Mesa display (" + hex(api_->GetError()) + ")");
    EGLint major = 0, minor = 0;
    if (!api_->Initialize(dpy_, &major, &minor))
      throw std::runtime_error("egl: eglInitialize failed " + hex(api_->GetError()) +
                               " (is libgl1-mesa-dri installed?)");
    ++g_egl_users;
    if (!api_->BindAPI(EGL_OPENGL_API)) fail("eglBindAPI(EGL_OPENGL_API)");
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    ctx_ = api_->CreateContext(dpy_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (ctx_ == EGL_NO_CONTEXT) fail("eglCreateContext (core 3.3, no config)");
    if (!api_->MakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_)) fail("eglMakeCurrent");
    const char* missing = nullptr;
    auto loader = [](const char* n, void* u) -> void* {
      return reinterpret_cast<void*>(static_cast<const EglApi*>(u)->GetProcAddress(n));
    };
    if (!glfn::load_gl_functions(loader, const_cast<EglApi*>(api_), &missing))
      fail(std::string("eglGetProcAddress(") + missing + ")");
    info_.backend = Backend::Egl;
  }
  ~EglContext() override {
    std::lock_guard<std::mutex> lock(g_egl_mu);
    release();
  }

 private:
  void release() {
    if (ctx_ != EGL_NO_CONTEXT) {
      api_->MakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      api_->DestroyContext(dpy_, ctx_);
      ctx_ = EGL_NO_CONTEXT;
    }
    if (api_->ReleaseThread) api_->ReleaseThread();
    if (--g_egl_users == 0) api_->Terminate(dpy_);
  }
  [[noreturn]] void fail(const std::string& what) {
    std::string msg = "egl: " + what + " failed " + hex(api_->GetError());
    release();
    throw std::runtime_error(msg);
  }
  const EglApi* api_ = nullptr;
  EGLDisplay dpy_ = EGL_NO_DISPLAY;
  EGLContext ctx_ = EGL_NO_CONTEXT;
};

// ------------------------------------------------------------------------------- OSMesa
struct OSMesaApi {
  PFNOSMESACREATECONTEXTATTRIBS CreateContextAttribs = nullptr;
  PFNOSMESAMAKECURRENT MakeCurrent = nullptr;
  PFNOSMESADESTROYCONTEXT DestroyContext = nullptr;
  PFNOSMESAGETPROCADDRESS GetProcAddress = nullptr;
};

const OSMesaApi* osmesa_api(std::string* err) {
  static std::mutex mu;
  static OSMesaApi api;
  static bool loaded = false;
  static std::string load_err;
  std::lock_guard<std::mutex> lock(mu);
  if (!loaded) {
    loaded = true;
    void* h = open_lib("libOSMesa.so.8", &load_err);
    if (h) {
      auto get = [&](const char* n) {
        void* p = dlsym(h, n);
        if (!p && load_err.empty()) load_err = std::string("libOSMesa lacks ") + n;
        return p;
      };
      api.CreateContextAttribs =
          reinterpret_cast<PFNOSMESACREATECONTEXTATTRIBS>(get("OSMesaCreateContextAttribs"));
      api.MakeCurrent = reinterpret_cast<PFNOSMESAMAKECURRENT>(get("OSMesaMakeCurrent"));
      api.DestroyContext = reinterpret_cast<PFNOSMESADESTROYCONTEXT>(get("OSMesaDestroyContext"));
      api.GetProcAddress = reinterpret_cast<PFNOSMESAGETPROCADDRESS>(get("OSMesaGetProcAddress"));
    }
  }
  if (!load_err.empty()) {
    *err = load_err;
    return nullptr;
  }
  return &api;
}

class OSMesaGlContext final : public GlContext {
 public:
  OSMesaGlContext() : dummy_(16 * 16 * 4) {
    std::string err;
    api_ = osmesa_api(&err);
    if (!api_) throw std::runtime_error("osmesa: " + err);
    const int attribs[] = {kOSMesaFormat, GL_RGBA, kOSMesaDepthBits, 24, kOSMesaStencilBits, 0,
                           kOSMesaAccumBits, 0, kOSMesaProfile, kOSMesaCoreProfile,
                           kOSMesaMajor, 3, kOSMesaMinor, 3, 0};
    ctx_ = api_->CreateContextAttribs(attribs, nullptr);
    if (!ctx_) throw std::runtime_error("osmesa: OSMesaCreateContextAttribs (core 3.3) failed");
    if (!api_->MakeCurrent(ctx_, dummy_.data(), GL_UNSIGNED_BYTE, 16, 16)) {
      api_->DestroyContext(ctx_);
      throw std::runtime_error("osmesa: OSMesaMakeCurrent failed");
    }
    const char* missing = nullptr;
    auto loader = [](const char* n, void* u) -> void* {
      return static_cast<const OSMesaApi*>(u)->GetProcAddress(n);
    };
    if (!glfn::load_gl_functions(loader, const_cast<OSMesaApi*>(api_), &missing)) {
      api_->DestroyContext(ctx_);
      throw std::runtime_error(std::string("osmesa: OSMesaGetProcAddress(") + missing +
                               ") failed");
    }
    info_.backend = Backend::OSMesa;
  }
  ~OSMesaGlContext() override {
    api_->MakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
    api_->DestroyContext(ctx_);
  }

 private:
  const OSMesaApi* api_ = nullptr;
  OSMesaContext ctx_ = nullptr;
  std::vector<unsigned char> dummy_;
};

}  // namespace

std::unique_ptr<GlContext> GlContext::create(Backend requested) {
  std::vector<Backend> order;
  if (requested == Backend::Auto) order = {Backend::Egl, Backend::OSMesa};
  else order = {requested};
  std::string log;
  for (Backend b : order) {
    try {
      std::unique_ptr<GlContext> c;
      if (b == Backend::Egl) c = std::make_unique<EglContext>();
      else c = std::make_unique<OSMesaGlContext>();
      fill_gl_info(&c->info_);
      log += std::string(backend_name(b)) + ": ok";
      c->info_.log = log;
      return c;
    } catch (const std::exception& e) {
      log += std::string(e.what()) + "; ";
    }
  }
  throw std::runtime_error("no headless OpenGL context (requested " +
                           std::string(backend_name(requested)) + "): " + log);
}

}  // namespace capflow::render
