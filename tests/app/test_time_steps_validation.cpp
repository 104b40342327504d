// The default adaptive tolerance against a fixed step 8x smaller than the largest adaptive step
// (Skalak C=1, Ca=0.35, NE=6, NB=12 from rest to t=0.15, the paper's sec. 5 case): D, L, S, W
// and the volume agree within 1e-5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "app/simulation.h"
#include "control/control_file.h"
#include "test_util.h"

using namespace capflow;
namespace fs = std::filesystem;

namespace {

control::ControlOptions options(const fs::path& dir) {
  control::ParsedControl p = control::parse_control(R"({
    "capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 12, "division": "cube"},
    "time": {"t_end": 0.15}, "ca": 0.35, "output": {"csv_every": 0.05}})");
  p.options.output.dir = dir.string();
  return p.options;
}

struct Final {
  double D, L, S, W, volume, max_dt;
  long steps;
};

Final run(const control::ControlOptions& o) {
  app::Simulation sim(o, "");
  const app::RunSummary s = sim.run();
  EXPECT_FALSE(s.failed) << s.failure;
  const fs::path csv = fs::path(o.output.dir) / "timeseries.csv";
  const std::vector<double> dt = test::csv_column(csv, "dt");
  return {s.D,
          s.L,
          s.S,
          s.W,
          test::csv_column(csv, "volume").back(),
          *std::max_element(dt.begin(), dt.end()),
          s.steps};
}

}  // namespace

TEST(TimeStepsValidation, DefaultToleranceAgreesWithAFixedStepEightTimesSmaller) {
  const fs::path da = test::fresh_dir("auto_default"), df = test::fresh_dir("fixed_small");
  const control::ControlOptions oa = options(da);
  ASSERT_TRUE(oa.time.adaptive);  // "auto" is the default
  const Final a = run(oa);
  control::ControlOptions of = options(df);
  of.time.adaptive = false;
  const long n = static_cast<long>(std::ceil(0.15 / (a.max_dt / 8)));
  of.time.dt = 0.15 / n;
  const Final f = run(of);
  EXPECT_EQ(f.steps, n);
  std::printf(
      "auto: %ld steps (largest %.5f); fixed dt = %.6f: %ld steps; differences D %.1e "
      "L %.1e S %.1e W %.1e volume %.1e\n",
      a.steps, a.max_dt, of.time.dt, f.steps, std::abs(a.D - f.D), std::abs(a.L - f.L),
      std::abs(a.S - f.S), std::abs(a.W - f.W), std::abs(a.volume - f.volume));
  EXPECT_NEAR(a.D, f.D, 1e-5);
  EXPECT_NEAR(a.L, f.L, 1e-5);
  EXPECT_NEAR(a.S, f.S, 1e-5);
  EXPECT_NEAR(a.W, f.W, 1e-5);
  EXPECT_NEAR(a.volume, f.volume, 1e-5);
  fs::remove_all(da);
  fs::remove_all(df);
}
