#include "serve/api.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "control/live_patch.h"
#include "control/record.h"
#include "files/input_file.h"
#include "render/data_dir.h"
#include "serve/appended_lines.h"
#include "serve/json_out.h"
#include "serve/token.h"

namespace capflow::serve {

namespace {

Response json(int status, std::string body) {
  Response r;
  r.status = status;
  r.body = std::move(body);
  r.headers.push_back({"Cache-Control", "no-store"});
  return r;
}

Response message(int status, const std::string& text) {
  return json(status, "{\"error\":" + json_string(text) + "}");
}

std::optional<double> number_param(const Request& r, const char* name) {
  const std::string s = r.param(name);
  if (s.empty() || s.size() > 64 || s.find_first_not_of("0123456789+-.eE") != std::string::npos)
    return std::nullopt;  // decimal only: no hex, inf, nan or spaces
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || std::isnan(v)) return std::nullopt;
  return v;
}

std::string issues_json(const std::vector<control::ControlIssue>& issues) {
  std::string o = "[";
  for (size_t i = 0; i < issues.size(); ++i)
    o += std::string(i ? "," : "") + "{\"path\":" + json_string(issues[i].path) +
         ",\"message\":" + json_string(issues[i].message) + "}";
  return o + "]";
}

std::string strings_json(const std::vector<std::string>& v) {
  std::string o = "[";
  for (size_t i = 0; i < v.size(); ++i) o += (i ? "," : "") + json_string(v[i]);
  return o + "]";
}

const std::map<std::string, std::string>& content_types() {
  static const std::map<std::string, std::string> t = {
      {"index.html", "text/html; charset=utf-8"},
      {"console.js", "text/javascript; charset=utf-8"},
      {"console.css", "text/css; charset=utf-8"},
      {"chart.min.js", "text/javascript; charset=utf-8"}};
  return t;
}

}  // namespace

std::map<std::string, std::string> load_console_assets() {
  std::map<std::string, std::string> a;
  for (const char* name : {"index.html", "console.js", "console.css"})
    a[name] = render::read_data_file(std::string("assets/console/") + name);
  a["chart.min.js"] = files::read_input_file("/usr/share/javascript/chart.js/chart.min.js",
                                             "Chart.js (Debian package libjs-chart.js)", 4 << 20);
  return a;
}

Api::Api(Source& source, FrameDrawer* frames, std::string token,
         std::map<std::string, std::string> assets)
    : source_(source),
      frames_(frames),
      token_(std::move(token)),
      assets_(std::move(assets)),
      control_(source.control_path(), source.command()),
      timeseries_(std::make_unique<AppendedLines>(source.run_dir() + "/" + source.series_file(),
                                                  "time series")),
      events_(std::make_unique<AppendedLines>(source.run_dir() + "/events.jsonl", "event log")) {}

Api::~Api() = default;

Response Api::handle(const Request& r) {
  if (r.body.size() > kMaxBody) return message(413, "the request body is too large");
  const GivenToken given = token_of(r);
  const bool token_ok = same_token(given.value, token_);
  if (r.method == "GET" && (r.path == "/" || r.path == "/index.html")) return page(r, token_ok);
  if (!token_ok)
    return message(401, "this console needs its token: open the URL capflow printed "
                        "(http://HOST:PORT/?token=...)");
  if (r.method == "GET") {
    const std::string name = r.path.size() > 1 ? r.path.substr(1) : "";
    if (name != "index.html" && assets_.count(name) && content_types().count(name)) {
      Response a;
      a.content_type = content_types().at(name);
      a.body = assets_.at(name);
      return a;
    }
    if (r.path == "/api/state") return state();
    if (r.path == "/api/timeseries") return timeseries(r);
    if (r.path == "/api/events") return events(r);
    if (r.path == "/api/surfaces") return surfaces();
    if (r.path == "/api/frame") return frame(r);
    if (r.path == "/api/control") return control_get();
  } else if (r.method == "POST" && r.path == "/api/control") {
    if (!given.in_header)
      return message(403, "an edit must carry the token in a header (Authorization: Bearer "
                          "TOKEN or X-Capflow-Token), not only in a cookie");
    return control_post(r);
  }
  return message(404, "not found");
}

Response Api::page(const Request& r, bool token_ok) {
  if (!token_ok) {
    Response p;
    p.status = 401;
    p.content_type = "text/plain; charset=utf-8";
    p.body = "This capflow console needs its token: open the URL capflow printed "
             "(http://HOST:PORT/?token=...).\n";
    return p;
  }
  Response p;
  p.content_type = "text/html; charset=utf-8";
  p.body = assets_.count("index.html") ? assets_.at("index.html") : "";
  p.headers.push_back({"Cache-Control", "no-store"});
  if (r.has_param("token"))
    p.headers.push_back({"Set-Cookie", "capflow_token=" + token_ +
                                           "; Path=/; HttpOnly; SameSite=Strict"});
  return p;
}

Response Api::state() {
  const LiveState s = source_.state();
  const ControlRevision::Current c = control_.current();
  std::string o = "{";
  for (const auto& [k, v] : {std::pair<const char*, double>{"t", s.t}, {"ca", s.ca}, {"D", s.D},
                             {"L", s.L}, {"S", s.S}, {"W", s.W}, {"dt", s.dt}})
    o += json_string(k) + ":" + json_number(v) + ",";
  o += "\"state\":" + json_string(s.state) + ",\"steps\":" + std::to_string(s.steps) +
       ",\"revision\":" + std::to_string(c.revision) + ",\"schedule\":{\"now\":" +
       json_string(s.schedule_now) + ",\"next\":" + json_string(s.schedule_next) +
       "},\"steps_per_second\":" + json_number(s.steps_per_second) +
       ",\"eta_seconds\":" + json_number(s.eta_seconds) +
       ",\"live\":" + (s.live ? "true" : "false") +
       ",\"command\":" + json_string(control::command_name(source_.command())) + "}";
  return json(200, o);
}

Response Api::timeseries(const Request& r) {
  double since = -INFINITY;
  if (r.has_param("since")) {
    const std::optional<double> v = number_param(r, "since");
    if (!v) return message(400, "since must be a number (the time of the last row you have)");
    since = *v;
  }
  std::lock_guard<std::mutex> lock(files_mutex_);
  timeseries_->refresh();
  const std::vector<std::string>& lines = timeseries_->lines();
  std::string columns = "[]", rows = "[";
  if (!lines.empty() && timeseries_->first_index() == 0) {
    std::vector<std::string> names;
    size_t at = 0;
    const std::string& h = lines[0];
    while (at <= h.size()) {
      size_t comma = h.find(',', at);
      if (comma == std::string::npos) comma = h.size();
      names.push_back(h.substr(at, comma - at));
      at = comma + 1;
    }
    columns = strings_json(names);
  }
  bool first = true;
  for (size_t i = timeseries_->first_index() == 0 ? 1 : 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    char* end = nullptr;
    const double t = std::strtod(l.c_str(), &end);
    if (end == l.c_str() || !(t > since)) continue;
    std::vector<double> v;
    const char* p = l.c_str();
    for (;;) {
      char* e = nullptr;
      v.push_back(std::strtod(p, &e));
      if (e == p) v.back() = NAN;
      const char* comma = std::strchr(e, ',');
      if (!comma) break;
      p = comma + 1;
    }
    rows += (first ? "" : ",") + json_numbers(v);
    first = false;
  }
  return json(200, "{\"columns\":" + columns + ",\"rows\":" + rows + "]}");
}

Response Api::events(const Request& r) {
  size_t since = 0;
  if (r.has_param("since")) {
    const std::optional<double> v = number_param(r, "since");
    if (!v || *v < 0 || *v > 1e12 || *v != std::floor(*v))
      return message(400, "since must be a whole number >= 0 (the next event's index)");
    since = static_cast<size_t>(*v);
  }
  std::lock_guard<std::mutex> lock(files_mutex_);
  events_->refresh();
  const std::vector<std::string>& lines = events_->lines();
  const size_t first = events_->first_index(), next = first + lines.size();
  std::string o = "{\"next\":" + std::to_string(next) + ",\"events\":[";
  bool any = false;
  for (size_t i = std::max(since, first); i < next; ++i) {
    o += (any ? "," : "") + control::json_value_text(lines[i - first]);
    any = true;
  }
  return json(200, o + "]}");
}

Response Api::surfaces() {
  return json(200, "{\"times\":" + json_numbers(source_.saved_times()) + "}");
}

Response Api::frame(const Request& r) {
  std::string error;
  const FrameQuery q = parse_frame_query(r, &error);
  if (!error.empty()) return message(400, error);
  if (!frames_) return message(503, "this console draws no images");
  source_.watched();
  std::shared_ptr<const render::Snapshot> s = q.time ? source_.saved(*q.time) : source_.newest();
  if (!s)
    return message(404, q.time ? "the run saved no surfaces (output.vtk_every)"
                               : "no state to draw yet");
  const std::optional<EncodedFrame> f = frames_->draw(std::move(s), q, &error);
  if (!f) return message(503, error);
  Response p;
  p.content_type = f->content_type;
  p.body = f->bytes;
  p.headers.push_back({"Cache-Control", "no-store"});
  return p;
}

Response Api::control_get() {
  const std::string path = source_.control_path();
  if (path.empty())
    return json(200, "{\"revision\":0,\"command\":" +
                         json_string(control::command_name(source_.command())) +
                         ",\"control\":null,\"fields\":[],\"error\":" +
                         json_string("this run watches no control file: it takes no edits") + "}");
  const ControlRevision::Current c = control_.current();
  return json(200, "{\"revision\":" + std::to_string(c.revision) + ",\"command\":" +
                       json_string(control::command_name(source_.command())) +
                       ",\"control\":" + control::json_value_text(c.text) + ",\"fields\":" +
                       control::live_fields_json(source_.command()) +
                       ",\"error\":" + json_string(c.error) + "}");
}

Response Api::control_post(const Request& r) {
  if (source_.control_path().empty())
    return message(409, "this run watches no control file: it takes no edits");
  const LiveState s = source_.state();
  const std::string refuse =
      s.live ? "" : "the run has ended (" + s.state + "): an edit would change nothing";
  long revision = 0;
  const control::LivePatch p = control_.submit(r.body, refuse, &revision);
  using S = control::LivePatch::Status;
  const std::string tail = ",\"revision\":" + std::to_string(revision) + ",\"keys\":" +
                           strings_json(p.keys) + ",\"issues\":" + issues_json(p.issues) + "}";
  const std::string head = "{\"status\":" + json_string(control::status_name(p.status));
  switch (p.status) {
    case S::Ok:
      return json(200, head + tail);
    case S::Stale:
      return json(409, head + tail);
    case S::Refused:
      return json(422, head + tail);
    case S::BadRequest:
      break;
  }
  return json(400, head + tail);
}

}  // namespace capflow::serve
