// The live console's API without a socket: the token, what is served and what is not, the size
// limit, edits through the control file (merge patch, schema, revision), the frame parameters.
#include <gtest/gtest.h>

#include "serve_fixture.h"

namespace capflow::serve::testing {
namespace {

TEST_F(ApiTest, EveryRequestNeedsTheToken) {
  EXPECT_EQ(api_->handle(get("/api/state", false)).status, 401);
  Request wrong = get("/api/state", false);
  wrong.headers["authorization"] = "Bearer " + token_.substr(0, 31) + "0";
  EXPECT_EQ(api_->handle(wrong).status, 401);
  Request prefix = get("/api/state", false);
  prefix.params["token"] = token_.substr(0, 16);
  EXPECT_EQ(api_->handle(prefix).status, 401);
  EXPECT_EQ(api_->handle(get("/", false)).status, 401);
  EXPECT_EQ(api_->handle(get("/console.js", false)).status, 401);
  // Each way of carrying it works.
  EXPECT_EQ(api_->handle(get("/api/state")).status, 200);
  Request query = get("/api/state", false);
  query.params["token"] = token_;
  EXPECT_EQ(api_->handle(query).status, 200);
  Request cookie = get("/api/state", false);
  cookie.headers["cookie"] = "other=1; capflow_token=" + token_;
  EXPECT_EQ(api_->handle(cookie).status, 200);
  Request header = get("/api/state", false);
  header.headers["x-capflow-token"] = token_;
  EXPECT_EQ(api_->handle(header).status, 200);
}

TEST_F(ApiTest, ThePageSetsTheCookieFromTheQuery) {
  Request r = get("/", false);
  r.params["token"] = token_;
  const Response p = api_->handle(r);
  ASSERT_EQ(p.status, 200);
  EXPECT_EQ(p.body, "<html>");
  bool cookie = false;
  for (const auto& [k, v] : p.headers)
    if (k == "Set-Cookie") {
      cookie = true;
      EXPECT_NE(v.find("capflow_token=" + token_), std::string::npos);
      EXPECT_NE(v.find("HttpOnly"), std::string::npos);
      EXPECT_NE(v.find("SameSite=Strict"), std::string::npos);
    }
  EXPECT_TRUE(cookie);
}

TEST_F(ApiTest, NothingOutsideTheNamedFilesIsServed) {
  write("secret.txt", "secret");
  for (const std::string& path : std::vector<std::string>
       {std::string("/console.js\0x", 13), std::string("/\0", 2), std::string("/api/state\0", 11),
        std::string("/../secret.txt"), "/secret.txt", "/../../etc/passwd", "/%2e%2e/secret.txt",
        "//etc/passwd", "/console.js/../secret.txt", "/api/state/../../x",
        "/c.json", "/timeseries.csv", "/api", "/api/", "/assets/console/console.js", "",
        "/index.html/../c.json", "/CONSOLE.JS", "/console.js%00", "/./console.js"}) {
    const Response r = api_->handle(get(path));
    EXPECT_EQ(r.status, 404) << path;
    EXPECT_EQ(r.body.find("secret"), std::string::npos) << path;
  }
  EXPECT_EQ(api_->handle(get("/console.js")).body, "js");
  EXPECT_EQ(api_->handle(get("/chart.min.js")).body, "chart");
}

TEST_F(ApiTest, OtherMethodsAreNotFound) {
  for (const char* m : {"PUT", "DELETE", "PATCH", "OPTIONS", "HEAD", ""}) {
    Request r = get("/api/control");
    r.method = m;
    EXPECT_EQ(api_->handle(r).status, 404) << m;
  }
}

TEST_F(ApiTest, ABodyOverTheLimitIsRefusedAndChangesNothing) {
  const std::string before = read("c.json");
  const Response r = post(std::string(Api::kMaxBody + 1, ' '));
  EXPECT_EQ(r.status, 413);
  EXPECT_EQ(read("c.json"), before);
}

TEST_F(ApiTest, APostNeedsTheTokenInAHeader) {
  Request r = get("/api/control", false);
  r.method = "POST";
  r.headers["cookie"] = "capflow_token=" + token_;
  r.body = R"({"revision": 0, "patch": {"ca": 0.4}})";
  const std::string before = read("c.json");
  EXPECT_EQ(api_->handle(r).status, 403);
  r.params["token"] = token_;
  EXPECT_EQ(api_->handle(r).status, 403);
  EXPECT_EQ(read("c.json"), before);
}

TEST_F(ApiTest, AnEditIsWrittenToTheControlFileAndTheRevisionGrows) {
  source_->state_.live = true;
  const Response r = post(R"({"revision": 0, "patch": {"ca": 0.45, "run": {"state": "paused"}}})");
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_NE(r.body.find("\"revision\":1"), std::string::npos) << r.body;
  const std::string text = read("c.json");
  EXPECT_NE(text.find("0.45"), std::string::npos) << text;
  EXPECT_NE(text.find("paused"), std::string::npos) << text;
  EXPECT_NE(text.find("skalak"), std::string::npos) << "the rest of the file stays";
  // The state reports the new revision; a hand edit makes the next.
  EXPECT_NE(api_->handle(get("/api/state")).body.find("\"revision\":1"), std::string::npos);
  write("c.json", text + " ");
  EXPECT_NE(api_->handle(get("/api/state")).body.find("\"revision\":2"), std::string::npos);
}

TEST_F(ApiTest, AStaleRevisionIsRefusedWith409) {
  source_->state_.live = true;
  ASSERT_EQ(post(R"({"revision": 0, "patch": {"ca": 0.4}})").status, 200);
  const std::string after_first = read("c.json");
  const Response r = post(R"({"revision": 0, "patch": {"ca": 0.5}})");
  EXPECT_EQ(r.status, 409) << r.body;
  EXPECT_NE(r.body.find("\"revision\":1"), std::string::npos) << r.body;
  EXPECT_EQ(read("c.json"), after_first);
}

TEST_F(ApiTest, RefusedEditsAnswer422WithTheSchemaMessageAndChangeNothing) {
  source_->state_.live = true;
  const std::string before = read("c.json");
  struct Case {
    const char* patch;
    const char* path;
    const char* words;
  };
  for (const Case& c : {Case{R"({"time": {"tolerance": 5}})", "time.tolerance", "0.01"},
                        Case{R"({"mesh": {"nb": 8}})", "mesh.nb", "restart the run"},
                        Case{R"({"capsule": {"law": "neo-hookean"}})", "capsule.law", "restart"},
                        Case{R"({"colour": 1})", "colour", "not a key"},
                        Case{R"({"time": 3})", "time", "one by one"},
                        Case{R"({"ca": -1})", "ca", "(0, 100]"},
                        Case{R"({"run": {"state": "flying"}})", "run.state", "paused"}}) {
    const Response r =
        post(std::string(R"({"revision": 0, "patch": )") + c.patch + "}");
    EXPECT_EQ(r.status, 422) << c.patch << " " << r.body;
    EXPECT_NE(r.body.find(std::string("\"path\":\"") + c.path), std::string::npos)
        << c.patch << " " << r.body;
    EXPECT_NE(r.body.find(c.words), std::string::npos) << c.patch << " " << r.body;
    EXPECT_EQ(read("c.json"), before) << c.patch;
  }
}

TEST_F(ApiTest, SteadyRefusesTheKeysItDoesNotUse) {
  source_->state_.live = true;
  source_->command_ = control::Command::Steady;
  api_ = std::make_unique<Api>(*source_, &drawer_, token_, std::map<std::string, std::string>{});  // as steady's
  const Response r = post(R"({"revision": 0, "patch": {"output": {"csv_every": 0.1}}})");
  EXPECT_EQ(r.status, 422) << r.body;
  EXPECT_NE(r.body.find("capflow steady does not use it"), std::string::npos) << r.body;
  EXPECT_EQ(post(R"({"revision": 0, "patch": {"ca": 0.4}})").status, 200);
}

TEST_F(ApiTest, MalformedEditsAnswer400) {
  source_->state_.live = true;
  for (const char* body : {"", "nope", "[]", R"({"patch": {"ca": 1}})",
                           R"({"revision": "0", "patch": {}})", R"({"revision": 0})",
                           R"({"revision": 0, "patch": 3})", R"({"revision": 0.5, "patch": {}})",
                           R"({"revision": 0, "patch": {}, "extra": 1})"})
    EXPECT_EQ(post(body).status, 400) << body;
}

TEST_F(ApiTest, AnEndedRunTakesNoEdits) {
  source_->state_.live = false;
  source_->state_.state = "finished";
  const Response r = post(R"({"revision": 0, "patch": {"ca": 0.4}})");
  EXPECT_EQ(r.status, 422);
  EXPECT_NE(r.body.find("ended"), std::string::npos);
}

TEST_F(ApiTest, TimeseriesAndEventsAreReadFromTheRunDirectory) {
  write("timeseries.csv", "t,ca,D\n0,0.3,0\n0.5,0.3,0.1\n1,0.3,0.2\n1.5,0.3,");
  Request r = get("/api/timeseries");
  r.params["since"] = "0.5";
  const Response s = api_->handle(r);
  ASSERT_EQ(s.status, 200);
  EXPECT_EQ(s.body, R"({"columns":["t","ca","D"],"rows":[[1,0.3,0.2]]})");
  r.params["since"] = "nan";
  EXPECT_EQ(api_->handle(r).status, 400);
  write("events.jsonl", "{\"event\":\"start\"}\n{\"event\":\"pause\"}\nnot json\n");
  Request e = get("/api/events");
  e.params["since"] = "1";
  EXPECT_EQ(api_->handle(e).body, R"({"next":3,"events":[{"event":"pause"},"not json"]})");
  e.params["since"] = "-1";
  EXPECT_EQ(api_->handle(e).status, 400);
}

TEST_F(ApiTest, FramesPassTheirQueryAndMarkTheSourceWatched) {
  Request r = get("/api/frame");
  EXPECT_EQ(api_->handle(r).status, 404) << "no state yet";
  auto s = std::make_shared<render::Snapshot>();
  s->time = 2;
  source_->newest_ = s;
  r.params["width"] = "640";
  r.params["height"] = "360";
  Response f = api_->handle(r);
  EXPECT_EQ(f.status, 200);
  EXPECT_EQ(f.body, "640x360 t=2.000000");
  EXPECT_GE(source_->watched_, 1);
  r.params["time"] = "0.5";
  api_->handle(r);
  EXPECT_EQ(source_->last_saved_, 0.5);
  r.params["width"] = "641";
  EXPECT_EQ(api_->handle(r).status, 400);
}

}  // namespace
}  // namespace capflow::serve::testing
