#include "study/plots.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/format.h>

#include "image/image_io.h"
#include "study/paired.h"

namespace rl::study {
namespace fs = std::filesystem;

namespace {
bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == 0;
}

// A gnuplot double-quoted string; a newline becomes gnuplot's \n (a line break in a title).
std::string gp_quote(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '\n') {
      o += "\\n";
      continue;
    }
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

std::string shell_quote(const std::string& s) {
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}
}  // namespace

bool reads_option(const std::string& key, const Row& r) {
  const std::string in = r.option("integrator");
  auto prefix = [&](const char* p) { return key.rfind(p, 0) == 0; };
  if (in.empty()) return true;  // rows without an integrator column (tests, hand-made rows)
  if (prefix("pt.")) return in == "restir-pt";
  if (prefix("di.")) return in == "restir-di" || (in == "restir-pt" && r.option("pt.direct") == "restir-di");
  if (prefix("gi.")) return in == "restir-gi";
  if (prefix("ssr.")) return in == "ssr";
  if (prefix("path.")) return in != "restir-di";
  return true;
}

namespace {
bool selected(const PlotSpec& p, const Row& r) { return r.matches(p.where); }

// Each configuration's point tag on an equal-time plot: "spp=4" for the keys that tell the
// configurations apart (less the series keys, which the legend names), the scene's name first
// where the points span several scenes and the series are not the scenes.
std::map<std::string, std::string> point_tags(const std::map<std::string, std::vector<const Row*>>& rows_of,
                                              const std::string& series_key) {
  std::vector<std::vector<const Row*>> groups;
  std::set<std::string> scenes;
  for (const auto& [config, rs] : rows_of) groups.push_back(rs), scenes.insert(rs.front()->scene);
  const auto series_keys = split_keys(series_key);
  std::vector<std::string> keys;
  for (const auto& k : distinguishing_keys(groups))
    if (std::find(series_keys.begin(), series_keys.end(), k) == series_keys.end()) keys.push_back(k);
  const bool name_scene = scenes.size() > 1 && std::find(series_keys.begin(), series_keys.end(), "scene") == series_keys.end();
  std::map<std::string, std::string> tags;
  for (const auto& [config, rs] : rows_of) {
    std::string tag = name_scene ? scene_name(rs.front()->scene) : "";
    for (const auto& k : keys)
      if (reads_option(k, *rs.front()))
        tag += (tag.empty() ? "" : " ") + k.substr(k.rfind('.') + 1) + "=" + rs.front()->option(k);
    tags[config] = tag;
  }
  return tags;
}

// x is a metric: one point per configuration (and scene) of each series, at the means over its
// seeds, the points of a series in order of x.
std::vector<PlotSeries> aggregate_metric_x(const PlotSpec& p, const std::vector<Row>& rows,
                                           const std::vector<std::pair<std::string, std::string>>& baseline) {
  std::vector<std::string> series_order;
  std::map<std::string, std::string> labels;
  std::map<std::string, std::map<std::string, std::pair<std::vector<double>, std::vector<double>>>> groups;
  std::map<std::string, std::vector<const Row*>> rows_of;  // config|scene -> its rows
  for (const auto& r : rows) {
    const double x = r.metric(p.x), y = r.metric(p.y);
    if (!selected(p, r) || !std::isfinite(x) || !std::isfinite(y)) continue;
    const std::string sv = p.series.empty() ? "" : r.option(p.series);
    if (!groups.count(sv)) series_order.push_back(sv), labels[sv] = p.series.empty() ? axis_label(p.y) : series_label(p.series, r, baseline);
    auto& g = groups[sv][r.config + "|" + r.scene];
    g.first.push_back(x);
    g.second.push_back(y);
    rows_of[r.config + "|" + r.scene].push_back(&r);
  }
  const std::map<std::string, std::string> tags = point_tags(rows_of, p.series);
  std::vector<PlotSeries> out;
  for (const auto& sv : series_order) {
    PlotSeries s;
    s.label = labels[sv];
    for (const auto& [config, xy] : groups[sv]) {
      PlotSeries::Point pt;
      pt.xpos = stat_of(xy.first).mean;
      pt.x = fmt::format("{:.4g}", pt.xpos);
      pt.y = stat_of(xy.second);
      pt.tag = tags.at(config);
      s.points.push_back(pt);
    }
    std::sort(s.points.begin(), s.points.end(), [](const auto& a, const auto& b) { return a.xpos < b.xpos; });
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

std::string scene_name(const std::string& scene) {
  const fs::path p(scene);
  // The shared scenes are folders of scene-v4.pbrt: name them by the folder.
  return p.stem() == "scene-v4" || p.stem() == "scene" ? p.parent_path().filename().string() : p.stem().string();
}

std::string series_label(const std::string& series_key, const Row& r,
                         const std::vector<std::pair<std::string, std::string>>& baseline) {
  std::string label;
  for (const auto& k : split_keys(series_key)) {
    if (!reads_option(k, r)) continue;
    std::string v = k == "scene" ? scene_name(r.scene) : r.option(k);
    // max_history 0 means "no cap" (options.h); a legend saying "0" reads as a cap of zero.
    if (v == "0" && k.size() > 12 && k.compare(k.size() - 12, 12, ".max_history") == 0) v = "no cap";
    label += (label.empty() ? "" : " ") + v;
  }
  if (!baseline.empty() && r.matches(baseline)) label += " (baseline)";
  return label;
}

void shorten_labels(std::vector<PlotSeries>& series, const std::string& series_key) {
  const auto keys = split_keys(series_key);
  if (keys.size() < 2 || keys.front() != "integrator") return;
  std::vector<std::string> shorter;
  for (const auto& s : series) {
    const size_t sp = s.label.find(' ');
    const bool more = sp != std::string::npos && s.label.compare(sp, 11, " (baseline)") != 0;
    shorter.push_back(more ? s.label.substr(sp + 1) : s.label);
  }
  std::set<std::string> distinct(shorter.begin(), shorter.end());
  if (distinct.size() != shorter.size()) return;
  for (size_t i = 0; i < series.size(); ++i) series[i].label = shorter[i];
}

std::string axis_label(const std::string& name) {
  static const std::map<std::string, std::string> labels = {
      {"ms_median", "frame time (ms, median over frames)"},
      {"ms_iqr", "frame time spread (ms, interquartile range over frames)"},
      {"fps", "frames per second (1000 / median ms)"},
      {"mse", "MSE of the last frame"},
      {"relmse", "relMSE of the last frame"},
      {"flip", "mean FLIP of the last frame"},
      {"noise", "noise (per-pixel std. dev. across seeds, mean)"},
      {"convergence", "relMSE of the running mean of frames"},
      {"relmse_reflective", "relMSE over the reflective pixels"},
      {"flip_reflective", "mean FLIP over the reflective pixels"},
      {"scene", "scene"},
      {"frame", "frame"},
      {"seed", "seed"}};
  auto it = labels.find(name);
  return it == labels.end() ? name : it->second;
}

std::vector<PlotSeries> aggregate(const PlotSpec& p, const std::vector<Row>& rows, bool* numeric_x,
                                  const std::vector<std::pair<std::string, std::string>>& baseline) {
  if (p.x_metric) {
    if (numeric_x) *numeric_x = true;
    auto out = aggregate_metric_x(p, rows, baseline);
    shorten_labels(out, p.series);
    return out;
  }
  // Group in first-seen order of series and x.
  std::vector<std::string> series_order, x_order;
  std::map<std::string, std::string> labels;
  std::map<std::string, std::map<std::string, std::vector<double>>> groups;
  for (const auto& r : rows) {
    if (!selected(p, r)) continue;
    double y = r.metric(p.y);
    if (!std::isfinite(y)) continue;
    std::string sv = p.series.empty() ? "" : r.option(p.series);
    std::string xv = r.option(p.x);
    if (!groups.count(sv)) series_order.push_back(sv), labels[sv] = p.series.empty() ? axis_label(p.y) : series_label(p.series, r, baseline);
    if (std::find(x_order.begin(), x_order.end(), xv) == x_order.end()) x_order.push_back(xv);
    groups[sv][xv].push_back(y);
  }
  bool numeric = !x_order.empty();
  for (const auto& x : x_order) {
    double v;
    numeric = numeric && parse_number(x, v);
  }
  if (numeric)
    std::stable_sort(x_order.begin(), x_order.end(), [](const std::string& a, const std::string& b) {
      return std::strtod(a.c_str(), nullptr) < std::strtod(b.c_str(), nullptr);
    });
  if (numeric_x) *numeric_x = numeric;
  std::vector<PlotSeries> out;
  // Categories: series side by side around each category, 0.6 of the gap between categories in all.
  const double n = double(series_order.size()), width = n > 1 ? std::min(0.6 / n, 0.15) : 0;
  for (size_t si = 0; si < series_order.size(); ++si) {
    const auto& sv = series_order[si];
    PlotSeries s;
    s.label = labels[sv];
    for (size_t i = 0; i < x_order.size(); ++i) {
      auto it = groups[sv].find(x_order[i]);
      if (it == groups[sv].end()) continue;
      PlotSeries::Point pt;
      pt.x = p.x == "scene" ? scene_name(x_order[i]) : x_order[i];
      pt.xpos = numeric ? std::strtod(pt.x.c_str(), nullptr) : double(i) + (double(si) - (n - 1) / 2) * width;
      pt.y = stat_of(it->second);
      s.points.push_back(pt);
    }
    out.push_back(std::move(s));
  }
  shorten_labels(out, p.series);
  return out;
}

namespace {
// Long titles on two lines (gnuplot cuts a long one at the image's edges).
std::string wrap_title(const std::string& t) {
  if (t.size() <= 90) return t;
  size_t cut = t.rfind(' ', t.size() / 2 + 10);
  if (cut == std::string::npos || cut < 20) cut = t.find(' ', t.size() / 2);
  return cut == std::string::npos ? t : t.substr(0, cut) + "\n" + t.substr(cut + 1);
}

// Category names at their integer positions (the series sit at offsets around them).
std::string category_tics(const std::vector<PlotSeries>& series) {
  std::map<long, std::string> names;
  for (const auto& s : series)
    for (const auto& pt : s.points) names.emplace(std::lround(pt.xpos), pt.x);
  std::string tics = "set xtics (";
  for (const auto& [i, name] : names) tics += fmt::format("{}{} {}", i == names.begin()->first ? "" : ", ", gp_quote(name), i);
  return tics + ")" + (names.size() > 4 ? " rotate by -30" : "") + "\nset xrange [-0.6:" + std::to_string(names.empty() ? 1 : names.rbegin()->first) + ".6]\n";
}
}  // namespace

AxisFit fit_axis(const std::vector<double>& values, bool want_log, double pad) {
  AxisFit f;
  std::vector<double> all, pos;
  for (double v : values)
    if (std::isfinite(v)) {
      all.push_back(v);
      if (v > 0) pos.push_back(v);
    }
  if (all.empty()) return f;
  f.valid = true;
  if (want_log && !pos.empty()) {
    const auto [lo, hi] = std::minmax_element(pos.begin(), pos.end());
    if (*hi > 10 * *lo) {  // more than a decade: a log axis shows the data, not blank decades
      const double a = std::log10(*lo), b = std::log10(*hi), d = pad * (b - a);
      f.log = true, f.min = std::pow(10.0, a - d), f.max = std::pow(10.0, b + d);
      return f;
    }
  }
  const auto [lo, hi] = std::minmax_element(all.begin(), all.end());
  const double span = *hi - *lo, d = span > 0 ? pad * span : (*hi != 0 ? pad * std::fabs(*hi) : 1.0);
  // Positive data (errors, times) gets no negative axis; data at 0 keeps its margin, off the frame.
  f.min = *lo > 0 ? std::max(*lo - d, 0.0) : *lo - d;
  f.max = *hi + d;
  return f;
}

std::string axis_commands(const std::string& axis, const AxisFit& f) {
  if (!f.valid) return "";
  return (f.log ? "set logscale " + axis + "\n" : std::string()) + fmt::format("set {}range [{:.6g}:{:.6g}]\n", axis, f.min, f.max);
}

std::string legend_title(const std::string& series_key) {
  std::string t;
  for (const auto& k : split_keys(series_key)) t += (t.empty() ? "" : " + ") + k;
  return t;
}

namespace {
// NAME.dat: one block per series (gnuplot "index"), tab separated; a sixth column, the point's tag.
std::string plot_data(const Study& s, const PlotSpec& p, const std::vector<PlotSeries>& series) {
  std::string dat = fmt::format("# study {}: {} over {}; mean and standard error over the pooled rows\n", s.name, p.y, p.x);
  dat += "# x\tlabel\tmean\tstderr\tn\ttag\n";
  for (const auto& ser : series) {
    dat += "# " + ser.label + "\n";
    for (const auto& pt : ser.points)
      dat += fmt::format("{:.9g}\t{}\t{:.9g}\t{:.9g}\t{}\t{}\n", pt.xpos, pt.x, pt.y.mean, pt.y.stderr_, pt.y.n, pt.tag);
    dat += "\n\n";
  }
  return dat;
}

// The axes fitted to what is drawn: error-bar ends on y, point positions on a numeric x (a
// categorical x has its own range, category_tics). Equal-time plots get more room on the right
// for the point tags.
std::string fitted_axes(const PlotSpec& p, const std::vector<PlotSeries>& series, bool numeric) {
  std::vector<double> xs, ys;
  for (const auto& ser : series)
    for (const auto& pt : ser.points) {
      xs.push_back(pt.xpos);
      ys.insert(ys.end(), {pt.y.mean, pt.y.mean - pt.y.stderr_, pt.y.mean + pt.y.stderr_});
    }
  // A point at x <= 0 has no place on a log axis: gnuplot would drop it silently.
  const bool logx = p.logx && std::all_of(xs.begin(), xs.end(), [](double x) { return x > 0; });
  return (numeric ? axis_commands("x", fit_axis(xs, logx, p.x_metric ? 0.12 : 0.05)) : category_tics(series)) +
         axis_commands("y", fit_axis(ys, p.logy));
}

// The plot command: each series with its error bars; on an equal-time plot, each point's tag
// beside it in its series' colour (explicit line types, so that the tags do not shift the colours).
// gnuplot has 8 line colours and repeats them: each further group of 8 series gets its own dash
// pattern and point shape, so that series 9 is not drawn like series 1.
std::string plot_command(const PlotSpec& p, const std::vector<PlotSeries>& series, bool numeric) {
  std::string cmd = "plot ", tags;
  constexpr int kPointTypes[] = {7, 5, 9, 11};  // filled circle, square, triangle up, triangle down
  for (size_t i = 0; i < series.size(); ++i) {
    const size_t group = i / 8;
    cmd += fmt::format("{}{} index {} using 1:3:4 with {} lt {} dt {} lw 2 pt {} title {}", i ? ", \\\n     " : "",
                       i == 0 ? gp_quote(p.name + ".dat") : std::string("\"\""), i, numeric ? "yerrorlines" : "yerrorbars",
                       i + 1, group + 1, kPointTypes[group % 4], gp_quote(series[i].label));
    const bool tagged = std::any_of(series[i].points.begin(), series[i].points.end(), [](const auto& pt) { return !pt.tag.empty(); });
    if (p.x_metric && tagged)
      tags += fmt::format(", \\\n     \"\" index {} using 1:3:6 with labels left offset char 0.7,0.6 tc lt {} notitle", i, i + 1);
  }
  return cmd + tags;
}
}  // namespace

std::vector<PlotResult> write_plots(const Study& s, const std::vector<Row>& rows, const std::string& plot_dir, bool quick) {
  std::vector<PlotResult> results;
  fs::create_directories(plot_dir);
  const bool have_gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  for (const auto& p : s.plots) {
    PlotResult pr;
    pr.name = p.name;
    pr.title = p.title;
    bool numeric = true;
    auto series = aggregate(p, rows, &numeric, s.baseline);
    write_text_file_atomic((fs::path(plot_dir) / (p.name + ".dat")).string(), plot_data(s, p, series));
    const bool any = std::any_of(series.begin(), series.end(), [](const auto& ser) { return !ser.points.empty(); });

    // A --quick run says so on every plot: its numbers are a smoke test, not evidence.
    const std::string title = (quick ? "[--quick smoke test: not evidence] " : "") + wrap_title(p.title);
    std::string y_label = axis_label(p.y);  // over frames, a metric is each frame's, not the last one's
    if (const size_t at = y_label.find(" of the last frame"); p.x == "frame" && at != std::string::npos)
      y_label.replace(at, 18, " of each frame");
    std::string gp = fmt::format(
        "# Drawn by `restir study` ({}); edit and re-run here with: gnuplot {}.gp\n"
        "set encoding utf8\nset datafile separator \"\\t\"\n"
        "set title {}\nset xlabel {}\nset ylabel {}\n"
        "set grid\nset key outside right top\nset bars small\nset offsets graph 0.04, graph 0.04, graph 0.02, graph 0.02\n",
        s.name, p.name, gp_quote(title), gp_quote(axis_label(p.x) + (p.x_metric ? ", mean over seeds" : "")),
        gp_quote(y_label + " (mean ± s.e. over seeds)"));
    // A legend of bare values ("1", "3") says nothing without the key they are values of.
    if (!p.series.empty()) gp += "set key title " + gp_quote(legend_title(p.series)) + "\n";
    gp += fitted_axes(p, series, numeric);
    std::string plot_cmd = plot_command(p, series, numeric);
    if (series.empty() || !any) plot_cmd = "set label 1 \"no data\" at graph 0.5, graph 0.5 center\nplot [0:1][0:1] NaN notitle";
    gp += fmt::format(
        "set terminal pngcairo size 900,540 noenhanced font \"sans,10\"\nset output {}\n{}\n"
        "set terminal svg size 900,540 noenhanced dynamic font \"sans,10\"\nset output {}\nreplot\nunset output\n",
        gp_quote(p.name + ".png"), plot_cmd, gp_quote(p.name + ".svg"));
    const std::string gp_path = (fs::path(plot_dir) / (p.name + ".gp")).string();
    write_text_file_atomic(gp_path, gp);
    if (!have_gnuplot) {
      pr.message = "gnuplot not found (install gnuplot-nox; then run the .gp script in plots/)";
    } else {
      for (const char* ext : {".png", ".svg"}) fs::remove(fs::path(plot_dir) / (p.name + ext));
      std::string cmd = "cd " + shell_quote(plot_dir) + " && gnuplot " + shell_quote(p.name + ".gp") + " 2>" +
                        shell_quote(p.name + ".log");
      int st = std::system(cmd.c_str());
      auto nonempty = [&](const char* ext) {
        fs::path f = fs::path(plot_dir) / (p.name + ext);
        return fs::exists(f) && fs::file_size(f) > 0;
      };
      pr.drawn = st == 0 && nonempty(".png") && nonempty(".svg");
      if (!pr.drawn) pr.message = "gnuplot failed, see plots/" + p.name + ".log";
      else fs::remove(fs::path(plot_dir) / (p.name + ".log"));
    }
    results.push_back(pr);
  }
  return results;
}

}  // namespace rl::study
