// One line per located corner view, written by corner_accuracy_test's fresh-seed harness
// (MONOCLE_CORNER_VIEWS_OUT) and read back to compare two versions of the locator on the same
// views (MONOCLE_CORNER_VIEWS_BEFORE). A change to the locator is judged by how each view's error
// moves, paired, not by two sets' p95 side by side: p95 of ~1000 views scatters by +-10 % from
// set to set, far more than most changes move it, while the same views before and after share
// that scatter. tests/accuracy/corner_pose_notes.md records what such comparisons measured.
//
// File format, text, one view per line ('#' starts a comment line):
//   seed index error_pct bound_pct sigma_pct suspect short_edge
// error_pct: horizontal position error, % of the camera's horizontal distance to the corner;
// bound_pct: the Cramér–Rao bound's sqrt(trace), same unit; sigma_pct: the pose's reported
// horizontal 1 sigma (sqrt(var x + var y)), same unit; suspect, short_edge: 0 or 1.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace monocle::testing {

struct CornerViewRecord {
  uint64_t seed = 0;
  int index = 0;
  double error_pct = 0, bound_pct = 0, sigma_pct = 0;
  bool suspect = false, short_edge = false;
};

void WriteCornerViewRecord(std::ostream& os, const CornerViewRecord& record);

// Every record in `path`; on a malformed line, `error` names the file, the line and the field
// (and the result is empty).
std::vector<CornerViewRecord> ReadCornerViewRecords(const std::string& path, std::string* error);

// Two runs over the same views, paired by (seed, index).
struct PairedComparison {
  int views = 0;                 // located in both runs
  double mean_log_ratio = 0;     // mean of ln(error after / error before)
  double mean_log_ratio_se = 0;  // its standard error
  double p95_before_pct = 0, p95_after_pct = 0;
  double p95_ratio_low = 0, p95_ratio_high = 0;  // 95 % bootstrap interval of p95 after / before
  int over_1pct_before = 0, over_1pct_after = 0;
  double short_edge_p95_before_pct = 0, short_edge_p95_after_pct = 0;
  // By the view's bound (%, before's): [0, 0.1), [0.1, 0.3), [0.3, 0.6), [0.6, inf).
  struct Bin {
    int views = 0;
    double mean_log_ratio = 0, mean_log_ratio_se = 0;
  };
  std::vector<Bin> by_bound;
};

PairedComparison ComparePaired(const std::vector<CornerViewRecord>& before,
                               const std::vector<CornerViewRecord>& after);

std::ostream& operator<<(std::ostream& os, const PairedComparison& c);

}  // namespace monocle::testing
