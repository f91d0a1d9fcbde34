#include "client/cli/args.h"

#include <gtest/gtest.h>

namespace monocle::cli {
namespace {

TEST(ArgsTest, ParsesNumberLists) {
  EXPECT_EQ(*ParseNumberList("1,2.5,-3"), (std::vector<double>{1, 2.5, -3}));
  EXPECT_FALSE(ParseNumberList("1,,2").has_value());
  EXPECT_FALSE(ParseNumberList("1,2,").has_value());
  EXPECT_FALSE(ParseNumberList("1,nan").has_value());
  EXPECT_FALSE(ParseNumberList("1,2x").has_value());
}

TEST(ArgsTest, ParsesPointArguments) {
  const auto floor = ParsePointArgument("640.5,800");
  ASSERT_TRUE(floor.ok()) << floor.error();
  EXPECT_EQ(floor->u, 640.5);
  EXPECT_EQ(floor->v, 800);
  EXPECT_FALSE(floor->foot_px.has_value());
  // u,v@fu,fv: the pixel u,v stands above the floor pixel fu,fv.
  const auto above = ParsePointArgument("640,300@641,800");
  ASSERT_TRUE(above.ok()) << above.error();
  EXPECT_EQ(above->u, 640);
  EXPECT_EQ(above->v, 300);
  ASSERT_TRUE(above->foot_px.has_value());
  EXPECT_EQ((*above->foot_px)[0], 641);
  EXPECT_EQ((*above->foot_px)[1], 800);
  for (const char* bad : {"", "640", "640,800,1", "640,800@", "@640,800", "640,800@1", "nan,1",
                          "1,inf", "1,2@3,4@5,6", "1e999,2"}) {
    const auto r = ParsePointArgument(bad);
    EXPECT_FALSE(r.ok()) << bad;
    if (!r) {
      EXPECT_NE(r.error().message.find("is not u,v"), std::string::npos) << bad;
    }
  }
}

}  // namespace
}  // namespace monocle::cli
