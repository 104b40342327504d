// control/sweep: a sweep file's cases (every combination, the last key fastest), ranges, the
// case control files, and the errors that name the field.
#include <gtest/gtest.h>

#include <string>

#include "control/control_error.h"
#include "control/control_file.h"
#include "control/sweep.h"

using namespace capflow;

namespace {
const char* kBase = R"({"capsule": {"law": "skalak", "C": 1}, "mesh": {"elements": 6, "nb": 6},
  "flow": {"type": "planar-extension"}, "ca": 0.3, "time": {"t_end": 0.1}})";

control::SweepPlan plan_of(const std::string& vary) {
  return control::parse_sweep(std::string(R"({"base": )") + kBase + R"(, "vary": )" + vary + "}",
                              "sweep.json", ".", "runs/s");
}

std::string error_of(const std::string& doc) {
  try {
    control::parse_sweep(doc, "sweep.json", ".", "runs/s");
  } catch (const control::ControlError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Sweep, EveryCombinationTheLastKeyFastest) {
  const control::SweepPlan p = plan_of(R"({"ca": [0.3, 0.6], "capsule.C": [1, 2, 3]})");
  // keys in alphabetical order (the JSON object's), the last varying fastest
  ASSERT_EQ(p.keys, (std::vector<std::string>{"ca", "capsule.C"}));
  ASSERT_EQ(p.cases.size(), 6u);
  EXPECT_EQ(p.cases[0].label(), "ca = 0.3, capsule.C = 1");
  EXPECT_EQ(p.cases[1].label(), "ca = 0.3, capsule.C = 2");
  EXPECT_EQ(p.cases[5].label(), "ca = 0.6, capsule.C = 3");
  EXPECT_EQ(p.cases[4].name, "case_004");
  EXPECT_EQ(p.dir, "runs/s");
  // each case's control file is the base with the values and its own run directory
  const control::ParsedControl c = control::parse_control(p.cases[5].control_text);
  EXPECT_EQ(c.options.law.c, 3.0);
  EXPECT_EQ(c.options.output.dir, "runs/s/case_005");
  EXPECT_EQ(c.options.mesh.nb, 6);
}

TEST(Sweep, RangesAreLinearOrLogarithmic) {
  const control::SweepPlan lin = plan_of(R"({"ca": {"from": 0.1, "to": 0.5, "count": 5}})");
  ASSERT_EQ(lin.cases.size(), 5u);
  EXPECT_EQ(lin.cases[2].values[0].second, "0.3");  // written to 12 digits, not 0.30000000000000004
  EXPECT_EQ(lin.cases[4].values[0].second, "0.5");
  const control::SweepPlan lg = plan_of(
      R"({"capsule.viscosity_ratio": {"from": 0.1, "to": 10, "count": 3, "scale": "log"}})");
  ASSERT_EQ(lg.cases.size(), 3u);
  EXPECT_EQ(lg.cases[1].values[0].second, "1");
}

TEST(Sweep, ProblemsNameTheirField) {
  const std::string base = std::string(R"({"base": )") + kBase;
  const auto has = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  EXPECT_TRUE(has(error_of(base + R"(, "vary": {"ca": []}})"), "vary.ca: an empty list"));
  EXPECT_TRUE(has(error_of(base + R"(, "vary": {"ca": {"from": 1, "to": 2, "cnt": 3}}})"),
                  "did you mean \"count\""));
  EXPECT_TRUE(has(error_of(base + R"(, "varry": {"ca": [1]}})"), "did you mean \"vary\""));
  // a value the control file refuses: the case, its values and the field
  EXPECT_TRUE(has(error_of(base + R"(, "vary": {"ca": [0.3, -1]}})"),
                  "case 1 (ca = -1): ca: value -1 is out of range"));
  EXPECT_TRUE(has(error_of(base + R"(, "vary": {"output.dir": ["a"]}})"),
                  "the sweep sets each case's output.dir"));
  EXPECT_TRUE(has(error_of(base + R"(, "vary": {"ca": {"from": 0, "to": 1, "count": 2,
                  "scale": "log"}}})"),
                  "a log range needs from and to > 0"));
  EXPECT_TRUE(has(error_of(base + R"(, "vary": {"ca": {"from": 0.1, "to": 1, "count": 200},
                  "capsule.C": {"from": 1, "to": 2, "count": 200}}})"),
                  "40000 cases: at most 10000"));
  EXPECT_TRUE(has(error_of(R"({"vary": {"ca": [1]}})"), "base: missing"));
  EXPECT_TRUE(has(error_of("[1]"), "a sweep file is a JSON object"));
  EXPECT_TRUE(has(error_of(R"({"base": "no_such_base.json", "vary": {"ca": [1]}})"),
                  "cannot open the file"));
}
