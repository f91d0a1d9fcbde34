#include "tests/accuracy/corner_view_record.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <ostream>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

namespace monocle::testing {
namespace {

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

// Mean and standard error of the mean.
std::pair<double, double> MeanAndSe(const std::vector<double>& v) {
  if (v.empty()) return {std::nan(""), std::nan("")};
  double mean = 0;
  for (double x : v) mean += x / static_cast<double>(v.size());
  if (v.size() < 2) return {mean, std::nan("")};
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()))};
}

}  // namespace

void WriteCornerViewRecord(std::ostream& os, const CornerViewRecord& r) {
  os << r.seed << ' ' << r.index << ' ' << std::setprecision(6) << r.error_pct << ' ' << r.bound_pct
     << ' ' << r.sigma_pct << ' ' << (r.suspect ? 1 : 0) << ' ' << (r.short_edge ? 1 : 0) << '\n';
}

std::vector<CornerViewRecord> ReadCornerViewRecords(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot be read";
    return {};
  }
  static const char* kFields[] = {"seed",      "index",   "error_pct", "bound_pct",
                                  "sigma_pct", "suspect", "short_edge"};
  std::vector<CornerViewRecord> records;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    CornerViewRecord r;
    int suspect = 0, short_edge = 0;
    int read = 0;
    if (fields >> r.seed) ++read;
    if (read == 1 && fields >> r.index) ++read;
    if (read == 2 && fields >> r.error_pct) ++read;
    if (read == 3 && fields >> r.bound_pct) ++read;
    if (read == 4 && fields >> r.sigma_pct) ++read;
    if (read == 5 && fields >> suspect && (suspect == 0 || suspect == 1)) ++read;
    if (read == 6 && fields >> short_edge && (short_edge == 0 || short_edge == 1)) ++read;
    std::string extra;
    const bool errors_valid = read < 7 || (r.error_pct >= 0 && r.bound_pct > 0 && r.sigma_pct > 0);
    if (read < 7 || (fields >> extra) || !errors_valid) {
      *error = path + ":" + std::to_string(number) + ": field " +
               (read < 7        ? kFields[read]
                : !errors_valid ? "error_pct/bound_pct/sigma_pct"
                                : "(none: too many fields)") +
               " is missing or malformed in \"" + line +
               "\"; expected: seed index error_pct bound_pct sigma_pct suspect short_edge";
      return {};
    }
    r.suspect = suspect == 1;
    r.short_edge = short_edge == 1;
    records.push_back(r);
  }
  error->clear();
  return records;
}

PairedComparison ComparePaired(const std::vector<CornerViewRecord>& before,
                               const std::vector<CornerViewRecord>& after) {
  std::map<std::pair<uint64_t, int>, const CornerViewRecord*> by_view;
  for (const auto& r : before) by_view[{r.seed, r.index}] = &r;
  std::vector<std::pair<const CornerViewRecord*, const CornerViewRecord*>> pairs;
  for (const auto& r : after) {
    const auto it = by_view.find({r.seed, r.index});
    if (it != by_view.end()) pairs.push_back({it->second, &r});
  }
  PairedComparison c;
  c.views = static_cast<int>(pairs.size());
  static constexpr double kBinEdges[] = {0, 0.1, 0.3, 0.6, 1e300};
  std::vector<double> log_ratio, before_pct, after_pct, short_before, short_after;
  std::vector<std::vector<double>> bin_ratio(4);
  for (const auto& [b, a] : pairs) {
    before_pct.push_back(b->error_pct);
    after_pct.push_back(a->error_pct);
    c.over_1pct_before += b->error_pct > 1;
    c.over_1pct_after += a->error_pct > 1;
    if (b->short_edge) short_before.push_back(b->error_pct), short_after.push_back(a->error_pct);
    // An error of exactly 0 (a printed 0) would make the ratio infinite: floor at 1e-6 %.
    const double ratio = std::log(std::max(a->error_pct, 1e-6) / std::max(b->error_pct, 1e-6));
    log_ratio.push_back(ratio);
    for (int bin = 0; bin < 4; ++bin)
      if (b->bound_pct >= kBinEdges[bin] && b->bound_pct < kBinEdges[bin + 1])
        bin_ratio[bin].push_back(ratio);
  }
  std::tie(c.mean_log_ratio, c.mean_log_ratio_se) = MeanAndSe(log_ratio);
  c.p95_before_pct = Percentile(before_pct, 0.95);
  c.p95_after_pct = Percentile(after_pct, 0.95);
  c.short_edge_p95_before_pct = Percentile(short_before, 0.95);
  c.short_edge_p95_after_pct = Percentile(short_after, 0.95);
  for (const auto& v : bin_ratio) {
    PairedComparison::Bin bin;
    bin.views = static_cast<int>(v.size());
    std::tie(bin.mean_log_ratio, bin.mean_log_ratio_se) = MeanAndSe(v);
    c.by_bound.push_back(bin);
  }
  // The p95 ratio's interval: the same views resampled for both runs (paired bootstrap).
  if (!pairs.empty()) {
    std::mt19937_64 rng(1);
    std::uniform_int_distribution<size_t> pick(0, pairs.size() - 1);
    std::vector<double> ratios, b(pairs.size()), a(pairs.size());
    for (int draw = 0; draw < 2000; ++draw) {
      for (size_t i = 0; i < pairs.size(); ++i) {
        const size_t j = pick(rng);
        b[i] = before_pct[j], a[i] = after_pct[j];
      }
      ratios.push_back(Percentile(a, 0.95) / Percentile(b, 0.95));
    }
    c.p95_ratio_low = Percentile(ratios, 0.025);
    c.p95_ratio_high = Percentile(ratios, 0.975);
  }
  return c;
}

std::ostream& operator<<(std::ostream& os, const PairedComparison& c) {
  os << std::setprecision(3) << "paired over " << c.views
     << " views located in both runs: mean ln(error after / before) " << c.mean_log_ratio << " +- "
     << c.mean_log_ratio_se << " (negative: smaller errors after); p95 " << c.p95_before_pct
     << " -> " << c.p95_after_pct << " % of the distance, ratio's 95 % interval " << c.p95_ratio_low
     << "-" << c.p95_ratio_high << " (paired bootstrap); more than 1 % off " << c.over_1pct_before
     << " -> " << c.over_1pct_after << "; short-edge views' p95 " << c.short_edge_p95_before_pct
     << " -> " << c.short_edge_p95_after_pct << " %\n";
  static const char* kBins[] = {"under 0.1 %", "0.1-0.3 %", "0.3-0.6 %", "over 0.6 %"};
  for (size_t i = 0; i < c.by_bound.size(); ++i) {
    os << "  views whose bound is " << kBins[i] << ": " << c.by_bound[i].views << ", mean ln ratio "
       << c.by_bound[i].mean_log_ratio << " +- " << c.by_bound[i].mean_log_ratio_se << "\n";
  }
  return os;
}

}  // namespace monocle::testing
