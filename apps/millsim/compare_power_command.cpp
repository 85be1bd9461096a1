// `millsim compare-power`: reads each run's OUT/power.csv (one row per speed level), reports its
// curve, whether it rises monotonically, and the squared differences to a measured curve; plots
// all of them in one PNG.
#include "compare_power_command.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "csv_table.hpp"
#include "millsim/core/error.hpp"
#include "millsim/io/plot_png.hpp"

namespace millsim::cli {

namespace {

struct Level {
  double rpm = 0, net_power_W = 0;
  bool steady = false;
};

std::vector<Level> readPowerCsv(const std::string& dir) {
  const CsvTable t = readCsvTable(dir + "/power.csv", "not the output directory of a stirred-mill run?");
  const std::string what = "not a stirred mill's power.csv";
  const std::size_t c_rpm = t.column("rpm", what), c_p = t.column("net_power_W", what), c_s = t.column("steady", what);
  std::vector<Level> out;
  for (std::size_t r = 0; r < t.cells.size(); ++r)
    out.push_back({t.number(r, c_rpm), t.number(r, c_p), t.number(r, c_s) != 0});
  if (out.empty())
    throw core::InputError(t.path + ": no speed level closed (did the run end before the first window?)");
  std::stable_sort(out.begin(), out.end(), [](const Level& a, const Level& b) { return a.rpm < b.rpm; });
  return out;
}

std::vector<Level> readMeasured(const std::string& path) {
  const CsvTable t = readCsvTable(path, "");
  const std::string what = "expected columns rpm,power_W: the measured net power";
  const std::size_t c_rpm = t.column("rpm", what), c_p = t.column("power_W", what);
  std::vector<Level> out;
  for (std::size_t r = 0; r < t.cells.size(); ++r) {
    const double rpm = t.number(r, c_rpm);
    if (!(rpm > 0)) throw core::InputError(path, t.lines[r], "'rpm' must be > 0");
    out.push_back({rpm, t.number(r, c_p), true});
  }
  if (out.empty()) throw core::InputError(path, 2, "no data rows");
  return out;
}

}  // namespace

CLI::App* addComparePowerCommand(CLI::App& app, ComparePowerArgs& a) {
  auto* c = app.add_subcommand("compare-power",
                               "Net power against stirrer speed of stirred-mill runs (their OUT dirs) side by side: "
                               "monotone or not, squared differences to a measured curve, one PNG");
  c->add_option("dirs", a.dirs, "Output directories of stirred-mill runs (each holds power.csv)")->required();
  c->add_option("--labels", a.labels, "Legend label of each run")->delimiter(',');
  c->add_option("--measured", a.measured, "Measured net power: CSV with columns rpm,power_W")->check(CLI::ExistingFile);
  c->add_option("--png", a.png, "Write the plot of net power against speed here");
  return c;
}

int comparePowerCommand(const ComparePowerArgs& a) {
  const std::vector<Level> measured = a.measured.empty() ? std::vector<Level>{} : readMeasured(a.measured);
  std::vector<io::PlotSeries> series;
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < a.dirs.size(); ++k) {
    const std::vector<Level> levels = readPowerCsv(a.dirs[k]);
    nlohmann::ordered_json j, lv = nlohmann::ordered_json::array();
    j["run"] = a.dirs[k];
    if (k < a.labels.size()) j["label"] = a.labels[k];
    // Monotone: every level draws more than the slower one before it (the seed's curves do).
    bool monotone = true;
    nlohmann::ordered_json drops = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < levels.size(); ++i) {
      lv.push_back({{"rpm", levels[i].rpm}, {"net_power_W", levels[i].net_power_W}, {"steady", levels[i].steady}});
      if (i > 0 && levels[i].net_power_W <= levels[i - 1].net_power_W) {
        monotone = false;
        drops.push_back({levels[i - 1].rpm, levels[i].rpm});
      }
    }
    j["levels"] = lv;
    j["monotone"] = monotone;
    j["drops_rpm"] = drops;
    j["all_steady"] = std::all_of(levels.begin(), levels.end(), [](const Level& l) { return l.steady; });
    if (!measured.empty()) {
      // The seed's calibration measure: the sum over the measured speeds of (P_sim - P_exp)^2.
      double sse = 0;
      int matched = 0;
      nlohmann::ordered_json unmatched = nlohmann::ordered_json::array();
      for (const Level& m : measured) {
        const auto it =
            std::find_if(levels.begin(), levels.end(), [&](const Level& l) { return std::abs(l.rpm - m.rpm) < 0.5; });
        if (it == levels.end()) {
          unmatched.push_back(m.rpm);
          continue;
        }
        sse += (it->net_power_W - m.net_power_W) * (it->net_power_W - m.net_power_W);
        ++matched;
      }
      j["measured_points_matched"] = matched;
      j["measured_rpm_without_level"] = unmatched;
      j["sse_W2"] = matched > 0 ? nlohmann::ordered_json(sse) : nlohmann::ordered_json(nullptr);
      j["rms_W"] = matched > 0 ? nlohmann::ordered_json(std::sqrt(sse / matched)) : nlohmann::ordered_json(nullptr);
    }
    out.push_back(j);
    io::PlotSeries s;
    s.label = k < a.labels.size() ? a.labels[k] : a.dirs[k];
    s.rgb = io::seriesColour(k);
    s.markers = true;
    for (const Level& l : levels) {
      s.x.push_back(l.rpm);
      s.y.push_back(l.net_power_W);
    }
    series.push_back(s);
  }
  if (!measured.empty()) {
    io::PlotSeries m;
    m.label = "measured";
    m.line = false;
    m.markers = true;
    m.rgb = {0, 0, 0};
    for (const Level& l : measured) {
      m.x.push_back(l.rpm);
      m.y.push_back(l.net_power_W);
    }
    series.push_back(m);
  }
  if (!a.png.empty()) {
    io::PlotAxes axes;
    axes.title = "Net power vs stirrer speed";
    axes.x_label = "stirrer speed [rpm]";
    axes.y_label = "net power [W]";
    // Power from zero (its level is read against the axis), speeds with half a step either side.
    double top = 0, lo = 1e300, hi = -1e300;
    for (const auto& s : series)
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        top = std::max(top, s.y[i]);
        lo = std::min(lo, s.x[i]);
        hi = std::max(hi, s.x[i]);
      }
    axes.x_min = lo - 250;
    axes.x_max = hi + 250;
    axes.y_min = 0;
    axes.y_max = top > 0 ? 1.1 * top : 1;
    io::writeLinePlot(a.png, axes, series);
  }
  std::cout << out.dump(2) << std::endl;
  return 0;
}

}  // namespace millsim::cli
