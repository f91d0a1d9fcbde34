#include "tests/accuracy/corner_view_record.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace monocle::testing {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("monocle_" + name)).string();
}

// 100 views: view i's error is i/100 % (so p95 is 0.95 %), bound 0.05-0.7 %.
std::vector<CornerViewRecord> HundredViews(double scale) {
  std::vector<CornerViewRecord> v;
  for (int i = 0; i < 100; ++i) {
    CornerViewRecord r;
    r.seed = 7 + i / 50;
    r.index = i % 50;
    r.error_pct = scale * (i + 1) / 100.0;
    r.bound_pct = 0.05 + 0.0065 * i;
    r.sigma_pct = 0.2;
    r.short_edge = i % 3 == 0;
    r.suspect = i > 97;
    v.push_back(r);
  }
  return v;
}

TEST(CornerViewRecordTest, WrittenRecordsReadBackUnchanged) {
  const std::string path = TempPath("views_roundtrip.txt");
  const auto views = HundredViews(1.0);
  {
    std::ofstream out(path);
    out << "# seed index error_pct bound_pct sigma_pct suspect short_edge\n";
    for (const auto& r : views) WriteCornerViewRecord(out, r);
  }
  std::string error;
  const auto read = ReadCornerViewRecords(path, &error);
  EXPECT_EQ(error, "");
  ASSERT_EQ(read.size(), views.size());
  for (size_t i = 0; i < views.size(); ++i) {
    EXPECT_EQ(read[i].seed, views[i].seed);
    EXPECT_EQ(read[i].index, views[i].index);
    EXPECT_NEAR(read[i].error_pct, views[i].error_pct, 1e-5);
    EXPECT_NEAR(read[i].bound_pct, views[i].bound_pct, 1e-5);
    EXPECT_EQ(read[i].suspect, views[i].suspect);
    EXPECT_EQ(read[i].short_edge, views[i].short_edge);
  }
  std::remove(path.c_str());
}

TEST(CornerViewRecordTest, AMalformedLineIsRejectedWithItsLineAndField) {
  const std::string path = TempPath("views_broken.txt");
  {
    std::ofstream out(path);
    out << "7 0 0.1 0.05 0.2 0 1\n";
    out << "# a comment\n";
    out << "7 1 0.1 0.05 0.2 maybe 1\n";
  }
  std::string error;
  EXPECT_TRUE(ReadCornerViewRecords(path, &error).empty());
  EXPECT_NE(error.find(path + ":3: field suspect"), std::string::npos) << error;
  {
    std::ofstream out(path);
    out << "7 0 0.1 0.05 0.2 0 1 extra\n";
  }
  EXPECT_TRUE(ReadCornerViewRecords(path, &error).empty());
  EXPECT_NE(error.find(":1: field (none: too many fields)"), std::string::npos) << error;
  {
    std::ofstream out(path);
    out << "7 0 0.1 -0.05 0.2 0 1\n";  // a negative bound
  }
  EXPECT_TRUE(ReadCornerViewRecords(path, &error).empty());
  EXPECT_NE(error.find(":1: field error_pct/bound_pct/sigma_pct"), std::string::npos) << error;
  std::remove(path.c_str());
  EXPECT_TRUE(ReadCornerViewRecords(path, &error).empty());
  EXPECT_NE(error.find("cannot be read"), std::string::npos) << error;
}

TEST(CornerViewRecordTest, ErrorsHalvedOnTheSameViewsAreSeenAsHalved) {
  const auto before = HundredViews(1.0);
  const auto after = HundredViews(0.5);
  const PairedComparison c = ComparePaired(before, after);
  EXPECT_EQ(c.views, 100);
  EXPECT_NEAR(c.mean_log_ratio, std::log(0.5), 1e-9);
  EXPECT_NEAR(c.mean_log_ratio_se, 0, 1e-9);
  EXPECT_NEAR(c.p95_before_pct, 0.96, 1e-9);  // the 96th of 100 sorted, as the tests count p95
  EXPECT_NEAR(c.p95_after_pct, 0.48, 1e-9);
  // Every resample halves p95 too: the interval is a point.
  EXPECT_NEAR(c.p95_ratio_low, 0.5, 1e-9);
  EXPECT_NEAR(c.p95_ratio_high, 0.5, 1e-9);
  EXPECT_EQ(c.over_1pct_before, 0);
  ASSERT_EQ(c.by_bound.size(), 4u);
  int binned = 0;
  for (const auto& bin : c.by_bound) binned += bin.views;
  EXPECT_EQ(binned, 100);
}

TEST(CornerViewRecordTest, OnlyViewsLocatedInBothRunsArePaired) {
  auto before = HundredViews(1.0);
  auto after = HundredViews(1.0);
  after.erase(after.begin() + 10, after.begin() + 20);  // not located after
  after[0].error_pct *= std::exp(1.0);
  const PairedComparison c = ComparePaired(before, after);
  EXPECT_EQ(c.views, 90);
  EXPECT_NEAR(c.mean_log_ratio, 1.0 / 90, 1e-9);
  EXPECT_LE(c.p95_ratio_low, 1.0);
  EXPECT_GE(c.p95_ratio_high, 1.0);
  std::ostringstream printed;
  printed << c;
  EXPECT_NE(printed.str().find("paired over 90 views"), std::string::npos) << printed.str();
}

}  // namespace
}  // namespace monocle::testing
