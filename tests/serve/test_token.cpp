// serve/token: fresh tokens, comparison and where a request carries one.
#include <gtest/gtest.h>

#include <set>

#include "serve/token.h"

namespace capflow::serve {
namespace {

TEST(Token, FreshTokensAre32HexDigitsAndDiffer) {
  std::set<std::string> seen;
  for (int i = 0; i < 100; ++i) {
    const std::string t = new_token();
    EXPECT_EQ(t.size(), 32u);
    EXPECT_EQ(t.find_first_not_of("0123456789abcdef"), std::string::npos);
    seen.insert(t);
  }
  EXPECT_EQ(seen.size(), 100u);
}

TEST(Token, OnlyTheWholeTokenMatches) {
  const std::string t = "00112233445566778899aabbccddeeff";
  EXPECT_TRUE(same_token(t, t));
  EXPECT_FALSE(same_token("", t));
  EXPECT_FALSE(same_token(t.substr(0, 31), t));
  EXPECT_FALSE(same_token(t + "0", t));
  EXPECT_FALSE(same_token(std::string(t).replace(31, 1, "e"), t));
  EXPECT_FALSE(same_token(std::string(t).replace(0, 1, "1"), t));
  EXPECT_FALSE(same_token("", "")) << "an empty expected token matches nothing";
  std::string with_nul = t;
  with_nul[5] = '\0';
  EXPECT_FALSE(same_token(with_nul, t));
}

TEST(Token, HeadersComeFirstAndSaySo) {
  Request r;
  r.params["token"] = "q";
  r.headers["cookie"] = "a=b; capflow_token=c; d=e";
  EXPECT_EQ(token_of(r).value, "q");
  EXPECT_FALSE(token_of(r).in_header);
  r.params.clear();
  EXPECT_EQ(token_of(r).value, "c");
  EXPECT_FALSE(token_of(r).in_header);
  r.headers["x-capflow-token"] = "x";
  EXPECT_EQ(token_of(r).value, "x");
  EXPECT_TRUE(token_of(r).in_header);
  r.headers["authorization"] = "Bearer b";
  EXPECT_EQ(token_of(r).value, "b");
  EXPECT_TRUE(token_of(r).in_header);
  r.headers["authorization"] = "Basic b";
  EXPECT_EQ(token_of(r).value, "x");
}

}  // namespace
}  // namespace capflow::serve
