// capflow/serve/api: the live console's HTTP surface as a function Request -> Response.
//
//   GET  /                     the page (assets/console/index.html); with a valid ?token= it
//                              sets the cookie capflow_token (HttpOnly, SameSite=Strict)
//   GET  /console.js, /console.css, /chart.min.js   the page's script, style and plots
//                              (Chart.js from Debian's libjs-chart.js)
//   GET  /api/state            t, ca, D, L, S, W, dt, state, steps, revision, schedule
//                              {now, next}, steps_per_second, eta_seconds, live
//   GET  /api/timeseries?since=T   {"columns": [...], "rows": [[...], ...]}: rows with t > T
//                              (timeseries.csv; steady.csv for capflow steady)
//   GET  /api/events?since=N   {"next": M, "events": [...]}: events.jsonl lines N.. (0-based)
//   GET  /api/surfaces         {"times": [...]}: the saved surfaces (the timeline)
//   GET  /api/frame            an image (serve/frame_query.h for its parameters)
//   GET  /api/control          {"revision", "command", "control": the file, "fields": the live
//                              keys (control/live_patch.h: live_fields_json)}
//   POST /api/control          {"revision": R, "patch": {...}} -> 200 {"revision", "applied"},
//                              409 stale revision, 422 refused {"issues": [{path, message}]},
//                              400 malformed
// Every request needs the token (serve/token.h), else 401; a POST needs it in a header, else
// 403. Anything else is 404: nothing is served from a path the request names, so traversal,
// NUL bytes or encodings reach nothing. Request bodies over kMaxBody are refused (413).
#pragma once

#include <map>
#include <memory>
#include <string>

#include "serve/control_revision.h"
#include "serve/frame_drawer.h"
#include "serve/http.h"
#include "serve/source.h"

namespace capflow::serve {

class AppendedLines;

class Api {
 public:
  static constexpr size_t kMaxBody = 1 << 20;

  // `assets`: the files the page is made of, by name ("index.html", "console.js",
  // "console.css", "chart.min.js"), read once at start.
  Api(Source& source, FrameDrawer* frames, std::string token,
      std::map<std::string, std::string> assets);
  ~Api();

  Response handle(const Request& r);

 private:
  Response page(const Request& r, bool token_ok);
  Response state();
  Response timeseries(const Request& r);
  Response events(const Request& r);
  Response surfaces();
  Response frame(const Request& r);
  Response control_get();
  Response control_post(const Request& r);

  Source& source_;
  FrameDrawer* frames_;
  std::string token_;
  std::map<std::string, std::string> assets_;
  ControlRevision control_;
  std::mutex files_mutex_;
  std::unique_ptr<AppendedLines> timeseries_, events_;
};

// The page's files from the assets directory (render/data_dir.h) and Chart.js from its Debian
// path; std::runtime_error naming a file that is missing.
std::map<std::string, std::string> load_console_assets();

}  // namespace capflow::serve
