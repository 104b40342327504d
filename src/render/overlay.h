// capflow/render/overlay: the Dear ImGui overlay drawn off-screen into every frame (no
// platform backend, no window): a labelled colour bar (the colour map as a vertical gradient,
// field name above it, 5 tick values at its right) and a text block (t, Ca, D, law) at the
// top left. Each part is switchable. Uses Dear ImGui's OpenGL3 backend, compiled from
// libimgui-dev's source with capflow's GL loader (see gl.h); requires a current GL context.
//
// Threads: Dear ImGui keeps a process-wide "current context"; every Overlay call takes a
// process-wide lock and selects its own context, so several renderers may coexist.
#pragma once

#include <string>
#include <vector>

#include "render/colormap.h"

struct ImGuiContext;
struct ImFont;

namespace capflow::render {

// Colour bar rectangle in pixels, origin top-left, y down. Value v maps to the row
//   y(v) = y1 - (v - vmin)/(vmax - vmin) * (y1 - y0)      (vmin at the bottom y1).
struct ColorbarGeometry {
  float x0, y0, x1, y1;
};
ColorbarGeometry colorbar_geometry(int width, int height);

struct OverlayContent {
  bool colorbar = false;
  const Colormap* colormap = nullptr;
  double vmin = 0, vmax = 1;
  bool under = false, over = false;  // values below vmin / above vmax: a triangle at that end
  std::string title;                 // above the bar (UTF-8: Greek, sub- and superscripts)
  bool text = false;
  std::vector<std::string> lines;  // the text block
  // Axis triad at the bottom left: the screen directions (x right, y up; length <= 1, shorter
  // when the axis points towards or away from the viewer) of the world axes x, y, z, and
  // whether each points towards the viewer (drawn last, over the others).
  bool triad = false;
  float axis_x[3] = {1, 0, 0}, axis_y[3] = {0, 1, 0};  // screen x and y of world x, y, z
  bool towards_viewer[3] = {false, false, true};
};

class Overlay {
 public:
  Overlay(int width, int height);  // GL context must be current
  ~Overlay();
  Overlay(const Overlay&) = delete;
  Overlay& operator=(const Overlay&) = delete;
  // Draws into the currently bound draw framebuffer (size width x height).
  void draw(const OverlayContent& c);

 private:
  int width_, height_;
  ImGuiContext* ctx_ = nullptr;
  ImFont* font_ = nullptr;
  float font_px_ = 13;
};

}  // namespace capflow::render
