#include "study/plots.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "image/image_io.h"

namespace rl::study {
namespace fs = std::filesystem;

namespace {
bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == 0;
}

std::string gp_quote(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
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

namespace {
bool selected(const PlotSpec& p, const Row& r) {
  return std::all_of(p.where.begin(), p.where.end(), [&](const auto& kv) { return r.option(kv.first) == kv.second; });
}

// x is a metric: one point per configuration (and scene) of each series, at the means over its
// seeds, the points of a series in order of x.
std::vector<PlotSeries> aggregate_metric_x(const PlotSpec& p, const std::vector<Row>& rows) {
  std::vector<std::string> series_order;
  std::map<std::string, std::map<std::string, std::pair<std::vector<double>, std::vector<double>>>> groups;
  for (const auto& r : rows) {
    const double x = r.metric(p.x), y = r.metric(p.y);
    if (!selected(p, r) || !std::isfinite(x) || !std::isfinite(y)) continue;
    const std::string sv = p.series.empty() ? "" : r.option(p.series);
    if (!groups.count(sv)) series_order.push_back(sv);
    auto& g = groups[sv][r.config + "|" + r.scene];
    g.first.push_back(x);
    g.second.push_back(y);
  }
  std::vector<PlotSeries> out;
  for (const auto& sv : series_order) {
    PlotSeries s;
    s.label = p.series.empty() ? p.y : p.series + " = " + sv;
    for (const auto& [config, xy] : groups[sv]) {
      PlotSeries::Point pt;
      pt.xpos = stat_of(xy.first).mean;
      pt.x = fmt::format("{:.4g}", pt.xpos);
      pt.y = stat_of(xy.second);
      s.points.push_back(pt);
    }
    std::sort(s.points.begin(), s.points.end(), [](const auto& a, const auto& b) { return a.xpos < b.xpos; });
    out.push_back(std::move(s));
  }
  return out;
}
}  // namespace

std::vector<PlotSeries> aggregate(const PlotSpec& p, const std::vector<Row>& rows, bool* numeric_x) {
  if (p.x_metric) {
    if (numeric_x) *numeric_x = true;
    return aggregate_metric_x(p, rows);
  }
  // Group in first-seen order of series and x.
  std::vector<std::string> series_order, x_order;
  std::map<std::string, std::map<std::string, std::vector<double>>> groups;
  for (const auto& r : rows) {
    if (!selected(p, r)) continue;
    double y = r.metric(p.y);
    if (!std::isfinite(y)) continue;
    std::string sv = p.series.empty() ? "" : r.option(p.series);
    std::string xv = r.option(p.x);
    if (!groups.count(sv)) series_order.push_back(sv);
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
  for (const auto& sv : series_order) {
    PlotSeries s;
    s.label = p.series.empty() ? p.y : p.series + " = " + sv;
    for (size_t i = 0; i < x_order.size(); ++i) {
      auto it = groups[sv].find(x_order[i]);
      if (it == groups[sv].end()) continue;
      PlotSeries::Point pt;
      pt.x = x_order[i];
      pt.xpos = numeric ? std::strtod(pt.x.c_str(), nullptr) : double(i);
      pt.y = stat_of(it->second);
      s.points.push_back(pt);
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<PlotResult> write_plots(const Study& s, const std::vector<Row>& rows, const std::string& plot_dir) {
  std::vector<PlotResult> results;
  fs::create_directories(plot_dir);
  const bool have_gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  for (const auto& p : s.plots) {
    PlotResult pr;
    pr.name = p.name;
    pr.title = p.title;
    bool numeric = true;
    auto series = aggregate(p, rows, &numeric);
    // Data: one block per series (gnuplot "index"), tab separated.
    std::string dat = fmt::format("# study {}: {} over {}; mean and standard error over the pooled rows\n", s.name, p.y, p.x);
    dat += "# x\tlabel\tmean\tstderr\tn\n";
    bool any = false;
    for (const auto& ser : series) {
      dat += "# " + ser.label + "\n";
      for (const auto& pt : ser.points) {
        dat += fmt::format("{:.9g}\t{}\t{:.9g}\t{:.9g}\t{}\n", pt.xpos, pt.x, pt.y.mean, pt.y.stderr_, pt.y.n);
        any = true;
      }
      dat += "\n\n";
    }
    write_text_file_atomic((fs::path(plot_dir) / (p.name + ".dat")).string(), dat);

    std::string gp = fmt::format(
        "# Drawn by `restir study` ({}); edit and re-run here with: gnuplot {}.gp\n"
        "set encoding utf8\nset datafile separator \"\\t\"\n"
        "set title {}\nset xlabel {}\nset ylabel {}\n"
        "set grid\nset key outside right top\nset bars small\nset offsets graph 0.04, graph 0.04, graph 0.02, graph 0.02\n",
        s.name, p.name, gp_quote(p.title), gp_quote(p.x_metric ? p.x + " (mean over seeds)" : p.x), gp_quote(p.y + " (mean ± standard error)"));
    if (p.logx) gp += "set logscale x\n";
    if (p.logy) gp += "set logscale y\n";
    if (!numeric) gp += "set xtics rotate by -30\n";
    std::string plot_cmd = "plot ";
    for (size_t i = 0; i < series.size(); ++i) {
      if (i) plot_cmd += ", \\\n     ";
      plot_cmd += fmt::format("{} index {} using 1:3:4{} with {} lw 2 pt 7 title {}",
                              i == 0 ? gp_quote(p.name + ".dat") : std::string("\"\""), i, numeric ? "" : ":xticlabels(2)",
                              numeric ? "yerrorlines" : "yerrorbars",
                              gp_quote(series[i].label));
    }
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
