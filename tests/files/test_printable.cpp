// files/printable: bytes from files shown on a terminal cannot drive it.
#include <gtest/gtest.h>

#include <string>

#include "files/printable.h"

using capflow::files::printable;

TEST(Printable, ControlBytesAreEscapedAndUtf8Passes) {
  // an xterm title sequence and a bell
  EXPECT_EQ(printable("a\x1b]0;PWNED\x07z"), "a\\x1B]0;PWNED\\x07z");
  EXPECT_EQ(printable("cr\rdel\x7f"), "cr\\x0Ddel\\x7F");
  // UTF-8 passes: tau_1 / G_s, the true minus
  EXPECT_EQ(printable("\u03c4\u2081 / G\u209b \u2212"), "\u03c4\u2081 / G\u209b \u2212");
  // a C1 control encoded in UTF-8 (U+009B, CSI) and a lone 0x9B byte
  EXPECT_EQ(printable("x\xc2\x9by"), "x\\u009By");
  EXPECT_EQ(printable("x\x9by"), "x\\x9By");
  // overlong and truncated sequences are not UTF-8
  EXPECT_EQ(printable("\xc0\xaf"), "\\xC0\\xAF");
  EXPECT_EQ(printable("\xe2\x82"), "\\xE2\\x82");
  // newlines and tabs only where lines are kept
  EXPECT_EQ(printable("a\nb\tc"), "a\\x0Ab\\x09c");
  EXPECT_EQ(printable("a\nb\tc", 100, true), "a\nb\tc");
}

TEST(Printable, LongTextIsCut) {
  const std::string s = printable(std::string(100, 'a'), 10);
  EXPECT_EQ(s, std::string(10, 'a') + "...");
  EXPECT_LE(printable(std::string(100, '\x1b'), 10).size(), 16u + 3u);
}
