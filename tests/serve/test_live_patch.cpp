// control/live_patch: the console's edit as a JSON merge patch (RFC 7386) of the control file,
// checked against the schema's live keys and validated as a whole.
#include <gtest/gtest.h>

#include <set>

#include "control/control_file.h"
#include "control/live_patch.h"
#include "serve_fixture.h"

namespace capflow::control {
namespace {

using S = LivePatch::Status;

LivePatch patch(const std::string& p, long rev = 7, Command c = Command::Run) {
  return apply_live_patch(serve::testing::kControl, 7,
                          "{\"revision\": " + std::to_string(rev) + ", \"patch\": " + p + "}", c);
}

TEST(LivePatch, MergesAndKeepsTheRest) {
  const LivePatch p = patch(R"({"ca": [{"ca": 0.3, "hold": 1}, {"ramp": {"to": 0.6, "rate": 0.5}}],
                                "output": {"csv_every": 0.1}})");
  ASSERT_EQ(p.status, S::Ok) << (p.issues.empty() ? "" : p.issues[0].str());
  const ControlOptions o = parse_control(p.text).options;
  EXPECT_EQ(o.ca.segments.size(), 2u);
  EXPECT_DOUBLE_EQ(o.output.csv_every, 0.1);
  EXPECT_EQ(o.mesh.nb, 6) << "untouched keys stay";
  EXPECT_EQ(p.keys, (std::vector<std::string>{"ca", "output.csv_every"}));
}

TEST(LivePatch, NullRemovesAKeyAsRfc7386Says) {
  const LivePatch p = patch(R"({"output": {"csv_every": null}})");
  ASSERT_EQ(p.status, S::Ok);
  EXPECT_EQ(p.text.find("csv_every"), std::string::npos);
  EXPECT_DOUBLE_EQ(parse_control(p.text).options.output.csv_every, ControlOptions{}.output.csv_every);
}

TEST(LivePatch, StaleBeforeAnythingElse) {
  EXPECT_EQ(patch(R"({"mesh": {"nb": 9}})", 6).status, S::Stale);
  EXPECT_EQ(patch(R"({"ca": 0.4})", 8).status, S::Stale);
}

TEST(LivePatch, EveryRefusalNamesItsPath) {
  const LivePatch p = patch(R"({"mesh": {"nb": 9}, "time": {"tolerance": 1}, "bogus": {}})");
  ASSERT_EQ(p.status, S::Refused);
  ASSERT_EQ(p.issues.size(), 2u) << "the schema's checks first; the value check needs a clean patch";
  std::set<std::string> paths{p.issues[0].path, p.issues[1].path};
  EXPECT_EQ(paths, (std::set<std::string>{"mesh.nb", "bogus"}));
  const LivePatch v = patch(R"({"time": {"tolerance": 1}})");
  ASSERT_EQ(v.status, S::Refused);
  EXPECT_EQ(v.issues.at(0).path, "time.tolerance");
  EXPECT_NE(v.issues[0].message.find("[1e-10, 0.01]"), std::string::npos) << v.issues[0].message;
}

TEST(LivePatch, TheLiveKeysOfEachCommandComeFromTheSchema) {
  const std::string run = live_fields_json(Command::Run), steady = live_fields_json(Command::Steady);
  for (const FieldInfo& f : control_fields()) {
    const std::string quoted = "\"path\":\"" + f.path + "\"";
    EXPECT_EQ(run.find(quoted) != std::string::npos, f.live_for(Command::Run)) << f.path;
    EXPECT_EQ(steady.find(quoted) != std::string::npos, f.live_for(Command::Steady)) << f.path;
  }
}

}  // namespace
}  // namespace capflow::control
