#include "render/overlay.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>

#include "imgui.h"
#include "imgui_impl_opengl3.h"
#include "render/color_range.h"
#include "render/gl.h"

namespace capflow::render {
namespace {
std::mutex& imgui_mutex() {
  static std::mutex mu;
  return mu;
}
ImU32 to_u32(const std::array<float, 3>& c) {
  auto b = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.f, 1.f) * 255)); };
  return IM_COL32(b(c[0]), b(c[1]), b(c[2]), 255);
}
}  // namespace

ColorbarGeometry colorbar_geometry(int width, int height) {
  const float w = std::max(14.f, std::round(0.018f * width));
  const float label_room = std::max(64.f, std::round(0.065f * width));
  ColorbarGeometry g;
  g.x1 = std::round(width - label_room);
  g.x0 = g.x1 - w;
  g.y0 = std::round(0.22f * height);
  g.y1 = std::round(0.82f * height);
  return g;
}

Overlay::Overlay(int width, int height) : width_(width), height_(height) {
  std::lock_guard<std::mutex> lock(imgui_mutex());
  ImGuiContext* prev = ImGui::GetCurrentContext();
  ctx_ = ImGui::CreateContext();
  ImGui::SetCurrentContext(ctx_);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.LogFilename = nullptr;
  io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
  font_px_ = std::max(13.f, std::round(18.f * height / 720.f));
  // A scalable system font when present (fonts-dejavu-core), else ImGui's built-in one.
  const char* ttf = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  // Latin-1, Greek (tau), super- and subscripts (tau_1, G_s, G^-1) and the minus sign
  static const ImWchar kRanges[] = {0x0020, 0x00FF, 0x0370, 0x03FF, 0x2070,
                                    0x209F, 0x2212, 0x2212, 0};
  if (::access(ttf, R_OK) == 0)
    font_ = io.Fonts->AddFontFromFileTTF(ttf, font_px_, nullptr, kRanges);
  if (!font_) {
    ImFontConfig cfg;
    cfg.SizePixels = 13.f * std::max(1.f, std::round(font_px_ / 13.f));
    font_px_ = cfg.SizePixels;
    font_ = io.Fonts->AddFontDefault(&cfg);
  }
  const bool ok = ImGui_ImplOpenGL3_Init("#version 330 core");
  ImGui::SetCurrentContext(prev);
  if (!ok) throw std::runtime_error("overlay: ImGui_ImplOpenGL3_Init failed");
}

Overlay::~Overlay() {
  std::lock_guard<std::mutex> lock(imgui_mutex());
  ImGuiContext* prev = ImGui::GetCurrentContext();
  ImGui::SetCurrentContext(ctx_);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui::DestroyContext(ctx_);
  ImGui::SetCurrentContext(prev == ctx_ ? nullptr : prev);
}

void Overlay::draw(const OverlayContent& c) {
  if (!(c.colorbar && c.colormap) && !c.text && !c.triad) return;
  std::lock_guard<std::mutex> lock(imgui_mutex());
  ImGuiContext* prev = ImGui::GetCurrentContext();
  ImGui::SetCurrentContext(ctx_);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(width_), static_cast<float>(height_));
  io.DeltaTime = 1.f / 60.f;
  ImGui_ImplOpenGL3_NewFrame();  // required every frame (creates device objects lazily)
  ImGui::NewFrame();
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  const ImU32 ink = IM_COL32(20, 20, 20, 255);
  const float fs = font_px_;

  if (c.colorbar && c.colormap) {
    const ColorbarGeometry g = colorbar_geometry(width_, height_);
    const int segments = 256;
    const float h = g.y1 - g.y0;
    for (int k = 0; k < segments; ++k) {
      const float ya = g.y1 - h * k / segments, yb = g.y1 - h * (k + 1) / segments;
      const ImU32 ca = to_u32(c.colormap->at(static_cast<double>(k) / segments));
      const ImU32 cb = to_u32(c.colormap->at(static_cast<double>(k + 1) / segments));
      // upper-left, upper-right, bottom-right, bottom-left
      dl->AddRectFilledMultiColor(ImVec2(g.x0, yb), ImVec2(g.x1, ya), cb, cb, ca, ca);
    }
    dl->AddRect(ImVec2(g.x0 - 1, g.y0 - 1), ImVec2(g.x1 + 1, g.y1 + 1), ink, 0.f, 0, 1.f);
    // values beyond the range: a triangle in the end colour above / below the bar
    const float tw = g.x1 - g.x0, gap = 3.f, xm = 0.5f * (g.x0 + g.x1);
    if (c.over) {
      const ImVec2 a(g.x0, g.y0 - gap), b(g.x1, g.y0 - gap), t(xm, g.y0 - gap - tw);
      dl->AddTriangleFilled(a, b, t, to_u32(c.colormap->at(1.0)));
      dl->AddTriangle(a, b, t, ink, 1.f);
    }
    if (c.under) {
      const ImVec2 a(g.x0, g.y1 + gap), b(g.x1, g.y1 + gap), t(xm, g.y1 + gap + tw);
      dl->AddTriangleFilled(a, b, t, to_u32(c.colormap->at(0.0)));
      dl->AddTriangle(a, b, t, ink, 1.f);
    }
    // round tick values (multiples of a 1-2-5 step) at their place on the bar
    for (double v : round_ticks(c.vmin, c.vmax)) {
      const float y = g.y1 - static_cast<float>(h * (v - c.vmin) / (c.vmax - c.vmin));
      dl->AddLine(ImVec2(g.x1 + 1, y), ImVec2(g.x1 + 6, y), ink, 1.f);
      char buf[32];
      std::snprintf(buf, sizeof buf, "%g", std::abs(v));
      const std::string label = (v < 0 ? "\u2212" : "") + std::string(buf);  // a true minus
      dl->AddText(font_, fs, ImVec2(g.x1 + 9, y - 0.5f * fs), ink, label.c_str());
    }
    const ImVec2 ts = font_->CalcTextSizeA(fs, 1e9f, 0.f, c.title.c_str());
    const float tx = std::max(4.f, std::min(g.x0, width_ - 6.f - ts.x));
    const float above = c.over ? tw + gap : 0.f;  // the title clears the triangle
    dl->AddText(font_, fs, ImVec2(tx, g.y0 - above - 1.9f * fs), ink, c.title.c_str());
  }
  if (c.triad) {
    // world x, y, z in red, green, blue from a common origin, the ones pointing away from the
    // viewer first; each labelled at its tip
    const float len = std::max(28.f, std::round(0.075f * height_));
    const ImVec2 o(0.8f * fs + len * 1.15f, height_ - 0.8f * fs - len * 1.15f);
    const ImU32 colour[3] = {IM_COL32(200, 40, 40, 255), IM_COL32(30, 150, 50, 255),
                             IM_COL32(40, 80, 210, 255)};
    const char* name[3] = {"x", "y", "z"};
    for (int pass = 0; pass < 2; ++pass)
      for (int a = 0; a < 3; ++a) {
        if (c.towards_viewer[a] != (pass == 1)) continue;
        const ImVec2 tip(o.x + len * c.axis_x[a], o.y - len * c.axis_y[a]);
        dl->AddLine(o, tip, colour[a], 2.f);
        const float r = std::hypot(c.axis_x[a], c.axis_y[a]);
        const float ux = r > 1e-3f ? c.axis_x[a] / r : 0.f, uy = r > 1e-3f ? c.axis_y[a] / r : 0.f;
        const ImVec2 label(o.x + (len * r + 0.7f * fs) * ux - 0.3f * fs,
                           o.y - (len * r + 0.7f * fs) * uy - 0.55f * fs);
        dl->AddText(font_, fs, label, colour[a], name[a]);
      }
  }
  if (c.text) {
    float y = 0.6f * fs;
    for (const auto& line : c.lines) {
      dl->AddText(font_, fs, ImVec2(0.8f * fs, y), ink, line.c_str());
      y += 1.3f * fs;
    }
  }
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  ImGui::SetCurrentContext(prev);
}

}  // namespace capflow::render
