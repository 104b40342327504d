// A run the API can be asked about without a process behind it: a temporary run directory with
// its control file, and a Source whose state the test sets.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "serve/api.h"
#include "serve/source.h"

namespace capflow::serve::testing {

inline const char* kControl = R"({
  "capsule": {"law": "skalak", "C": 1},
  "mesh": {"elements": 6, "nb": 6},
  "flow": {"type": "planar-extension"},
  "time": {"t_end": 4},
  "ca": 0.3,
  "output": {"dir": "run", "csv_every": 0.05}
}
)";

class FakeSource : public Source {
 public:
  explicit FakeSource(std::string dir) : dir_(std::move(dir)) {}
  LiveState state() override { return state_; }
  std::shared_ptr<const render::Snapshot> newest() override { return newest_; }
  void watched() override { ++watched_; }
  std::shared_ptr<const render::Snapshot> saved(double t) override {
    last_saved_ = t;
    return newest_;
  }
  std::vector<double> saved_times() override { return {0, 0.5, 1}; }
  std::string run_dir() const override { return dir_; }
  std::string control_path() const override { return dir_ + "/c.json"; }
  control::Command command() const override { return command_; }
  render::RenderOptions render_options() const override { return {}; }

  LiveState state_;
  std::shared_ptr<const render::Snapshot> newest_;
  control::Command command_ = control::Command::Run;
  int watched_ = 0;
  double last_saved_ = -1;

 private:
  std::string dir_;
};

// Draws nothing: returns the query's size and camera as the "image", so tests see what reached it.
class EchoDrawer : public FrameDrawer {
 public:
  std::optional<EncodedFrame> draw(std::shared_ptr<const render::Snapshot> s, const FrameQuery& q,
                                   std::string*) override {
    EncodedFrame f;
    f.content_type = "image/test";
    f.bytes = std::to_string(q.width) + "x" + std::to_string(q.height) + " t=" +
              std::to_string(s->time);
    return f;
  }
};

class ApiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("capflow_serve_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    write("c.json", kControl);
    source_ = std::make_unique<FakeSource>(dir_.string());
    api_ = std::make_unique<Api>(*source_, &drawer_, token_,
                                 std::map<std::string, std::string>{{"index.html", "<html>"},
                                                                    {"console.js", "js"},
                                                                    {"console.css", "css"},
                                                                    {"chart.min.js", "chart"}});
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
  }
  std::string read(const std::string& name) {
    std::ifstream in(dir_ / name);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  Request get(const std::string& path, bool token = true) {
    Request r;
    r.method = "GET";
    r.path = path;
    if (token) r.headers["authorization"] = "Bearer " + token_;
    return r;
  }
  Response post(const std::string& body) {
    Request r = get("/api/control");
    r.method = "POST";
    r.body = body;
    return api_->handle(r);
  }

  std::filesystem::path dir_;
  std::string token_ = "0123456789abcdef0123456789abcdef";
  EchoDrawer drawer_;
  std::unique_ptr<FakeSource> source_;
  std::unique_ptr<Api> api_;
};

}  // namespace capflow::serve::testing
