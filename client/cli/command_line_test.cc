#include "client/cli/command_line.h"

#include <gtest/gtest.h>

#include <iostream>
#include <sstream>

namespace monocle::cli {
namespace {

// A command with two forms, as `floor measure` has: offline (--calibration) and live
// (--camera), sharing --json and a number with a unit.
struct Example {
  std::vector<std::string> points;
  std::string calibration;
  std::optional<std::string> camera;
  double sigma_px = 0.5;
  int count = 1;
  std::string method = "full";
  bool json = false;
  CommandLine line{"floor measure", "Measures points."};
  Example() {
    line.Positionals("POINT", &points, "a pixel");
    line.Number("--pixel-sigma", &sigma_px, "PX", "noise of a pixel", In("pixels").AtLeast(0));
    line.Flag("--json", &json, "print JSON");
    line.InForms({0});
    line.Text("--calibration", &calibration, "CAL.pbtxt", "a calibration file");
    line.Require("--calibration");
    line.Choice("--method", &method, {"full", "paper"}, "how");
    line.Form("Live");
    line.Text("--camera", &camera, "ID", "a camera of the service");
    line.Require("--camera");
    line.Whole("--count", &count, "N", "poses", In("poses").AtLeast(1));
  }
};

// Runs Parse with stderr captured.
std::optional<int> Parse(Example& e, const std::vector<std::string>& argv, std::string* err) {
  std::ostringstream captured;
  std::streambuf* const previous = std::cerr.rdbuf(captured.rdbuf());
  const auto r = e.line.Parse(argv);
  std::cerr.rdbuf(previous);
  *err = captured.str();
  return r;
}

TEST(CommandLineTest, FillsTheTypedFields) {
  Example e;
  std::string err;
  EXPECT_FALSE(Parse(e,
                     {"1,2", "--pixel-sigma", "0.8", "--calibration=c.pbtxt", "3,4", "--json",
                      "--method", "paper", "-5.5,6"},
                     &err))
      << err;
  EXPECT_EQ(e.points, (std::vector<std::string>{"1,2", "3,4", "-5.5,6"}));
  EXPECT_EQ(e.sigma_px, 0.8);
  EXPECT_EQ(e.calibration, "c.pbtxt");
  EXPECT_EQ(e.method, "paper");
  EXPECT_TRUE(e.json);
  EXPECT_EQ(e.line.ChosenForm(), 0);
  EXPECT_FALSE(e.camera.has_value());
}

TEST(CommandLineTest, TheOptionsGivenChooseTheForm) {
  Example e;
  std::string err;
  EXPECT_FALSE(Parse(e, {"--camera", "floor", "--count", "3", "1,2"}, &err)) << err;
  EXPECT_EQ(e.line.ChosenForm(), 1);
  EXPECT_EQ(*e.camera, "floor");
  EXPECT_EQ(e.count, 3);
  Example both;
  EXPECT_EQ(Parse(both, {"--camera", "x", "--calibration", "c", "1,2"}, &err), 2);
  EXPECT_NE(err.find("--calibration and --camera do not go together"), std::string::npos) << err;
}

TEST(CommandLineTest, EveryMistakeIsNamedAndExitsWithTwo) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"1,2"}, "missing --calibration CAL.pbtxt"},
      {{"--calibration", "c"}, "floor measure takes at least 1 POINT, not 0"},
      {{"--calibration", "c", "1,2", "--pixel-sigma", "-1"},
       "--pixel-sigma must be a number of pixels >= 0, not '-1'"},
      {{"--calibration", "c", "1,2", "--pixel-sigma", "abc"}, "--pixel-sigma must be a number"},
      {{"--calibration", "c", "1,2", "--pixel-sigma"}, "--pixel-sigma needs a value"},
      {{"--calibration", "c", "1,2", "--method", "fast"},
       "--method 'fast' is not one of full, paper"},
      {{"--calibration", "c", "1,2", "--bogus", "3"}, "unknown option --bogus"},
      {{"--calibration", "c", "1,2", "--json=1"}, "--json takes no value"},
      {{"--camera", "x", "1,2", "--count", "1.5"}, "--count must be a whole number of poses >= 1"},
  };
  for (const auto& [argv, expected] : cases) {
    Example e;
    std::string err;
    EXPECT_EQ(Parse(e, argv, &err), 2) << expected;
    EXPECT_NE(err.find(expected), std::string::npos)
        << "expected: " << expected << "\ngot: " << err;
  }
}

TEST(CommandLineTest, AfterTwoDashesEverythingIsPositionalAndRepeatsAreKept) {
  std::vector<std::string> words, boxes;
  bool json = false;
  CommandLine line("render floor", "");
  line.Positionals("WORD", &words, "a word", 0);
  line.Texts("--box", &boxes, "X,Y,W,D,H", "a box");
  line.Flag("--json", &json, "JSON");
  std::ostringstream captured;
  std::streambuf* const previous = std::cerr.rdbuf(captured.rdbuf());
  const auto r =
      line.Parse({"a", "--box=1,2,3,4,5", "b", "--box", "6,7,8,9,1", "--", "--json", "-x"});
  std::cerr.rdbuf(previous);
  EXPECT_FALSE(r) << captured.str();
  EXPECT_EQ(words, (std::vector<std::string>{"a", "b", "--json", "-x"}));
  EXPECT_EQ(boxes, (std::vector<std::string>{"1,2,3,4,5", "6,7,8,9,1"}));
  EXPECT_FALSE(json);
}

TEST(CommandLineTest, TheLastOccurrenceCounts) {
  Example e;
  std::string err;
  EXPECT_FALSE(Parse(e, {"--calibration", "a", "--calibration", "b", "1,2"}, &err)) << err;
  EXPECT_EQ(e.calibration, "b");
}

TEST(CommandLineTest, HelpIsMadeFromTheDeclarations) {
  Example e;
  std::ostringstream captured;
  std::streambuf* const previous = std::cout.rdbuf(captured.rdbuf());
  const auto r = e.line.Parse({"--help"});
  std::cout.rdbuf(previous);
  EXPECT_EQ(r, 0);
  const std::string help = captured.str();
  EXPECT_EQ(help.rfind("Usage: monocle floor measure POINT... --calibration CAL.pbtxt", 0), 0u)
      << help;
  EXPECT_NE(help.find("       monocle floor measure POINT... --camera ID"), std::string::npos)
      << help;
  EXPECT_NE(help.find("--pixel-sigma PX"), std::string::npos) << help;
  EXPECT_NE(help.find("noise of a pixel (a number of pixels >= 0; default 0.5)"), std::string::npos)
      << help;
  EXPECT_NE(help.find("a calibration file (required)"), std::string::npos) << help;
  EXPECT_NE(help.find("--method full|paper"), std::string::npos) << help;
  EXPECT_NE(help.find("\nLive:\n  --camera ID"), std::string::npos) << help;
  EXPECT_EQ(help.find("--camera", help.find("Live:")),
            help.find("--camera ID", help.find("Live:")));
  EXPECT_EQ(help, e.line.Help());
}

}  // namespace
}  // namespace monocle::cli
