// Paired comparisons of a study's configurations over seeds: what lets a report conclude.
// Every configuration of a study runs the same seeds, so the per-seed difference of a metric
// between two configurations cancels what the seeds have in common (a firefly of that seed, the
// machine's load at its turn). The mean of those differences, with a 95% confidence interval from
// Student's t, says whether the two differ (the interval excludes 0) or the study cannot tell.
// This is scripts/study_paired.py's analysis, computed by the harness for report.html.
#pragma once
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "study/results.h"
#include "study/study_file.h"

namespace rl::study {

// Two-sided 95% quantile of Student's t with dof degrees of freedom (dof >= 1).
double t975(int dof);

// Mean and 95% confidence half-width (t distribution) of the finite values; half is NaN for n < 2.
struct Interval {
  double mean = kNone, half = kNone;
  int n = 0;
  double lo() const { return mean - half; }
  double hi() const { return mean + half; }
  bool excludes(double v) const { return n >= 2 && std::isfinite(half) && (lo() > v || hi() < v); }
};
Interval mean_ci(const std::vector<double>& v);

// Lower is better for every metric but fps (and the "x" of a metric product, see plot_verdict).
bool lower_is_better(const std::string& metric);

// seed -> value of one metric for one configuration (at the last frame).
using SeedValues = std::map<uint64_t, double>;

// a − b over the seeds both have (paired); where fewer than 2 seeds are shared, the unpaired
// difference of means with non-overlapping 95% intervals as the test. resolved: the difference is
// not 0 at 95%. Values computed across seeds (noise: one per configuration, no spread over seeds)
// carry no uncertainty estimate and never resolve.
struct Comparison {
  Interval diff;   // paired: mean and CI of a − b; unpaired: diff.mean = mean(a) − mean(b), no CI
  Interval ratio;  // paired only: mean and CI of a / b per seed
  bool paired = false, resolved = false;
  bool measured = false;  // a or b varies over seeds (else: no uncertainty estimate at all)
};
Comparison compare(const SeedValues& a, const SeedValues& b);

// One configuration of one scene, with its per-seed values of a metric.
struct ConfigValues {
  std::string scene, config, label;  // label: "key=value, ..." of the keys that tell it apart
  Row first;                         // its first row (options, to match a baseline)
  SeedValues values;
  double mean() const;
};
// The configurations of `rows` (the last frame, rows matching `where`) in first-seen order, with
// metric `metric` ("a*b" = the product of two metrics per seed). Labels name the option keys whose
// values differ between the configurations but not between seeds (so never render.seed), each only
// where the configuration's integrator reads it (reads_option).
std::vector<ConfigValues> config_values(const std::vector<Row>& rows, const std::string& metric, int last_frame,
                                        const std::vector<std::pair<std::string, std::string>>& where = {});

// The option keys whose value is one per group (configuration) and not the same for all groups.
std::vector<std::string> distinguishing_keys(const std::vector<std::vector<const Row*>>& groups);

enum class Verdict { Better, Worse, NotResolved };
const char* verdict_text(Verdict v);  // "better", "worse", "not resolved"

struct PairedRow {
  size_t config = 0, base = 0;  // indices into PairedTable::configs
  Comparison cmp;  // config − base
  Verdict verdict = Verdict::NotResolved;
};
struct PairedTable {
  std::string metric;  // a metric column or "a*b"
  std::vector<ConfigValues> configs;
  std::vector<PairedRow> rows;
};
// The metrics a report compares: the study's per-seed metrics (not fps, which is 1000/ms_median,
// ms_iqr, or the values computed across seeds or of the reference), and error x ms_median for the
// error metrics when the study measures time (the equal-time view: for an estimator whose error
// falls as 1/time, error x time is constant).
std::vector<std::string> paired_metrics(const Study& s);
// Each configuration against its scene's baseline: the first configuration matching s.baseline,
// or the scene's first configuration where the study names none.
PairedTable paired_vs_baseline(const Study& s, const std::vector<Row>& rows, const std::string& metric);

// The one-line conclusion of a plot, per scene: the best configuration of the plotted metric and
// whether it is resolved against the runner-up (paired 95% CI of their difference), e.g.
// "relmse, teapot: pt.spatial_neighbors=8 lowest (0.0123), resolved vs pt.spatial_neighbors=6
// (difference -0.0011, 95% CI [-0.0019, -0.0003], 8 paired seeds)". An equal-time plot (x
// ms_median, y an error metric) is judged on y x ms_median.
std::string plot_verdict(const PlotSpec& p, const std::vector<Row>& rows, int last_frame);

// "difference D, 95% CI [LO, HI], N paired seeds" (or the unpaired intervals) of a − b.
std::string comparison_text(const Comparison& c, const ConfigValues& a, const ConfigValues& b);

// "0.0123" style numbers for the report (4 significant digits).
std::string num(double v);

}  // namespace rl::study
