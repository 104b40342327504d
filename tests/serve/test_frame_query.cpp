// serve/frame_query: every parameter of GET /api/frame checked, with its range in the message.
#include <gtest/gtest.h>

#include "serve/frame_query.h"

namespace capflow::serve {
namespace {

FrameQuery parse(std::map<std::string, std::string> p, std::string* error) {
  Request r;
  r.params = std::move(p);
  return parse_frame_query(r, error);
}

TEST(FrameQuery, DefaultsAndValues) {
  std::string e;
  FrameQuery q = parse({}, &e);
  EXPECT_EQ(e, "");
  EXPECT_EQ(q.width, 1280);
  EXPECT_EQ(q.height, 720);
  EXPECT_FALSE(q.time);
  q = parse({{"yaw", "-30"}, {"pitch", "90"}, {"zoom", "2.5"}, {"field", "tau2"},
             {"range", "frame"}, {"width", "640"}, {"height", "360"}, {"time", "1.5"},
             {"format", "png"}},
            &e);
  EXPECT_EQ(e, "");
  EXPECT_EQ(q.orbit.yaw, -30);
  EXPECT_EQ(q.orbit.pitch, 90);
  EXPECT_EQ(q.orbit.zoom, 2.5);
  EXPECT_EQ(q.field, render::ColorField::MinTension);
  EXPECT_EQ(q.range, render::RangeMode::Frame);
  EXPECT_EQ(q.width, 640);
  EXPECT_EQ(*q.time, 1.5);
  EXPECT_TRUE(q.png);
  q = parse({{"view", "xy"}, {"zoom", "2"}}, &e);
  EXPECT_EQ(e, "");
  EXPECT_EQ(q.orbit.pitch, 90);
  EXPECT_EQ(q.orbit.zoom, 2);
}

TEST(FrameQuery, BadValuesNameTheParameterAndItsRange) {
  struct Case {
    const char* name;
    const char* value;
    const char* words;
  };
  for (const Case& c :
       {Case{"yaw", "nan", "[-3600, 3600]"}, Case{"yaw", "1e400", "yaw"},
        Case{"pitch", "90.5", "[-90, 90]"}, Case{"zoom", "0", "[0.05, 20]"},
        Case{"zoom", "inf", "zoom"}, Case{"width", "641", "even"}, Case{"width", "8000", "2560"},
        Case{"height", "-2", "height"}, Case{"height", "2e3", "1440"},
        Case{"time", "abc", "time"}, Case{"field", "pressure", "tau1"}, Case{"range", "fixed", "grow"},
        Case{"format", "gif", "jpeg"}, Case{"view", "top", "oblique"}, Case{"yaw", "", "yaw"},
        Case{"yaw", "1 ", "yaw"}, Case{"width", "0x100", "width"}}) {
    std::string e;
    parse({{c.name, c.value}}, &e);
    EXPECT_NE(e.find(c.words), std::string::npos) << c.name << "=" << c.value << ": " << e;
  }
}

}  // namespace
}  // namespace capflow::serve
