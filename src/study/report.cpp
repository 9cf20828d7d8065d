#include "study/report.h"

#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <fmt/format.h>

#include "core/build_info.h"
#include "image/image_io.h"
#include "study/images.h"
#include "study/paired.h"

namespace rl::study {
namespace fs = std::filesystem;

namespace {
std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '&': o += "&amp;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string fmt_stat(const Stat& st) {
  if (st.n == 0) return "–";
  if (st.n < 2 || st.stderr_ == 0) return fmt::format("{:.4g}", st.mean);  // one value, or one per configuration (noise)
  return fmt::format("{:.4g} ± {:.2g}", st.mean, st.stderr_);
}

std::string values_text(const ReportConfig& c) {
  std::string t;
  for (const auto& [k, v] : c.values) t += (t.empty() ? "" : ", ") + k + " = " + v;
  return t.empty() ? "base" : t;
}
}  // namespace

std::string machine_description() {
  std::string model;
  int logical = 0;
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0 && model.empty()) {
      auto c = line.find(':');
      if (c != std::string::npos) model = line.substr(c + 2);
    }
    if (line.rfind("processor", 0) == 0) ++logical;
  }
  if (model.empty()) model = "unknown CPU";
  utsname u{};
  std::string os = uname(&u) == 0 ? fmt::format("{} {} {}", u.sysname, u.release, u.machine) : "unknown OS";
  return fmt::format("{}; {} logical cores in /proc/cpuinfo, {} hardware threads usable; {}", model, logical,
                     std::thread::hardware_concurrency(), os);
}

std::string build_description() {
#ifdef NDEBUG
  const char* type = "optimised (NDEBUG)";
#else
  const char* type = "debug (assertions on)";
#endif
#if defined(__clang__)
  std::string compiler = "clang " __clang_version__;
#elif defined(__GNUC__)
  std::string compiler = "g++ " __VERSION__;
#else
  std::string compiler = "unknown compiler";
#endif
  return fmt::format("restir {}; {}; {}; built {} {}; FLIP metric {}", build_id(), compiler, type, __DATE__, __TIME__,
                     flip_available() ? "built in" : "not built (relative error maps instead)");
}

std::map<std::string, std::string> resolved_best(const std::vector<Row>& rows, const std::string& metric, int last_frame) {
  const std::vector<ConfigValues> cs = config_values(rows, metric, last_frame);
  const bool lower = lower_is_better(metric);
  std::map<std::string, std::vector<const ConfigValues*>> by_scene;
  for (const auto& c : cs)
    if (std::isfinite(c.mean())) by_scene[c.scene].push_back(&c);
  std::map<std::string, std::string> out;
  for (auto& [scene, v] : by_scene) {
    if (v.size() < 2) continue;  // nothing to be best against
    std::stable_sort(v.begin(), v.end(), [&](const ConfigValues* a, const ConfigValues* b) {
      return lower ? a->mean() < b->mean() : a->mean() > b->mean();
    });
    if (v[0]->mean() == v[1]->mean()) continue;  // a tie at the top, or a constant column
    if (compare(v[0]->values, v[1]->values).resolved) out[scene] = v[0]->config;
  }
  return out;
}

namespace {
// One row per (scene, configuration): each metric's mean ± standard error over seeds at the last
// frame; a scene's best value in bold only where resolved_best says so; with a study "baseline",
// each metric relative to the scene's first baseline configuration.
std::string configuration_table(const Study& s, const std::vector<Row>& rows, const std::vector<ReportConfig>& configs) {
  const auto cols = metric_columns(s);
  const bool rel = !s.baseline.empty();
  std::map<std::string, std::vector<const Row*>> by_config;
  for (const auto& r : rows)
    if (r.frame == s.frames - 1) by_config[r.config].push_back(&r);
  std::map<std::string, std::map<std::string, Stat>> stats;  // config -> column -> stat
  std::map<std::string, std::string> baseline_of;             // scene -> its baseline configuration
  std::map<std::string, std::map<std::string, std::string>> bold;  // column -> scene -> configuration
  for (const auto& col : cols) bold[col] = resolved_best(rows, col, s.frames - 1);
  for (const auto& c : configs) {
    const auto& rs = by_config[c.config];
    if (rel && !rs.empty() && rs.front()->matches(s.baseline) && !baseline_of.count(c.scene)) baseline_of[c.scene] = c.config;
    for (const auto& col : cols) {
      std::vector<double> v;
      for (const Row* r : rs) v.push_back(r->metric(col));
      stats[c.config][col] = stat_of(v);
    }
  }
  std::string h = "<h2>Configurations</h2>\n<p>Mean ± standard error over seeds at the last frame. In bold: a scene's "
                  "best value where it is resolved against the runner-up, i.e. the 95% confidence interval of their "
                  "per-seed (paired) difference excludes 0; no bold: no configuration of that scene is resolved best "
                  "(overlapping results, a constant column, or a value computed across seeds such as noise)";
  if (rel) {
    h += "; <i>÷ baseline</i>: the mean relative to the scene's baseline configuration (";
    for (const auto& [k, v] : s.baseline) h += fmt::format("<code>{}={}</code> ", esc(k), esc(v));
    h += "), below 1 = lower than the baseline";
  }
  h += ".</p>\n<table class=\"configurations\">\n<tr><th class=\"l\">scene</th><th class=\"l\">configuration</th>"
       "<th class=\"l\">id</th><th>seeds</th>";
  for (const auto& c : cols) h += "<th>" + esc(c) + "</th>" + (rel ? "<th>÷ baseline</th>" : "");
  h += "</tr>\n";
  for (const auto& c : configs) {
    const bool is_base = rel && baseline_of.count(c.scene) && baseline_of[c.scene] == c.config;
    h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}{}</td><td class=\"l\"><code>{}</code></td><td>{}</td>",
                     esc(c.scene), esc(values_text(c)), is_base ? " <b>(baseline)</b>" : "", c.config, by_config[c.config].size());
    for (const auto& col : cols) {
      const Stat& st = stats[c.config][col];
      const auto b = bold[col].find(c.scene);
      const bool top = b != bold[col].end() && b->second == c.config;
      h += std::string(top ? "<td class=\"best\">" : "<td>") + fmt_stat(st) + "</td>";
      if (!rel) continue;
      const Stat* base = baseline_of.count(c.scene) ? &stats[baseline_of[c.scene]][col] : nullptr;
      const bool ok = base && base->n > 0 && st.n > 0 && base->mean != 0 && std::isfinite(base->mean) && std::isfinite(st.mean);
      h += ok ? fmt::format("<td class=\"rel\">{:.3g}</td>", st.mean / base->mean) : std::string("<td class=\"rel\">–</td>");
    }
    h += "</tr>\n";
  }
  return h + "</table>\n";
}

// A metric of the paired tables as a heading: "relmse", or "relmse × ms_median (equal time ...)".
std::string metric_heading(const std::string& m) {
  const auto star = m.find('*');
  if (star == std::string::npos) return "<code>" + esc(m) + "</code>";
  return fmt::format("<code>{}</code> × <code>{}</code> (equal time: for an error falling as 1/time, the lower "
                     "product is the lower error at the same frame time)", esc(m.substr(0, star)), esc(m.substr(star + 1)));
}

// One table of paired_vs_baseline: each configuration against its scene's baseline.
std::string paired_table(const PairedTable& t) {
  std::string h = "<h3>" + metric_heading(t.metric) + "</h3>\n<table class=\"paired\">\n<tr><th class=\"l\">scene</th>"
                  "<th class=\"l\">configuration</th><th class=\"l\">baseline</th><th>seeds</th><th>baseline mean</th>"
                  "<th>mean difference<br>(configuration − baseline)</th><th>95% CI</th><th>mean ratio<br>"
                  "(configuration / baseline)</th><th>95% CI</th><th class=\"l\">verdict</th></tr>\n";
  for (const auto& r : t.rows) {
    const ConfigValues &c = t.configs[r.config], &b = t.configs[r.base];
    const Comparison& cmp = r.cmp;
    auto ci = [&](const Interval& i) { return cmp.paired && cmp.measured && i.n >= 2 ? fmt::format("[{}, {}]", num(i.lo()), num(i.hi())) : std::string("–"); };
    h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td>"
                     "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"l {}\">{}</td></tr>\n",
                     esc(scene_name(c.scene)), esc(c.label), esc(b.label), cmp.paired ? std::to_string(cmp.diff.n) : "unpaired",
                     num(b.mean()), num(cmp.diff.mean), ci(cmp.diff), cmp.paired ? num(cmp.ratio.mean) : "–", ci(cmp.ratio),
                     r.verdict == Verdict::NotResolved ? "unresolved" : verdict_text(r.verdict), verdict_text(r.verdict));
  }
  return h + "</table>\n";
}

// The paired analysis (paired.h): per metric, each configuration against the baseline.
std::string paired_section(const Study& s, const std::vector<Row>& rows) {
  std::string h = "<h2>Paired comparison against the baseline</h2>\n<p>Every configuration runs the same seeds, so the "
                  "per-seed difference to the baseline cancels what a seed's images and timings have in common. For each "
                  "metric at the last frame: the mean over seeds of <i>configuration − baseline</i> and of "
                  "<i>configuration / baseline</i>, each with its 95% confidence interval (Student's t over the seeds). "
                  "Verdict: <i>better</i> or <i>worse</i> where the interval of the difference excludes 0 (lower is "
                  "better for every metric here), else <i>not resolved</i>: more seeds, or no difference. Baseline: ";
  if (s.baseline.empty()) {
    h += "the study names none (\"baseline\" in the study file), so each scene's first configuration";
  } else {
    h += "each scene's first configuration with";
    for (const auto& [k, v] : s.baseline) h += fmt::format(" <code>{}={}</code>", esc(k), esc(v));
  }
  h += ". <code>scripts/study_paired.py</code> prints the same analysis from results.csv against any other key and "
       "value.</p>\n";
  bool any = false;
  for (const auto& m : paired_metrics(s)) {
    const PairedTable t = paired_vs_baseline(s, rows, m);
    if (t.rows.empty()) continue;
    h += paired_table(t);
    any = true;
  }
  if (!any) h += "<p class=\"note\">Nothing to compare: each scene has one configuration.</p>\n";
  return h;
}

// One <img> of images/NAME.png with the crop region outlined (crop_rect of the PNG's own size).
std::string framed_image(const fs::path& out, const std::string& name, const std::string& alt) {
  std::string box;
  try {
    const Image im = read_image((out / "images" / (name + ".png")).string());
    const CropRect r = crop_rect(im.width, im.height);
    auto pct = [](int a, int b) { return 100.0 * double(a) / double(std::max(b, 1)); };
    box = fmt::format("<div class=\"box\" style=\"left:{:.2f}%;top:{:.2f}%;width:{:.2f}%;height:{:.2f}%\"></div>",
                      pct(r.x0, im.width), pct(r.y0, im.height), pct(r.width, im.width), pct(r.height, im.height));
  } catch (const std::exception&) {  // unreadable PNG: the image without its box
  }
  return fmt::format("<div class=\"frame\"><img src=\"images/{}.png\" alt=\"{}\">{}</div>", name, esc(alt), box);
}

// Per scene, one table: a column per configuration (the reference first), and labelled rows of the
// full image (crop region outlined), its crop, the error map with its colour scale, and its crop.
std::string image_tables(const fs::path& out, const Study& s, const std::vector<ReportConfig>& configs) {
  auto exists = [&](const std::string& f) { return fs::exists(out / "images" / f); };
  const std::string metric = flip_available() ? "FLIP" : "relative error";
  bool any_error = false;
  for (const auto& c : configs) any_error = any_error || exists(c.config + "-error.png");
  if (any_error) write_png((out / "images" / "error-scale.png").string(), error_scale_bar(240));
  std::string h = "<h2>Images</h2>\n<p>Last frame of the first seed, tone-mapped. The cyan box marks the crop: the "
                  "centre quarter, shown 4× larger (nearest neighbour). Error maps: " + metric +
                  " against the reference, on the scale under each map (0 = identical).</p>\n";
  std::set<std::string> scenes_done;
  for (const auto& sc : s.scenes) {
    if (!scenes_done.insert(sc).second) continue;
    std::vector<const ReportConfig*> cols;
    std::string ref_name;
    for (const auto& c : configs) {
      if (c.scene != sc) continue;
      if (ref_name.empty() && c.has_reference && exists("ref-" + c.config + ".png")) ref_name = "ref-" + c.config;
      if (exists(c.config + ".png")) cols.push_back(&c);
    }
    if (cols.empty() && ref_name.empty()) continue;
    std::string head = "<tr><th></th>", full = "<tr><th class=\"l\">image</th>",
                crop = "<tr><th class=\"l\">crop<br>(centre quarter, 4×)</th>",
                err = "<tr><th class=\"l\">error map<br>(" + metric + ")</th>",
                err_crop = "<tr><th class=\"l\">error crop<br>(same scale)</th>", files = "<tr><th class=\"l\">files</th>";
    if (!ref_name.empty()) {
      head += "<th>reference</th>";
      full += "<td>" + framed_image(out, ref_name, "reference") + "</td>";
      crop += fmt::format("<td><img src=\"images/{}-crop.png\" alt=\"reference crop\"></td>", ref_name);
      err += "<td></td>";
      err_crop += "<td></td>";
      files += "<td></td>";
    }
    for (const ReportConfig* c : cols) {
      const std::string label = values_text(*c);
      head += "<th>" + esc(label) + "</th>";
      full += "<td>" + framed_image(out, c->config, label) + "</td>";
      crop += fmt::format("<td><img src=\"images/{}-crop.png\" alt=\"crop\"></td>", c->config);
      if (exists(c->config + "-error.png")) {
        err += fmt::format("<td><img src=\"images/{}-error.png\" alt=\"error map\"><img class=\"scale\" "
                           "src=\"images/error-scale.png\" alt=\"error scale: 0 (black) to 1 (white)\"></td>",
                           c->config);
        err_crop += fmt::format("<td><img src=\"images/{}-error-crop.png\" alt=\"error crop\"></td>", c->config);
      } else {
        err += "<td></td>";
        err_crop += "<td></td>";
      }
      files += fmt::format("<td><a href=\"images/{}.exr\">EXR</a></td>", c->config);
    }
    h += fmt::format("<h3>{}</h3>\n<div class=\"images\"><table class=\"images\">\n", esc(sc));
    for (const std::string* row : {&head, &full, &crop, &err, &err_crop, &files}) h += *row + "</tr>\n";
    h += "</table></div>\n";
  }
  return h;
}
}  // namespace

void write_report(const std::string& out_dir, const Study& s, const std::vector<Row>& rows,
                  const std::vector<ReportConfig>& configs, const std::vector<PlotResult>& plots, const ReportInfo& info) {
  const fs::path out(out_dir);
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += fmt::format("<title>restir study: {}</title>\n", esc(s.name));
  h += "<style>body{font-family:sans-serif;margin:1.5em;max-width:1400px}table{border-collapse:collapse;font-size:90%}"
       "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}th{background:#eee}td.l,th.l{text-align:left}"
       "div.images{overflow-x:auto}table.images td,table.images th{vertical-align:top;text-align:center;font-size:80%}"
       "table.images th{max-width:240px}table.images img{width:240px;image-rendering:pixelated;display:block}"
       "table.images img.scale{image-rendering:auto;margin-top:3px}.frame{position:relative;display:inline-block}"
       ".frame .box{position:absolute;border:1px solid #0ff;box-sizing:border-box}"
       ".plot img{max-width:900px;width:100%}.note{background:#fff7d6;padding:6px}"
       ".banner{background:#ffd7d7;border:2px solid #c00;padding:8px;font-weight:bold}td.best{font-weight:bold;background:#e3f5e3}"
       "td.rel{color:#555}p.verdict{margin:2px 0 6px;font-style:italic}td.better{color:#060;font-weight:bold}"
       "td.worse{color:#a00;font-weight:bold}td.unresolved{color:#777}</style></head><body>\n";
  std::time_t now = std::time(nullptr);
  char when[64];
  std::strftime(when, sizeof(when), "%Y-%m-%d %H:%M:%S", std::localtime(&now));
  h += fmt::format("<h1>Study <code>{}</code>{}</h1>\n", esc(s.name), info.quick ? " (quick)" : "");
  if (info.quick)
    h += "<p class=\"banner\">Smoke test (<code>--quick</code>): tiny images, few seeds and frames, a low-sample reference. "
         "It shows that the study runs, not what it finds: its numbers are not evidence. Run the study without "
         "<code>--quick</code> for the figure.</p>\n";
  h += fmt::format("<p>{}</p>\n", esc(s.description));
  h += "<h2>Run</h2><ul>\n";
  h += fmt::format("<li>study file: <code>{}</code>; written {}</li>\n", esc(s.file), when);
  h += fmt::format("<li>{} scene(s) × {} configuration(s) × {} seed(s), {} frame(s) each; {} of {} job(s) run now (the rest "
                   "resumed from results.json), {:.1f} s</li>\n",
                   s.scenes.size(), configs.size() / std::max<size_t>(1, s.scenes.size()), s.seeds.size(), s.frames,
                   info.jobs_run, info.jobs_total, info.seconds);
  if (info.stale_rows > 0)
    h += fmt::format("<li>{} stored row(s) were stale (computed from older scene files, meshes, textures or renderer "
                     "version) and were recomputed</li>\n", info.stale_rows);
  h += fmt::format("<li>references: path tracer, {} spp; {} rendered now, {} reused from <code>references/</code></li>\n",
                   s.reference.spp, info.references_rendered, info.references_reused);
  h += fmt::format("<li>machine: {}</li>\n<li>build: {}</li>\n", esc(machine_description()), esc(build_description()));
  h += fmt::format("<li>--jobs {}</li></ul>\n", info.jobs);
  if (info.jobs > 1)
    h += "<p class=\"note\">This run rendered several configurations at once (--jobs &gt; 1): they shared the CPU "
         "cores, so frame times and fps are noisier and higher than with --jobs 1. Use --jobs 1 for timing studies.</p>\n";
  h += "<p>Data: <a href=\"results.csv\">results.csv</a>, <a href=\"results.json\">results.json</a>. Metrics: "
       "<code>ms_median</code>/<code>ms_iqr</code> frame time (median, interquartile range over frames), <code>fps</code> = "
       "1000 / ms_median, <code>mse</code>, <code>relmse</code> (pbrt's relative MSE, eps 0.01) and <code>flip</code> (mean "
       "LDR-FLIP after the configuration's tone mapper) of the last frame against the reference, <code>convergence</code> = "
       "relMSE of the running mean of frames 0..f, <code>noise</code> = per-pixel standard deviation across seeds of the "
       "last frame, mean over pixels, <code>ref_relmse</code> = the reference's own relMSE, estimated from its two "
       "independent halves (a configuration's relmse is, in expectation, its own plus this). Error bars: mean ± standard "
       "error over seeds (and pooled axes).</p>\n";

  h += "<h2>Plots</h2>\n";
  for (const auto& p : plots) {
    h += fmt::format("<div class=\"plot\"><h3>{}</h3>\n", esc(p.title));
    if (p.drawn)
      h += fmt::format("<img src=\"plots/{0}.png\" alt=\"{1}\"><br>\n", esc(p.name), esc(p.title));
    else
      h += fmt::format("<p class=\"note\">not drawn: {}</p>\n", esc(p.message));
    // The plot's conclusion in words, from the same rows (paired.h): what is best, and whether resolved.
    const auto spec = std::find_if(s.plots.begin(), s.plots.end(), [&](const PlotSpec& ps) { return ps.name == p.name; });
    if (spec != s.plots.end())
      h += fmt::format("<p class=\"verdict\">{}</p>\n", esc(plot_verdict(*spec, rows, s.frames - 1)));
    h += fmt::format("<a href=\"plots/{0}.svg\">SVG</a> · <a href=\"plots/{0}.gp\">gnuplot script</a> · "
                     "<a href=\"plots/{0}.dat\">data</a></div>\n",
                     esc(p.name));
  }

  h += configuration_table(s, rows, configs);
  h += paired_section(s, rows);
  // Base options of the study (what every configuration shares).
  if (!s.base.empty()) {
    h += "<p>Base options:";
    for (const auto& [k, v] : s.base) h += fmt::format(" <code>{}={}</code>", esc(k), esc(v));
    h += fmt::format(" <code>render.frames={}</code></p>\n", s.frames);
  }

  h += image_tables(out, s, configs);
  h += "</body></html>\n";
  write_text_file_atomic((out / "report.html").string(), h);
}

}  // namespace rl::study
