// libFuzzer target for the live console's HTTP surface (serve/api.h): the input is one raw
// request - "METHOD TARGET HTTP/1.1", header lines, a blank line, the body - split here the way
// an HTTP library splits it (the target's query percent-decoded), then handled by the API over a
// run directory with a control file, without a socket. Every input must end in a known status;
// a request that is not answered 200 leaves the control file as it was, and an accepted edit
// leaves one that validates. The frame query and the merge patch get the raw pieces too.
// Built by scripts/fuzz (target http); replayed over tests/fuzz/corpus_http by CTest.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "control/control_file.h"
#include "control/live_patch.h"
#include "serve/api.h"

using namespace capflow;

namespace {

const char* kControl =
    "{\"capsule\": {\"law\": \"skalak\"}, \"mesh\": {\"elements\": 6, \"nb\": 6}, "
    "\"flow\": {\"type\": \"planar-extension\"}, \"time\": {\"t_end\": 4}, \"ca\": 0.3}\n";
const char* kToken = "0123456789abcdef0123456789abcdef";

class Dir : public serve::Source {
 public:
  explicit Dir(std::string d) : dir_(std::move(d)) {}
  serve::LiveState state() override {
    serve::LiveState s;
    s.live = true;
    return s;
  }
  std::shared_ptr<const render::Snapshot> newest() override { return nullptr; }
  std::shared_ptr<const render::Snapshot> saved(double) override { return nullptr; }
  std::vector<double> saved_times() override { return {0, 1}; }
  std::string run_dir() const override { return dir_; }
  std::string control_path() const override { return dir_ + "/c.json"; }
  control::Command command() const override { return control::Command::Run; }
  render::RenderOptions render_options() const override { return {}; }

 private:
  std::string dir_;
};

std::string decode(const std::string& s) {
  std::string o;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      o += static_cast<char>(std::strtol(s.substr(i + 1, 2).c_str(), nullptr, 16));
      i += 2;
    } else {
      o += s[i] == '+' ? ' ' : s[i];
    }
  }
  return o;
}

serve::Request split(const std::string& raw) {
  serve::Request r;
  size_t eol = raw.find("\r\n");
  const std::string line = raw.substr(0, eol);
  const size_t sp1 = line.find(' '), sp2 = line.rfind(' ');
  r.method = line.substr(0, sp1);
  std::string target = sp1 == std::string::npos ? "" : line.substr(sp1 + 1, sp2 - sp1 - 1);
  const size_t q = target.find('?');
  r.path = decode(target.substr(0, q));
  if (q != std::string::npos) {
    std::string query = target.substr(q + 1);
    size_t at = 0;
    while (at <= query.size()) {
      size_t amp = query.find('&', at);
      if (amp == std::string::npos) amp = query.size();
      const std::string kv = query.substr(at, amp - at);
      const size_t eq = kv.find('=');
      r.params.emplace(decode(kv.substr(0, eq)),
                       eq == std::string::npos ? "" : decode(kv.substr(eq + 1)));
      at = amp + 1;
    }
  }
  size_t at = eol == std::string::npos ? raw.size() : eol + 2;
  while (at < raw.size()) {
    const size_t e = raw.find("\r\n", at);
    const std::string h = raw.substr(at, e == std::string::npos ? std::string::npos : e - at);
    at = e == std::string::npos ? raw.size() : e + 2;
    if (h.empty()) break;
    const size_t colon = h.find(':');
    std::string name = h.substr(0, colon);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string value = colon == std::string::npos ? "" : h.substr(colon + 1);
    value.erase(0, value.find_first_not_of(' '));
    r.headers.emplace(name, value);
  }
  r.body = raw.substr(std::min(at, raw.size()));
  return r;
}

std::string slurp(const std::string& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 8192) return 0;
  static const std::string dir = [] {
    const std::string d = std::filesystem::temp_directory_path() /
                          ("capflow_fuzz_http_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  std::ofstream(dir + "/c.json") << kControl;
  std::ofstream(dir + "/timeseries.csv") << "t,ca,D\n0,0.3,0\n1,0.3,0.2\n";
  std::ofstream(dir + "/events.jsonl") << "{\"event\":\"start\"}\n";
  const std::string raw(reinterpret_cast<const char*>(data), size);
  const serve::Request r = split(raw);

  Dir source(dir);
  serve::Api api(source, nullptr, kToken, {{"index.html", "<html>"}, {"console.js", "js"}});
  const std::string before = slurp(dir + "/c.json");
  const serve::Response out = api.handle(r);
  static const std::set<int> known = {200, 400, 401, 403, 404, 409, 413, 422, 503};
  if (!known.count(out.status)) {
    std::fprintf(stderr, "unexpected status %d\n", out.status);
    std::abort();
  }
  const std::string after = slurp(dir + "/c.json");
  if (out.status != 200 && after != before) {
    std::fprintf(stderr, "a refused request (%d) changed the control file\n", out.status);
    std::abort();
  }
  if (after != before) control::parse_control(after);  // an accepted edit validates (or throws)

  // The pieces on their own.
  std::string error;
  serve::parse_frame_query(r, &error);
  control::apply_live_patch(kControl, 0, r.body, control::Command::Run);
  control::apply_live_patch(kControl, 0, r.body, control::Command::Steady);
  return 0;
}
