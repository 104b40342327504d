#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "render/data_dir.h"
#include "render/gl.h"
#include "render/overlay.h"

namespace capflow::render {
namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

unsigned compile(GLenum type, const std::string& file) {
  const std::string src = read_data_file(file);
  const unsigned sh = glCreateShader(type);
  const char* p = src.c_str();
  glShaderSource(sh, 1, &p, nullptr);
  glCompileShader(sh);
  GLint ok = 0;
  glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {0};
    glGetShaderInfoLog(sh, sizeof log, nullptr, log);
    glDeleteShader(sh);
    throw std::runtime_error("shader " + file + " does not compile: " + log);
  }
  return sh;
}

unsigned program(const std::string& vert, const std::string& frag) {
  const unsigned vs = compile(GL_VERTEX_SHADER, vert), fs = compile(GL_FRAGMENT_SHADER, frag);
  const unsigned p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {0};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    throw std::runtime_error("shaders " + vert + " + " + frag + " do not link: " + log);
  }
  return p;
}

// Antialias::Lines (measured against 4x multisampling, tests/render
// AntialiasLinesMatchesMultisampling): the outline's one-pixel smooth lines are moved half a pixel
// inside the surface, so that they cover the background pixels beside the edge by the box-filter
// coverage of the surface there (centred on the edge they make it half a pixel heavier: 54 against
// 28 levels mean difference at the silhouette for no anti-aliasing, 19 with the inset); the element
// lines, drawn smooth, carry the ink of a multisampled line at 0.7 opacity.
constexpr float kOutlineInset = 0.5f;  // pixels
constexpr float kSmoothLineAlpha = 0.7f;

// Streams the per-vertex attributes into the bound vertex array's buffers: 0 position (3),
// 1 normal (3), 2 colour-field value (1), as the surface shaders read them. A buffer keeps its
// storage while the data fits (capacity[k], bytes): a software driver allocates fresh storage
// for every glBufferData, and fresh pages fault in on first touch.
void upload_vertices(const unsigned* vbo, size_t* capacity, const std::vector<float>& position,
                     const std::vector<float>& normal, const std::vector<float>& value) {
  const std::vector<float>* attr[3] = {&position, &normal, &value};
  const int comps[3] = {3, 3, 1};
  for (int k = 0; k < 3; ++k) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo[k]);
    const size_t bytes = attr[k]->size() * sizeof(float);
    if (bytes > capacity[k]) {
      capacity[k] = bytes + bytes / 4;  // room for a longer outline next frame
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capacity[k]), nullptr, GL_DYNAMIC_DRAW);
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(bytes), attr[k]->data());
    glEnableVertexAttribArray(k);
    glVertexAttribPointer(k, comps[k], GL_FLOAT, GL_FALSE, 0, nullptr);
  }
}

// A software rasteriser: Mesa's llvmpipe / softpipe / swrast, or OSMesa (always software).
bool is_software(const ContextInfo& info) {
  if (info.backend == Backend::OSMesa) return true;
  for (const char* name : {"llvmpipe", "softpipe", "swrast"})
    if (info.renderer.find(name) != std::string::npos) return true;
  return false;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}
}  // namespace

Renderer::Renderer(const RenderOptions& options) : opt_(options) {
  std::string err;
  if (!opt_.IsValid(&err)) throw std::invalid_argument("render options: " + err);
  colormap_ = Colormap::load(opt_.colormap);  // before the context: fail early on assets
  range_ = std::make_unique<ColorRange>(opt_.range_mode, colormap_.diverging(), opt_.range_min,
                                        opt_.range_max);
  context_ = GlContext::create(opt_.backend);
  surface_prog_ = program("shaders/surface.vert", "shaders/surface.frag");
  lines_prog_ = program("shaders/lines.vert", "shaders/lines.frag");

  glGenVertexArrays(1, &vao_);
  glGenBuffers(3, vbo_);
  glGenBuffers(1, &ebo_tri_);
  glGenBuffers(1, &ebo_lines_);

  const auto& tab = colormap_.table();
  std::vector<float> texels;
  for (const auto& c : tab) texels.insert(texels.end(), c.begin(), c.end());
  glGenTextures(1, &cmap_tex_);
  glBindTexture(GL_TEXTURE_2D, cmap_tex_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, static_cast<GLsizei>(tab.size()), 1, 0, GL_RGB,
               GL_FLOAT, texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

  glGenVertexArrays(1, &outline_vao_);
  glGenBuffers(3, outline_vbo_);

  antialias_ = opt_.antialias;
  if (antialias_ == Antialias::Auto)
    antialias_ = is_software(context_->info()) ? Antialias::Lines : Antialias::Multisample;
  if (antialias_ == Antialias::Multisample && opt_.msaa <= 1) antialias_ = Antialias::Off;
  create_framebuffers();
  if (antialias_ == Antialias::Multisample && !msaa_used_) antialias_ = Antialias::Off;
  overlay_ = std::make_unique<Overlay>(opt_.width, opt_.height);
}

Renderer::~Renderer() {
  overlay_.reset();
  if (!context_) return;
  glDeleteProgram(surface_prog_);
  glDeleteProgram(lines_prog_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteBuffers(3, vbo_);
  glDeleteVertexArrays(1, &outline_vao_);
  glDeleteBuffers(3, outline_vbo_);
  glDeleteBuffers(1, &ebo_tri_);
  glDeleteBuffers(1, &ebo_lines_);
  glDeleteTextures(1, &cmap_tex_);
  if (msaa_fbo_) {
    glDeleteFramebuffers(1, &msaa_fbo_);
    glDeleteRenderbuffers(2, msaa_rb_);
  }
  glDeleteFramebuffers(1, &fbo_);
  glDeleteRenderbuffers(2, rb_);
}

void Renderer::create_framebuffers() {
  const int w = opt_.width, h = opt_.height;
  glGenFramebuffers(1, &fbo_);
  glGenRenderbuffers(2, rb_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glBindRenderbuffer(GL_RENDERBUFFER, rb_[0]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb_[0]);
  glBindRenderbuffer(GL_RENDERBUFFER, rb_[1]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb_[1]);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("render: resolve framebuffer incomplete");
  if (antialias_ == Antialias::Multisample) {
    // The largest sample count the GL supports up to the request (llvmpipe: 4); a count the
    // framebuffer still refuses is halved down to 2, then off.
    int max_samples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    int samples = std::min(opt_.msaa, max_samples);
    if (samples != opt_.msaa)
      warnings_.push_back("render.msaa " + std::to_string(opt_.msaa) +
                          " is above what this GL supports (" + std::to_string(max_samples) +
                          "): using " + std::to_string(std::max(samples, 0)) + "x");
    for (; samples > 1; samples /= 2) {
      glGenFramebuffers(1, &msaa_fbo_);
      glGenRenderbuffers(2, msaa_rb_);
      glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
      glBindRenderbuffer(GL_RENDERBUFFER, msaa_rb_[0]);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_rb_[0]);
      glBindRenderbuffer(GL_RENDERBUFFER, msaa_rb_[1]);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_rb_[1]);
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE) break;
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glDeleteFramebuffers(1, &msaa_fbo_);
      glDeleteRenderbuffers(2, msaa_rb_);
      msaa_fbo_ = 0;
      warnings_.push_back("multisample framebuffer with " + std::to_string(samples) +
                          " samples is incomplete: trying " + std::to_string(samples / 2));
    }
    msaa_used_ = samples > 1 ? samples : 0;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// The outline as smooth lines with the surface's shading (its program and uniforms are bound).
void Renderer::draw_outline() {
  outline_segments(mesh_, camera_, opt_.camera.orthographic, &outline_);
  if (outline_.segments() == 0) return;
  glUseProgram(surface_prog_);
  glBindVertexArray(outline_vao_);
  upload_vertices(outline_vbo_, outline_capacity_, outline_.position, outline_.normal,
                  outline_.value);
  glUniform1f(glGetUniformLocation(surface_prog_, "u_inset"), kOutlineInset);
  glLineWidth(1.f);
  glDrawArrays(GL_LINES, 0, 2 * outline_.segments());
  glUniform1f(glGetUniformLocation(surface_prog_, "u_inset"), 0.0f);
}

void Renderer::render(const Snapshot& s, Image* out, FrameTimings* timings) {
  FrameTimings t;
  auto t0 = std::chrono::steady_clock::now();
  double c0 = process_cpu_ms();
  if (!upsampler_ || s.nb != upsampler_nb_) {
    upsampler_ = std::make_unique<Upsampler>(s.nb, opt_.subdivisions);
    upsampler_nb_ = s.nb;
  }
  upsampler_->build(s, opt_.field, &mesh_);
  t.upsample_ms = ms_since(t0);
  t.upsample_cpu_ms = process_cpu_ms() - c0;

  // Colour range (render/color_range.h).
  range_->update(mesh_.value_min, mesh_.value_max);
  vmin_ = range_->lo();
  vmax_ = range_->hi();
  camera_ = make_camera(opt_.camera, mesh_.bbox_min, mesh_.bbox_max,
                        static_cast<double>(opt_.width) / opt_.height);

  // Draw.
  t0 = std::chrono::steady_clock::now();
  c0 = process_cpu_ms();
  glBindVertexArray(vao_);
  upload_vertices(vbo_, vbo_capacity_, mesh_.position, mesh_.normal, mesh_.value);
  if (uploaded_indices_ != mesh_.triangles.size()) {
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_tri_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh_.triangles.size() * sizeof(uint32_t)),
                 mesh_.triangles.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_lines_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh_.lines.size() * sizeof(uint32_t)), mesh_.lines.data(),
                 GL_STATIC_DRAW);
    uploaded_indices_ = mesh_.triangles.size();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_ ? msaa_fbo_ : fbo_);
  glViewport(0, 0, opt_.width, opt_.height);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  // A closed surface seen from outside its bounding box shows no back face: cull them (the
  // triangles are counter-clockwise seen from outside; ~35 % of the draw on llvmpipe). From
  // inside the box (a custom eye) every face is drawn, the back faces lit from their inner side.
  bool outside = false;
  for (int c = 0; c < 3; ++c)
    outside = outside || camera_.eye[c] < mesh_.bbox_min[c] || camera_.eye[c] > mesh_.bbox_max[c];
  if (opt_.cull_back_faces && outside) {
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
  } else {
    glDisable(GL_CULL_FACE);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_TRUE);
  glClearColor(opt_.background[0], opt_.background[1], opt_.background[2], 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  glUseProgram(surface_prog_);
  glUniformMatrix4fv(glGetUniformLocation(surface_prog_, "u_view"), 1, GL_FALSE,
                     camera_.view.data());
  glUniformMatrix4fv(glGetUniformLocation(surface_prog_, "u_proj"), 1, GL_FALSE,
                     camera_.proj.data());
  glUniform1f(glGetUniformLocation(surface_prog_, "u_colormap_size"),
              static_cast<float>(colormap_.table().size()));
  glUniform2f(glGetUniformLocation(surface_prog_, "u_range"), static_cast<float>(vmin_),
              static_cast<float>(vmax_));
  glUniform1i(glGetUniformLocation(surface_prog_, "u_plain"), opt_.field == ColorField::Plain);
  glUniform3f(glGetUniformLocation(surface_prog_, "u_plain_color"), opt_.plain_color[0],
              opt_.plain_color[1], opt_.plain_color[2]);
  glUniform1i(glGetUniformLocation(surface_prog_, "u_ortho"), opt_.camera.orthographic);
  glUniform1i(glGetUniformLocation(surface_prog_, "u_colormap"), 0);
  glUniform1f(glGetUniformLocation(surface_prog_, "u_alpha"), 1.0f);
  glUniform1f(glGetUniformLocation(surface_prog_, "u_inset"), 0.0f);
  glUniform2f(glGetUniformLocation(surface_prog_, "u_viewport"), static_cast<float>(opt_.width),
              static_cast<float>(opt_.height));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, cmap_tex_);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.f, 1.f);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_tri_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(mesh_.triangles.size()), GL_UNSIGNED_INT,
                 nullptr);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_CULL_FACE);

  const bool smooth_lines = antialias_ == Antialias::Lines;
  if (smooth_lines) {
    // coverage-blended lines over the finished surface; they do not write depth
    glEnable(GL_BLEND);
    // colour blended by coverage; the destination alpha stays 1 (an opaque frame)
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glEnable(GL_LINE_SMOOTH);
    glDepthMask(GL_FALSE);
    draw_outline();
    glBindVertexArray(vao_);
  }
  if (opt_.element_lines) {
    glUseProgram(lines_prog_);
    glUniformMatrix4fv(glGetUniformLocation(lines_prog_, "u_view"), 1, GL_FALSE,
                       camera_.view.data());
    glUniformMatrix4fv(glGetUniformLocation(lines_prog_, "u_proj"), 1, GL_FALSE,
                       camera_.proj.data());
    glUniform1f(glGetUniformLocation(lines_prog_, "u_depth_bias"), 2e-3f);
    glUniform3f(glGetUniformLocation(lines_prog_, "u_color"), opt_.line_color[0],
                opt_.line_color[1], opt_.line_color[2]);
    glUniform1f(glGetUniformLocation(lines_prog_, "u_alpha"),
                smooth_lines ? kSmoothLineAlpha : 1.f);
    glDisableVertexAttribArray(1);
    glDisableVertexAttribArray(2);
    glLineWidth(std::max(1.f, std::round(opt_.height / 720.f)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_lines_);
    glDrawElements(GL_LINES, static_cast<GLsizei>(mesh_.lines.size()), GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  if (smooth_lines) {
    glDisable(GL_LINE_SMOOTH);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
  }
  if (msaa_fbo_) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
    glBlitFramebuffer(0, 0, opt_.width, opt_.height, 0, 0, opt_.width, opt_.height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  glFinish();
  t.draw_ms = ms_since(t0);
  t.draw_cpu_ms = process_cpu_ms() - c0;

  // Overlay.
  t0 = std::chrono::steady_clock::now();
  c0 = process_cpu_ms();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  OverlayContent oc;
  oc.colorbar = opt_.overlay_colorbar && opt_.field != ColorField::Plain;
  oc.colormap = &colormap_;
  oc.vmin = vmin_;
  oc.vmax = vmax_;
  oc.under = range_->under();
  oc.over = range_->over();
  oc.title = field_label(opt_.field);
  oc.text = opt_.overlay_text;
  oc.triad = opt_.overlay_triad;
  for (int a = 0; a < 3; ++a) {  // the view matrix's rotation: world axis a in eye coordinates
    oc.axis_x[a] = camera_.view[4 * a + 0];
    oc.axis_y[a] = camera_.view[4 * a + 1];
    oc.towards_viewer[a] = camera_.view[4 * a + 2] > 0;  // the eye looks along -z
  }
  if (oc.text) {
    oc.lines = {fmt("Gt = %.4g", s.time), fmt("Ca = %.4g", s.ca), fmt("D = %.4f", s.diag.D),
                "law: " + (s.law.empty() ? std::string("-") : s.law)};
    if (!s.flow.empty()) oc.lines.push_back("flow: " + s.flow);
  }
  overlay_->draw(oc);
  glFinish();
  t.overlay_ms = ms_since(t0);
  t.overlay_cpu_ms = process_cpu_ms() - c0;

  // Readback (GL rows are bottom-up; Image rows are top-down).
  t0 = std::chrono::steady_clock::now();
  c0 = process_cpu_ms();
  const size_t row = static_cast<size_t>(opt_.width) * 4;
  readback_.resize(row * opt_.height);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, opt_.width, opt_.height, GL_RGBA, GL_UNSIGNED_BYTE, readback_.data());
  out->width = opt_.width;
  out->height = opt_.height;
  out->rgba.resize(readback_.size());
  for (int y = 0; y < opt_.height; ++y)
    std::memcpy(&out->rgba[static_cast<size_t>(y) * row],
                &readback_[static_cast<size_t>(opt_.height - 1 - y) * row], row);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  t.readback_ms = ms_since(t0);
  t.readback_cpu_ms = process_cpu_ms() - c0;
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    throw std::runtime_error("render: OpenGL error " + std::to_string(e));
  if (timings) *timings = t;
}

}  // namespace capflow::render
