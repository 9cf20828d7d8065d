#include "study/paired.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "study/plots.h"

namespace rl::study {

double t975(int dof) {
  // Exact to 4 decimals up to 30 degrees of freedom (studies run 2 to ~16 seeds); beyond, the
  // Cornish-Fisher expansion around the normal quantile, within 1e-5 there.
  static const double table[] = {12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281,
                                 2.2010,  2.1788, 2.1604, 2.1448, 2.1314, 2.1199, 2.1098, 2.1009, 2.0930, 2.0860,
                                 2.0796,  2.0739, 2.0687, 2.0639, 2.0595, 2.0555, 2.0518, 2.0484, 2.0452, 2.0423};
  dof = std::max(dof, 1);
  if (dof <= 30) return table[dof - 1];
  const double z = 1.959963985, n = dof;
  const double g1 = (z * z * z + z) / 4, g2 = (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / 96,
               g3 = (3 * std::pow(z, 7) + 19 * std::pow(z, 5) + 17 * z * z * z - 15 * z) / 384;
  return z + g1 / n + g2 / (n * n) + g3 / (n * n * n);
}

Interval mean_ci(const std::vector<double>& v) {
  const Stat st = stat_of(v);
  Interval i;
  i.mean = st.mean;
  i.n = st.n;
  if (st.n >= 2) i.half = t975(st.n - 1) * st.stderr_;  // stderr_ = sd / sqrt(n)
  return i;
}

bool lower_is_better(const std::string& metric) { return metric != "fps"; }

namespace {
bool spread(const SeedValues& v) {
  if (v.empty()) return false;
  const double first = v.begin()->second;
  return std::any_of(v.begin(), v.end(), [&](const auto& kv) { return kv.second != first; });
}
std::vector<double> values_of(const SeedValues& v) {
  std::vector<double> out;
  for (const auto& [seed, x] : v) out.push_back(x);
  return out;
}
}  // namespace

Comparison compare(const SeedValues& a, const SeedValues& b) {
  Comparison c;
  // Both constant over seeds: a value computed across seeds (noise), or one seed repeated; its
  // difference has no error estimate, however consistent it looks.
  const bool measured = c.measured = spread(a) || spread(b);
  std::vector<double> d, r;
  for (const auto& [seed, x] : a) {
    auto it = b.find(seed);
    if (it == b.end()) continue;
    d.push_back(x - it->second);
    if (it->second != 0) r.push_back(x / it->second);
  }
  if (d.size() >= 2) {
    c.paired = true;
    c.diff = mean_ci(d);
    c.ratio = mean_ci(r);
    c.resolved = measured && c.diff.excludes(0);
    return c;
  }
  const Interval ia = mean_ci(values_of(a)), ib = mean_ci(values_of(b));
  c.diff.mean = ia.mean - ib.mean;
  c.resolved = measured && ia.n >= 2 && ib.n >= 2 && std::isfinite(ia.half) && std::isfinite(ib.half) &&
               (ia.lo() > ib.hi() || ia.hi() < ib.lo());
  return c;
}

double ConfigValues::mean() const { return stat_of(values_of(values)).mean; }

namespace {
double metric_value(const Row& r, const std::string& metric) {
  if (auto star = metric.find('*'); star != std::string::npos)
    return r.metric(metric.substr(0, star)) * r.metric(metric.substr(star + 1));
  return r.metric(metric);
}
}  // namespace

std::vector<std::string> distinguishing_keys(const std::vector<std::vector<const Row*>>& groups) {
  std::vector<std::string> keys;
  if (groups.empty()) return keys;
  for (const auto& [k, v0] : groups.front().front()->options) {
    std::set<std::string> across;
    bool per_config = true;
    for (const auto& g : groups) {
      const std::string v = g.front()->option(k);
      per_config = per_config && std::all_of(g.begin(), g.end(), [&](const Row* r) { return r->option(k) == v; });
      across.insert(v);
    }
    if (per_config && across.size() > 1) keys.push_back(k);
  }
  return keys;
}

std::vector<ConfigValues> config_values(const std::vector<Row>& rows, const std::string& metric, int last_frame,
                                        const std::vector<std::pair<std::string, std::string>>& where) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const Row*>> groups;
  for (const auto& r : rows) {
    if (r.frame != last_frame || !r.matches(where)) continue;
    const std::string key = r.scene + "\n" + r.config;
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&r);
  }
  std::vector<std::vector<const Row*>> ordered;
  for (const auto& k : order) ordered.push_back(groups[k]);
  const std::vector<std::string> keys = distinguishing_keys(ordered);
  std::vector<ConfigValues> out;
  for (const auto& g : ordered) {
    ConfigValues c;
    c.scene = g.front()->scene;
    c.config = g.front()->config;
    c.first = *g.front();
    for (const auto& k : keys)
      if (reads_option(k, *g.front())) c.label += (c.label.empty() ? "" : ", ") + k + "=" + g.front()->option(k);
    if (c.label.empty()) c.label = keys.empty() ? "the configuration" : "base";
    for (const Row* r : g)
      if (const double v = metric_value(*r, metric); std::isfinite(v)) c.values[r->seed] = v;
    if (!c.values.empty()) out.push_back(std::move(c));
  }
  return out;
}

const char* verdict_text(Verdict v) {
  switch (v) {
    case Verdict::Better: return "better";
    case Verdict::Worse: return "worse";
    default: return "not resolved";
  }
}

std::vector<std::string> paired_metrics(const Study& s) {
  std::vector<std::string> out;
  for (const auto& c : metric_columns(s))
    if (c != "fps" && c != "ms_iqr" && c != "noise" && c != "ref_relmse") out.push_back(c);
  if (s.has_metric("time"))
    for (const char* e : {"mse", "relmse", "flip", "relmse_reflective", "flip_reflective"})
      if (s.has_metric(e)) out.push_back(std::string(e) + "*ms_median");
  return out;
}

PairedTable paired_vs_baseline(const Study& s, const std::vector<Row>& rows, const std::string& metric) {
  PairedTable t;
  t.metric = metric;
  t.configs = config_values(rows, metric, s.frames - 1);
  std::map<std::string, size_t> base_of;  // scene -> its baseline configuration
  for (size_t i = 0; i < t.configs.size(); ++i)
    if (!base_of.count(t.configs[i].scene) && (s.baseline.empty() || t.configs[i].first.matches(s.baseline)))
      base_of[t.configs[i].scene] = i;
  for (size_t i = 0; i < t.configs.size(); ++i) {
    auto b = base_of.find(t.configs[i].scene);
    if (b == base_of.end() || b->second == i) continue;
    PairedRow pr;
    pr.config = i;
    pr.base = b->second;
    pr.cmp = compare(t.configs[i].values, t.configs[b->second].values);
    if (pr.cmp.resolved) {
      const bool lower = pr.cmp.diff.mean < 0;
      pr.verdict = lower == lower_is_better(metric) ? Verdict::Better : Verdict::Worse;
    }
    t.rows.push_back(pr);
  }
  return t;
}

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : std::string("–"); }

std::string comparison_text(const Comparison& c, const ConfigValues& a, const ConfigValues& b) {
  if (!c.measured)  // a zero-width "interval" would read as certainty
    return fmt::format("difference {}; one value per configuration (computed across seeds): no confidence interval",
                       num(c.diff.mean));
  if (c.paired)
    return fmt::format("difference {}, 95% CI [{}, {}], {} paired seeds", num(c.diff.mean), num(c.diff.lo()),
                       num(c.diff.hi()), c.diff.n);
  const Interval ia = mean_ci(values_of(a.values)), ib = mean_ci(values_of(b.values));
  return fmt::format("difference {}; unpaired, 95% CIs [{}, {}] and [{}, {}]", num(c.diff.mean), num(ia.lo()),
                     num(ia.hi()), num(ib.lo()), num(ib.hi()));
}

namespace {
// One scene's clause of a plot verdict.
std::string scene_verdict(std::vector<const ConfigValues*> cs, const std::string& metric) {
  if (cs.size() < 2) return "one configuration, nothing to compare";
  const bool lower = lower_is_better(metric);
  std::stable_sort(cs.begin(), cs.end(), [&](const ConfigValues* a, const ConfigValues* b) {
    return lower ? a->mean() < b->mean() : a->mean() > b->mean();
  });
  const ConfigValues &best = *cs[0], &next = *cs[1];
  const Comparison c = compare(best.values, next.values);
  const std::string what = fmt::format("{} {} ({})", best.label, lower ? "lowest" : "highest", num(best.mean()));
  const std::string vs = fmt::format("{} ({}; {})", next.label, num(next.mean()), comparison_text(c, best, next));
  return c.resolved ? what + ", resolved vs " + vs : "no resolved difference: " + what + " vs " + vs;
}
}  // namespace

std::string plot_verdict(const PlotSpec& p, const std::vector<Row>& rows, int last_frame) {
  static const std::set<std::string> errors = {"mse", "relmse", "flip", "convergence", "relmse_reflective", "flip_reflective"};
  // Equal time: at the same frame time, the lower error x time wins (error ~ 1/time).
  const std::string metric = p.x_metric && p.x == "ms_median" && errors.count(p.y) ? p.y + "*ms_median" : p.y;
  const std::vector<ConfigValues> cs = config_values(rows, metric, last_frame, p.where);
  if (cs.empty()) return metric + ": no data";
  std::vector<std::string> scenes;
  for (const auto& c : cs)
    if (std::find(scenes.begin(), scenes.end(), c.scene) == scenes.end()) scenes.push_back(c.scene);
  std::string line = metric + (metric != p.y ? " (equal time: " + p.y + " x frame time)" : "") + ": ";
  for (size_t i = 0; i < scenes.size(); ++i) {
    std::vector<const ConfigValues*> of_scene;
    for (const auto& c : cs)
      if (c.scene == scenes[i]) of_scene.push_back(&c);
    line += (i ? "; " : "") + (scenes.size() > 1 ? scene_name(scenes[i]) + ": " : std::string()) +
            scene_verdict(of_scene, metric);
  }
  return line;
}

}  // namespace rl::study
