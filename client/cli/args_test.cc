#include "client/cli/args.h"

#include <gtest/gtest.h>

namespace monocle::cli {
namespace {

const ArgSpec kSpec{{"--board", "--box"}, {"--json"}};

TEST(ArgsTest, ParsesOptionsFlagsAndNegativeNumbers) {
  const auto args = Args::Parse(
      {"img.png", "--board", "9x6", "--json", "-3.5,2", "--box=1,2,3,4,5", "--box", "6,7,8,9,1"},
      kSpec);
  ASSERT_TRUE(args.ok()) << args.error();
  EXPECT_EQ(args->positionals(), (std::vector<std::string>{"img.png", "-3.5,2"}));
  EXPECT_EQ(*args->Get("--board"), "9x6");
  EXPECT_TRUE(args->Has("--json"));
  EXPECT_EQ(args->GetAll("--box").size(), 2u);
}

TEST(ArgsTest, RejectsUnknownOptionsAndMissingValues) {
  EXPECT_FALSE(Args::Parse({"--bord", "9x6"}, kSpec).ok());
  EXPECT_FALSE(Args::Parse({"--board"}, kSpec).ok());
  EXPECT_FALSE(Args::Parse({"--json=1"}, kSpec).ok());
}

TEST(ArgsTest, ParsesNumberLists) {
  EXPECT_EQ(*ParseNumberList("1,2.5,-3"), (std::vector<double>{1, 2.5, -3}));
  EXPECT_FALSE(ParseNumberList("1,,2").has_value());
  EXPECT_FALSE(ParseNumberList("1,2,").has_value());
  EXPECT_FALSE(ParseNumberList("1,nan").has_value());
  EXPECT_FALSE(ParseNumberList("1,2x").has_value());
}

}  // namespace
}  // namespace monocle::cli
