// capflow steady from rest where the NB=8 start does not resolve the tips (app/steady_run.cpp,
// SteadyRun::climb). The neo-Hookean capsule at Ca = 0.38 in planar extension, NE=6 NB=10: the
// NB=8 approach from the sphere breaks down (node-to-node oscillation at the tips) and Newton on
// NB=10 finds no root, so the level is solved again along the branch from a lower Ca whose NB=8
// state resolves its tips. That branch reaches Ca = 0.38 only with grid-scale oscillation at
// the tips (a march from it stops at its first step): the level fails and says so. The climb
// that succeeds, to the neo-Hookean Ca = 0.4 state at NE=14 NB=14 (8 minutes), is a benchmark
// (docs/performance.md, "capflow steady").
#include <gtest/gtest.h>

#include <string>

#include "app/steady_run.h"
#include "control/control_file.h"
#include "process_util.h"

using namespace capflow;
namespace fs = std::filesystem;

TEST(SteadyValidation, AClimbToAStateTheGridDoesNotResolveFailsAndSaysWhy) {
  const fs::path d = test::fresh_dir("steady_climb");
  control::ParsedControl p = control::parse_control(R"({"capsule": {"law": "neo-hookean"},
    "mesh": {"elements": 6, "nb": 10}, "flow": {"type": "planar-extension"}, "ca": 0.38,
    "output": {"mp4": false}})");
  p.options.output.dir = d.string();
  const app::SteadySummary s = app::run_steady(p.options, false);
  EXPECT_TRUE(s.failed);
  EXPECT_NE(s.exit_code(), 0);
  EXPECT_EQ(s.states, 0);
  double from_ca = 0;
  int climbs = 0;
  for (const auto& e : test::events(d))
    if (e["event"] == "climb") {
      ++climbs;
      from_ca = e["from_ca"].get<double>();
    }
  EXPECT_EQ(climbs, 1) << "the level was not solved again along the branch";
  EXPECT_GT(from_ca, 0.0);
  EXPECT_LT(from_ca, 0.38);
  const std::string log = test::read_file(d / "run.log");
  EXPECT_NE(log.find("climb: the branch reaches Ca = 0.380000 with node-to-node oscillation"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("raise mesh.nb"), std::string::npos);
  EXPECT_NE(s.failure.find("; climb: the branch reaches Ca = 0.380000"), std::string::npos)
      << s.failure;
  fs::remove_all(d);
}
