// capflow/control/schema_fields: the field table - every key of the control file, and its groups.
#include <algorithm>
#include <iterator>

#include "capsule/viscosity_ratio.h"
#include "control/limits.h"
#include "control/schema_builders.h"

namespace capflow::control::schema {

namespace detail {

std::vector<Field> build_fields() {
  using O = ControlOptions;
  std::vector<Field> t;
  t.push_back(text(
      "description", [](O& o) -> std::string& { return o.description; }, true, kMaxDescriptionBytes,
      "a free-text description of the run", "text of at most 65536 bytes", kFrozen,
      "free text, logged with the run"));
  t.back().info.default_value = "\"\"";
  // capsule
  t.push_back(choice(
      "capsule.law", [](const O& o) { return static_cast<int>(o.law.kind); },
      [](O& o, int i) { o.law.kind = static_cast<membrane::LawKind>(i); },
      {"skalak", "neo-hookean", "mooney-rivlin"}, kFrozen, "membrane law (paper eqs. 11-13)"));
  t.push_back(number(
      "capsule.C", [](O& o) -> double& { return o.law.c; }, open_closed(-0.5, 1e4),
      "the Skalak area-dilatation parameter C", "", kFrozen,
      "Skalak area-dilatation parameter (area modulus (1+2C) Gs)"));
  t.push_back(number(
      "capsule.psi", [](O& o) -> double& { return o.law.psi; }, closed(0, 1),
      "the Mooney-Rivlin parameter psi", "", kFrozen, "Mooney-Rivlin parameter (1 = neo-Hookean)"));
  t.push_back(custom(
      {"capsule.shape", "string or object",
       "\"sphere\" | \"biconcave\" | {\"biconcave\": {\"axis\": A}} | {\"spheroid\": "
       "{\"aspect\": r in [0.1, 10], \"axis\": A}}, A one of \"x\", \"y\", \"z\" (default z)",
       "\"sphere\"", "a", kFrozen,
       "the stress-free reference shape, also the initial shape, scaled to the equal-volume "
       "radius a: a sphere, the Evans-Fung red blood cell, or a spheroid with polar/equatorial "
       "aspect r (> 1 prolate), about their symmetry axis"},
      [](const json& v, ReadContext& c) {
        geometry::ReferenceShape& s = c.options.shape;
        s = geometry::ReferenceShape{};
        if (v.is_string() && v.get<std::string>() == "sphere") return;
        if (v.is_string() && v.get<std::string>() == "biconcave") {
          s.kind = geometry::ReferenceShape::Kind::Biconcave;
          return;
        }
        auto sp = v.is_object() && v.size() == 1 ? v.find("spheroid") : v.end();
        bool spheroid = true;
        if (v.is_object() && v.size() == 1 && sp == v.end()) {
          sp = v.find("biconcave");
          spheroid = false;
        }
        if (sp == v.end() || !sp->is_object())
          return add_error(c, "capsule.shape",
                           "value " + show(v) + " is not valid: give \"sphere\", \"biconcave\", "
                           "{\"biconcave\": {\"axis\": \"x\"}} or {\"spheroid\": {\"aspect\": r, "
                           "\"axis\": \"z\"}}");
        const std::string at = std::string("capsule.shape.") + (spheroid ? "spheroid." : "biconcave.");
        s.kind = spheroid ? geometry::ReferenceShape::Kind::Spheroid
                          : geometry::ReferenceShape::Kind::Biconcave;
        for (auto it = sp->begin(); it != sp->end(); ++it) {
          if (it.key() == "aspect" && spheroid) {
            if (!it->is_number() || !(it->get<double>() >= 0.1 && it->get<double>() <= 10))
              return add_error(c, at + "aspect",
                               "value " + show(*it) + " is out of range: the aspect must be a "
                               "number in [0.1, 10]");
            s.aspect = it->get<double>();
          } else if (it.key() == "axis") {
            const std::string a = it->is_string() ? it->get<std::string>() : "";
            if (a != "x" && a != "y" && a != "z")
              return add_error(c, at + "axis",
                               "value " + show(*it) + " is not valid: \"x\", \"y\" or \"z\"");
            s.axis = a == "x" ? 0 : a == "y" ? 1 : 2;
          } else {
            return add_error(c, at + it.key(),
                             spheroid ? "is not a key of a spheroid (aspect, axis)"
                                      : "is not a key of the biconcave shape (axis)");
          }
        }
        if (spheroid && sp->find("aspect") == sp->end())
          add_error(c, "capsule.shape.spheroid.aspect", "is required (a number in [0.1, 10])");
      },
      [](const O& o) -> std::optional<json> {
        const geometry::ReferenceShape& s = o.shape;
        const std::string axis(1, "xyz"[s.axis]);
        if (s.kind == geometry::ReferenceShape::Kind::Spheroid)
          return json{{"spheroid", {{"aspect", s.aspect}, {"axis", axis}}}};
        if (s.kind == geometry::ReferenceShape::Kind::Biconcave && s.axis != 2)
          return json{{"biconcave", {{"axis", axis}}}};
        return json(geometry::shape_name(s.kind));
      },
      [](O& dst, const O& src) { dst.shape = src.shape; }));
  t.push_back(number(
      "capsule.bending.modulus", [](O& o) -> double& { return o.bending.modulus; }, closed(0, 1),
      "the bending modulus Eb", "Gs a^2", kFrozen,
      "Eb = kappa_b / (Gs a^2), the bending stiffness (0: none; red blood cells ~5e-3)"));
  t.push_back(choice(
      "capsule.bending.model", [](const O& o) { return static_cast<int>(o.bending.model); },
      [](O& o, int i) { o.bending.model = static_cast<membrane::BendingModel>(i); },
      {"helfrich", "reference"}, kFrozen,
      "helfrich: W = (kappa_b/2) INT (2H - c0)^2 dA with a uniform c0; reference: c0 = 2H of the "
      "reference shape at each material point (shape memory)"));
  t.push_back(number(
      "capsule.bending.c0", [](O& o) -> double& { return o.bending.c0; }, closed(-10, 10),
      "the spontaneous curvature c0", "1/a", kFrozen,
      "spontaneous curvature of the helfrich model (2/a: the sphere's own)"));
  t.push_back(number(
      "capsule.viscosity_ratio", [](O& o) -> double& { return o.viscosity_ratio; },
      open_closed(0, capsule::kMaxViscosityRatio), "the viscosity ratio", "", kFrozen,
      "lambda, inner / outer viscosity; other than 1, each velocity evaluation solves the "
      "double-layer equation by GMRES"));
  // mesh
  t.push_back(integer_of(
      "mesh.elements", [](O& o) -> int& { return o.mesh.elements; }, {6, 10, 14},
      "the element division", "", kFrozen, "elements of the sphere (paper fig. 1)"));
  t.push_back(integer(
      "mesh.nb", [](O& o) -> int& { return o.mesh.nb; }, 4, 24, "nodes per element direction", "",
      kFrozen, "Gauss-Lobatto nodes per element direction"));
  {
    Field f = choice(
        "mesh.division", [](const O& o) { return static_cast<int>(o.mesh.division); },
        [](O& o, int i) { o.mesh.division = static_cast<geometry::Division>(i); },
        {"cube", "box", "diagonal"}, kFrozen,
        "cube: faces split in equal angles; box: the paper's parallelepiped; diagonal (NE=6 "
        "only): the cube turned 45 degrees about z (docs/validation.md)");
    f.info.default_value =
        "planar extension: \"diagonal\" (NE=6), \"box\" (NE=10), \"cube\" (NE=14); otherwise "
        "\"cube\"";
    t.push_back(f);
  }
  // start
  {
    Field f = text(
        "start.from", [](O& o) -> std::string& { return o.start.from; }, false, 4096,
        "a run directory or checkpoint file to start from", "a run directory or a .ckpt file",
        kFrozen,
        "start from that run's newest checkpoint, resampled onto this mesh; time "
        "goes on from its t");
    f.info.default_value = "none: the unstressed sphere at t = 0";
    t.push_back(f);
  }
  {
    Field f = boolean(
        "start.restore_volume", [](O& o) -> bool& { return o.start.restore_volume; }, kFrozen,
        "scale the resampled shape to the sphere's volume");
    // Without start.from it means nothing: left out at its default, but written when set (so
    // that a live edit of it is seen, and refused like any frozen key).
    const auto write = f.write;
    f.write = [write](const O& o) {
      return o.start.from.empty() && o.start.restore_volume ? std::nullopt : write(o);
    };
    f.info.default_value = "true";
    t.push_back(f);
  }
  // flow
  t.push_back(choice(
      "flow.type", [](const O& o) { return static_cast<int>(o.flow.type); },
      [](O& o, int i) {
        if (i == 0) o.flow = capsule::Flow::planar_extension();
        if (i == 1) o.flow = capsule::Flow::simple_shear();
        if (i == 2) o.flow.type = capsule::FlowType::Custom;  // flow.gradient sets G
      },
      {"planar-extension", "simple-shear", "custom"}, kFrozen,
      "u = (x, -y, 0), (z, 0, 0), or u = G x with flow.gradient"));
  t.push_back(custom(
      {"flow.gradient", "3 x 3 numbers",
       "rows of numbers in [-100, 100], not all 0, trace 0 (below 1e-9 of the largest: removed)",
       "none: required with \"custom\", refused otherwise", "G", kFrozen,
       "velocity gradient G_ij = du_i/dx_j; its scale sets the time unit and Ca"},
      read_gradient, [](const O& o) -> std::optional<json> {
        if (o.flow.type != capsule::FlowType::Custom) return std::nullopt;
        json rows = json::array();
        for (int i = 0; i < 3; ++i)
          rows.push_back({o.flow.gradient(i, 0), o.flow.gradient(i, 1), o.flow.gradient(i, 2)});
        return rows;
      }));
  // time
  t.push_back(custom(
      {"time.dt", "number or \"auto\"",
       "\"auto\", or a number in " + closed(kMinTimeStep, 0.1).text(), "\"auto\"", "1/G", kLive,
       "\"auto\": adaptive steps that keep the local error below time.tolerance and find the "
       "stability limit; a number: the fixed RK4 step (stable for dt < O(Ca dx_min))"},
      [](const json& v, ReadContext& c) {
        if (v.is_string() && v.get<std::string>() == "auto") {
          c.options.time.adaptive = true;
          return;
        }
        double d = 0;
        const std::string issue =
            number_issue(v, closed(kMinTimeStep, 0.1), "the time step dt (or \"auto\")", &d);
        if (!issue.empty()) return add_error(c, "time.dt", issue);
        c.options.time.adaptive = false;
        c.options.time.dt = d;
      },
      [](const O& o) -> std::optional<json> {
        return o.time.adaptive ? json("auto") : json(o.time.dt);
      },
      [](O& d, const O& s) {
        d.time.adaptive = s.time.adaptive;
        d.time.dt = s.time.dt;
      }));
  t.push_back(number(
      "time.tolerance", [](O& o) -> double& { return o.time.tolerance; }, closed(1e-10, 1e-2),
      "the local error tolerance", "a", kLive,
      "adaptive steps (time.dt \"auto\"): relative and absolute local error per step of the "
      "node positions"));
  t.push_back(choice(
      "time.method", [](const O& o) { return static_cast<int>(o.time.method); },
      [](O& o, int i) { o.time.method = static_cast<TimeMethod>(i); },
      {"cash-karp", "chebyshev"}, kFrozen,
      "adaptive steps (time.dt \"auto\"): \"cash-karp\", the explicit 5(4) pair, whose steps "
      "settle at the stability limit O(Ca dx / C); \"chebyshev\", a strongly damped second-order "
      "Runge-Kutta-Chebyshev method whose stages grow with the stiffness: for stiff membranes "
      "(large C, bending, fine meshes, low Ca), 2x to 7x fewer velocity evaluations on a red "
      "cell. capflow steady's approach always uses \"cash-karp\" (it measures the stability "
      "limit)"));
  t.back().info.default_value = "\"cash-karp\"";
  t.push_back(number(
      "time.t_end", [](O& o) -> double& { return o.time.t_end; }, open_closed(0, 1e6),
      "the end time t_end", "1/G", kLive,
      "simulated end time (fixed dt: at least dt, at most 1e7 steps)"));
  // ca
  t.push_back(custom(
      {"ca", "number, list or object", "(0, 100], a list of segments or a continuation (below)",
       "required", "", kLive, "capillary number mu G a / Gs, or a schedule of segments"},
      [](const json& v, ReadContext& c) { read_schedule(v, &c.errors, &c.options.ca); },
      [](const O& o) -> std::optional<json> { return schedule_json(o.ca); },
      [](O& d, const O& s) { d.ca = s.ca; }));
  // steady
  t.push_back(number(
      "steady.tolerance", [](O& o) -> double& { return o.steady.tolerance; }, open_closed(0, 1),
      "the steady-state rate tolerance", "a G", kLive,
      "steady when max |dL/dt|, |dS/dt|, |dW/dt| over the window is below this"));
  t.push_back(number(
      "steady.window", [](O& o) -> double& { return o.steady.window; }, open_closed(0, 100),
      "the steady-state window", "1/G", kLive, "time over which the rates are measured"));
  t.push_back(number(
      "steady.min_hold", [](O& o) -> double& { return o.steady.min_hold; }, closed(0, 1e4),
      "the minimum hold time", "1/G", kLive,
      "minimum time at a level before a steady state counts"));
  t.push_back(boolean(
      "steady.stop", [](O& o) -> bool& { return o.steady.stop; }, kLive,
      "end the run at the steady state of the final level"));
  t.push_back(number(
      "steady.solve_tolerance", [](O& o) -> double& { return o.steady.solve_tolerance; },
      closed(1e-12, 1e-3), "capflow steady's residual tolerance", "a G", kLive,
      "capflow steady: largest node velocity of the step-map residual at a steady state"));
  // output
  t.push_back(text(
      "output.dir", [](O& o) -> std::string& { return o.output.dir; }, false, 4096,
      "the run directory", "a path", kFrozen, "run directory (created; -o overrides it)"));
  t.push_back(number(
      "output.csv_every", [](O& o) -> double& { return o.output.csv_every; }, open_closed(0, 1e6),
      "the CSV cadence", "1/G", kLive, "timeseries.csv cadence"));
  t.push_back(number(
      "output.frame_every", [](O& o) -> double& { return o.output.frame_every; }, closed(0, 1e6),
      "the frame cadence (0: none)", "1/G", kLive, "movie/PNG frame cadence (0: no frames)"));
  t.push_back(boolean(
      "output.png", [](O& o) -> bool& { return o.output.png; }, kFrozen,
      "write frames as frames/frame_NNNNNN.png"));
  t.push_back(integer(
      "output.mp4.fps", [](O& o) -> int& { return o.output.mp4.fps; }, 1, 240, "frames per second",
      "1/s", kFrozen, "movie frame rate"));
  t.push_back(integer(
      "output.mp4.quality", [](O& o) -> int& { return o.output.mp4.quality; }, 0, 51,
      "the x264 CRF (0 best, 51 worst)", "", kFrozen,
      "x264 constant rate factor (lower is better)"));
  t.push_back(number(
      "output.checkpoint_every", [](O& o) -> double& { return o.output.checkpoint_every; },
      closed(0, 1e6), "the checkpoint cadence (0: only at the start and the end)", "1/G", kLive,
      "checkpoint cadence (0: at the start, the end and on request only)"));
  t.push_back(number(
      "output.vtk_every", [](O& o) -> double& { return o.output.vtk_every; }, closed(0, 1e6),
      "the ParaView output cadence (0: none)", "1/G", kLive, "ParaView surface cadence (0: none)"));
  t.push_back(integer(
      "output.vtk_points", [](O& o) -> int& { return o.output.vtk_points; }, 0, 64,
      "the ParaView surface's points per element edge (0: the nodes, else 2 to 64)", "", kFrozen,
      "ParaView surface points per element edge: the interpolant at n Gauss-Lobatto points "
      "(0: the nodes)"));
  // render
  t.push_back(integer(
      "render.width", [](O& o) -> int& { return o.render.width; }, 16, render::kMaxWidth,
      "the frame width in pixels", "px", kFrozen, "frame width (even)"));
  t.push_back(integer(
      "render.height", [](O& o) -> int& { return o.render.height; }, 16, render::kMaxHeight,
      "the frame height in pixels", "px", kFrozen, "frame height (even)"));
  t.push_back(choice(
      "render.view",
      [](const O& o) {
        const int v = static_cast<int>(o.render.camera.view);
        return v <= 3 ? v : 0;
      },
      [](O& o, int i) { o.render.camera.view = static_cast<render::View>(i); },
      {"oblique", "xy", "xz", "yz"}, kFrozen, "camera direction"));
  t.push_back(boolean(
      "render.orthographic", [](O& o) -> bool& { return o.render.camera.orthographic; }, kFrozen,
      "orthographic instead of perspective projection"));
  // The colour fields a control file names, in the order of the choice's values.
  static constexpr render::ColorField kFields[] = {
      render::ColorField::MaxTension, render::ColorField::MinTension,
      render::ColorField::MeanTension, render::ColorField::Plain,
      render::ColorField::BendingEnergy};
  t.push_back(choice(
      "render.field",
      [](const O& o) {
        const auto* at = std::find(std::begin(kFields), std::end(kFields), o.render.field);
        return at == std::end(kFields) ? 0 : static_cast<int>(at - std::begin(kFields));
      },
      [](O& o, int i) { o.render.field = kFields[i]; },
      {"max-tension", "min-tension", "mean-tension", "plain", "bending-energy"}, kFrozen,
      "colour field (bending-energy: (kappa_b / 2)(2H - c0)^2, Gs; zero without bending)"));
  t.push_back(choice(
      "render.colormap", [](const O& o) { return static_cast<int>(o.render.colormap); },
      [](O& o, int i) { o.render.colormap = static_cast<render::ColorMap>(i); },
      {"viridis", "coolwarm"}, kFrozen, "colour map (coolwarm: symmetric range)"));
  t.push_back(custom(
      {"render.range", "\"auto\", \"frame\" or [min, max]",
       "\"auto\" | \"frame\" | [min, max] with min < max, both within +-1e12, max - min at "
       "least 1e-12 and 1e-9 of the larger bound",
       "\"auto\"", "Gs", kFrozen,
       "colour range: \"auto\" holds every value drawn so far and only grows (one colour, one "
       "tension over a movie), \"frame\" each frame's own, [min, max] fixed (beyond it marked "
       "on the bar)"},
      [](const json& v, ReadContext& c) {
        render::RenderOptions& ro = c.options.render;
        if (v.is_string() && v.get<std::string>() == "auto") {
          ro.range_mode = render::RangeMode::Grow;
        } else if (v.is_string() && v.get<std::string>() == "frame") {
          ro.range_mode = render::RangeMode::Frame;
        } else if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number()) {
          const std::string why =
              render::fixed_range_problem(v[0].get<double>(), v[1].get<double>());
          if (!why.empty()) {
            add_error(c, "render.range", "value " + show(v) + " is not valid: " + why);
            return;
          }
          ro.range_mode = render::RangeMode::Fixed;
          ro.range_min = v[0].get<double>();
          ro.range_max = v[1].get<double>();
        } else {
          add_error(c, "render.range",
                    "value " + show(v) +
                        " is not valid: range must be \"auto\", \"frame\" or "
                        "[min, max] with min < max");
        }
      },
      [](const O& o) -> std::optional<json> {
        const render::RenderOptions& ro = o.render;
        if (ro.range_mode == render::RangeMode::Fixed)
          return json::array({ro.range_min, ro.range_max});
        return json(ro.range_mode == render::RangeMode::Frame ? "frame" : "auto");
      }));
  t.push_back(boolean(
      "render.element_lines", [](O& o) -> bool& { return o.render.element_lines; }, kFrozen,
      "draw element edges"));
  t.push_back(boolean(
      "render.overlay.colorbar", [](O& o) -> bool& { return o.render.overlay_colorbar; }, kFrozen,
      "colour bar"));
  t.push_back(boolean(
      "render.overlay.text", [](O& o) -> bool& { return o.render.overlay_text; }, kFrozen,
      "t, Ca, D and the law in the corner"));
  t.push_back(choice(
      "render.backend", [](const O& o) { return static_cast<int>(o.render.backend); },
      [](O& o, int i) { o.render.backend = static_cast<render::Backend>(i); },
      {"auto", "egl", "osmesa"}, kFrozen, "headless GL (auto: EGL, then OSMesa)"));
  t.push_back(choice(
      "render.antialias", [](const O& o) { return static_cast<int>(o.render.antialias); },
      [](O& o, int i) { o.render.antialias = static_cast<render::Antialias>(i); },
      {"auto", "msaa", "lines", "off"}, kFrozen,
      "edge anti-aliasing: msaa (render.msaa samples), lines (smooth lines along the outline and "
      "the element edges; a third of the CPU on a software rasteriser); auto: lines on "
      "llvmpipe / OSMesa, msaa on a GPU"));
  t.push_back(integer(
      "render.msaa", [](O& o) -> int& { return o.render.msaa; }, 0, 16, "the multisample count", "",
      kFrozen,
      "samples when multisampling (the largest count the GL supports up to this, with a warning)"));
  t.push_back(boolean(
      "render.preview", [](O& o) -> bool& { return o.render.preview; }, kFrozen,
      "keep preview.png current (never blocks the solver)"));
  // numerics
  t.push_back(boolean(
      "numerics.smoothing", [](O& o) -> bool& { return o.numerics.smoothing; }, kFrozen,
      "the paper's first-order membrane smoothing (off: unstable)"));
  t.push_back(boolean(
      "numerics.volume_correction", [](O& o) -> bool& { return o.numerics.volume_correction; },
      kLive, "rescale to the initial volume after each step (paper eq. 23)"));
  t.push_back(boolean(
      "numerics.symmetry", [](O& o) -> bool& { return o.numerics.symmetry; }, kFrozen,
      "evaluate velocities on the nodes the flow's symmetry leaves distinct"));
  t.push_back(integer(
      "numerics.threads", [](O& o) -> int& { return o.numerics.threads; }, 0, 1024,
      "the OpenMP thread count (0: all)", "", kLive, "OpenMP threads (0: all cores)"));
  t.push_back(number(
      "numerics.quadrature_scale", [](O& o) -> double& { return o.numerics.quadrature_scale; },
      closed(1, 4), "the factor on every quadrature order", "", kFrozen,
      "every boundary-integral quadrature order times this (accuracy checks)"));
  // run
  t.push_back(choice(
      "run.state", [](const O& o) { return static_cast<int>(o.run.state); },
      [](O& o, int i) { o.run.state = static_cast<RunState>(i); }, {"running", "paused", "stopped"},
      kLive, "paused holds the run; stopped ends it with a checkpoint"));
  t.push_back(boolean(
      "run.checkpoint_now", [](O& o) -> bool& { return o.run.checkpoint_now; }, kLive,
      "write a checkpoint when this becomes true"));

  const ControlOptions defaults;
  for (Field& f : t)
    if (f.info.default_value.empty())
      if (const auto v = f.write(defaults)) f.info.default_value = v->dump();
  return t;
}

std::vector<Group> build_groups() {
  std::vector<Group> g = {
      {"capsule", "the membrane", nullptr, nullptr},
      {"capsule.bending", "bending stiffness (method.md sec. 10)", nullptr, nullptr},
      {"mesh", "the spectral element mesh", nullptr, nullptr},
      {"start", "the initial shape", nullptr, nullptr},
      {"flow", "the imposed flow", nullptr, nullptr},
      {"time", "time stepping", nullptr, nullptr},
      {"steady", "steady-state detection", nullptr, nullptr},
      {"output", "what the run writes", nullptr, nullptr},
      {"output.mp4", "the movie: false, true (defaults) or an object",
       [](ControlOptions& o, bool on) { o.output.mp4.enabled = on; },
       [](const ControlOptions& o) { return o.output.mp4.enabled; }},
      {"render", "how frames look", nullptr, nullptr},
      {"render.overlay", "text and colour bar drawn over frames", nullptr, nullptr},
      {"numerics", "solver options", nullptr, nullptr},
      {"run", "steering", nullptr, nullptr},
  };
  return g;
}

}  // namespace detail

// Which commands take an edit of each live key: capflow run every one; capflow steady those its
// solver uses.
std::vector<Field> with_live_commands(std::vector<Field> t) {
  static const char* const kSteadyLive[] = {"ca", "steady.solve_tolerance", "time.tolerance",
                                            "run.state"};
  for (Field& f : t) {
    if (f.info.mutability != detail::kLive) continue;
    f.info.live_in = bit(Command::Run);
    for (const char* k : kSteadyLive)
      if (f.info.path == k) f.info.live_in |= bit(Command::Steady);
  }
  return t;
}

}  // namespace capflow::control::schema
