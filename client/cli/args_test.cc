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

TEST(ArgsTest, RejectsUnknownOptionsAndMissingValuesInMonoclesWords) {
  const auto unknown = Args::Parse({"a.png", "--bord", "9x6"}, kSpec);
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().message, "unknown option --bord (see --help)");
  const auto unknown_inline = Args::Parse({"--bord=9x6"}, kSpec);
  ASSERT_FALSE(unknown_inline.ok());
  EXPECT_EQ(unknown_inline.error().message, "unknown option --bord (see --help)");
  const auto missing = Args::Parse({"a.png", "--board"}, kSpec);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "--board needs a value");
  const auto flag_value = Args::Parse({"--json=1"}, kSpec);
  ASSERT_FALSE(flag_value.ok());
  EXPECT_EQ(flag_value.error().message, "--json takes no value");
}

TEST(ArgsTest, KeepsPositionalOrderAndTheLastOfARepeatedOption) {
  const auto args = Args::Parse(
      {"a.png", "--board", "9x6", "b.png", "--board=7x5", "c.png", "--", "--json", "-x"}, kSpec);
  ASSERT_TRUE(args.ok()) << args.error();
  // After "--" everything is a positional, options included.
  EXPECT_EQ(args->positionals(),
            (std::vector<std::string>{"a.png", "b.png", "c.png", "--json", "-x"}));
  EXPECT_FALSE(args->Has("--json"));
  EXPECT_EQ(*args->Get("--board"), "7x5");
  EXPECT_EQ(args->GetAll("--board"), (std::vector<std::string>{"9x6", "7x5"}));
  EXPECT_FALSE(args->Get("--box").has_value());
}

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
  EXPECT_FALSE(floor->floor_px.has_value());
  // u,v@fu,fv: the pixel u,v stands above the floor pixel fu,fv.
  const auto above = ParsePointArgument("640,300@641,800");
  ASSERT_TRUE(above.ok()) << above.error();
  EXPECT_EQ(above->u, 640);
  EXPECT_EQ(above->v, 300);
  ASSERT_TRUE(above->floor_px.has_value());
  EXPECT_EQ(above->floor_px->first, 641);
  EXPECT_EQ(above->floor_px->second, 800);
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
