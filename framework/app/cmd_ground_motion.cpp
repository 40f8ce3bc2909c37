// `rockdem ground-motion RECORD --units U [...]`: loads an accelerogram, reports it, turns it into
// a displacement drive (window, baseline, taper, pads, zero-phase band-pass, double integration,
// scaling; framework/seismic/signal_processing.hpp) written as a `time_s,shear_disp_mm` CSV for
// path = "file" stages, and prints linear SDOF peaks (--sdof-periods). Option values are read
// as text and checked here, so every bad option is an InputError (exit 2) saying what is valid.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/io/output_folder.hpp"
#include "framework/core/error.hpp"
#include "framework/core/units.hpp"
#include "framework/seismic/ground_motion.hpp"
#include "framework/seismic/sdof.hpp"
#include "framework/seismic/signal_processing.hpp"

namespace rockdem {
namespace {

using namespace seismic;

struct Options {
  std::string record, units, column, time_column, dt;
  // Processing; empty = not given (defaults below), so that any one given option asks for processing.
  std::string start, end, baseline, taper, pad, highpass, lowpass, order, disp_baseline, peak;
  std::string out, label, periods, damping = "0.05";
  bool overwrite = false;
};

double quantity(const std::string& text, Dimension d, const char* option) {
  try {
    return parse_quantity(text, d);
  } catch (const InputError& e) {
    throw InputError(std::string("option ") + option + " '" + text + "': " + e.what() +
                     "; valid units: " + std::string(units_for(d)));
  }
}

int integer(const std::string& text, const char* option, int lo, int hi) {
  int v = 0;
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || v < lo || v > hi) {
    throw InputError(std::string("option ") + option + " '" + text + "' is invalid; valid: an integer from " +
                     std::to_string(lo) + " to " + std::to_string(hi));
  }
  return v;
}

double plain_number(const std::string& text, const char* option) {
  double v = 0.0;
  const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || text.empty()) {
    throw InputError(std::string("option ") + option + " '" + text + "' is not a number");
  }
  return v;
}

// "0.5,1,2" (seconds) or "500 ms,1 s,2 s".
std::vector<double> periods_of(const std::string& text) {
  std::vector<double> out;
  std::size_t b = 0;
  while (b <= text.size()) {
    std::size_t e = text.find(',', b);
    if (e == std::string::npos) e = text.size();
    std::string item = text.substr(b, e - b);
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    double v = 0.0;
    const auto [p, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (ec == std::errc() && p == item.data() + item.size() && !item.empty()) {
      out.push_back(v);  // the option's unit is the second
    } else {
      out.push_back(quantity(item, Dimension::time, "--sdof-periods"));
    }
    if (!(out.back() > 0.0)) {
      throw InputError("option --sdof-periods: period '" + item + "' must be positive; write e.g. 0.5,1,2 (s)");
    }
    b = e + 1;
  }
  return out;
}

bool any_processing(const Options& o) {
  for (const std::string* v : {&o.out, &o.start, &o.end, &o.baseline, &o.taper, &o.pad, &o.highpass, &o.lowpass,
                               &o.order, &o.disp_baseline, &o.peak})
    if (!v->empty()) return true;
  return false;
}

void write_drive(const std::string& path, const ProcessedMotion& m, const std::string& label,
                 const std::string& processing, const std::string& source, const std::string& record,
                 const std::string& record_file) {
  // A drive with nan or inf rows would be read by the case readers as data: refuse it, naming the
  // record (one overflowing sample, e.g. 1e308 g, spreads through the filters and integration).
  for (std::size_t i = 0; i < m.disp.size(); ++i)
    if (!std::isfinite(m.disp[i]) || !std::isfinite(m.time[i]))
      throw InputError(record_file + ": the processed displacement is not finite at t = " + std::to_string(m.time[i]) +
                       " s (a sample of the record is too large or not a number); nothing written to --out " + path);
  std::ostringstream f;
  // Times on the sampling grid print exactly with 3 decimals for dt in whole milliseconds.
  const bool ms_grid = std::abs(m.dt * 1e3 - std::round(m.dt * 1e3)) < 1e-9;
  f << "# drive: " << label << "\n# processing: " << processing << "\n# source: " << source << "\n# record: " << record
    << "\ntime_s,shear_disp_mm\n";
  char buf[64];
  for (std::size_t i = 0; i < m.disp.size(); ++i) {
    std::snprintf(buf, sizeof buf, ms_grid ? "%.3f,%.4f\n" : "%.6f,%.4f\n", m.time[i], m.disp[i] * 1e3);
    f << buf;
  }
  write_file_atomically(path, f.str());
}

int run(const Options& o, const CLI::App& sub) {
  if (!sub.remaining().empty()) {
    std::string extra;
    for (const auto& r : sub.remaining()) extra += (extra.empty() ? "" : " ") + r;
    throw InputError("ground-motion: unknown arguments '" + extra +
                     "'; `rockdem ground-motion --help` lists the options");
  }
  if (o.record.empty()) {
    throw InputError(
        "ground-motion: no record given; usage: rockdem ground-motion RECORD --units g|m/s^2 [--column N]");
  }
  if (o.units.empty()) {
    throw InputError(
        "ground-motion: --units is required (the unit of the record's values: g, m/s^2, or a quantity "
        "such as \"9.81 m/s^2\"); a wrong unit is the commonest silent error in a record");
  }
  RecordLayout layout;
  try {
    layout.unit = parse_acceleration_unit(o.units);
  } catch (const InputError& e) {
    throw InputError(std::string("option --units: ") + e.what());
  }
  layout.column = o.column;
  if (!o.time_column.empty()) layout.time_column = integer(o.time_column, "--time-column", 0, 1000);
  if (!o.dt.empty()) {
    if (layout.time_column != 0) {
      throw InputError(
          "option --dt is only for records without a time column (--time-column 0); this record's "
          "times are in column " +
          std::to_string(layout.time_column));
    }
    layout.dt = quantity(o.dt, Dimension::time, "--dt");
  }
  if (o.overwrite && o.out.empty()) throw InputError("ground-motion: --overwrite goes with --out (it replaces that file)");
  ResultFilePlan plan;
  plan.input("the record", o.record);
  plan.output("--out", o.out);
  plan.check(o.overwrite);
  const GroundMotion g = load_ground_motion(o.record, layout);
  const std::size_t ip = peak_index(g.acc);
  std::printf("record %s (%s): %zu samples, dt %.6g s, %.6g s to %.6g s; peak %.6g m/s^2 (%.5g x %s) at %.6g s\n",
              g.source.c_str(), g.column_name.c_str(), g.acc.size(), g.dt, g.t0, g.t0 + g.duration(), g.acc[ip],
              g.acc[ip] / layout.unit.to_si, layout.unit.text.c_str(), g.t0 + g.dt * static_cast<double>(ip));

  if (!o.periods.empty()) {
    SdofOscillator osc;
    osc.damping = plain_number(o.damping, "--damping");
    std::printf("linear SDOF, damping %.4g, record as loaded (exact piecewise-linear recurrence):\n", osc.damping);
    std::printf("  %10s  %22s\n", "Tn (s)", "peak rel. disp. (m)");
    for (double T : periods_of(o.periods)) {
      osc.period = T;
      std::printf("  %10.4g  %22.6f\n", T, sdof_peak_displacement(g.acc, g.dt, osc));
    }
  }
  if (!any_processing(o)) return 0;

  DisplacementProcessing p;
  if (!o.start.empty()) p.start = quantity(o.start, Dimension::time, "--start");
  if (!o.end.empty()) p.end = quantity(o.end, Dimension::time, "--end");
  if (!o.baseline.empty()) p.acc_baseline_degree = integer(o.baseline, "--baseline-degree", -1, 10);
  if (!o.taper.empty()) p.taper = quantity(o.taper, Dimension::time, "--taper");
  if (!o.pad.empty()) p.pad = quantity(o.pad, Dimension::time, "--pad");
  if (!o.highpass.empty()) p.f_low = quantity(o.highpass, Dimension::frequency, "--highpass");
  if (!o.lowpass.empty()) p.f_high = quantity(o.lowpass, Dimension::frequency, "--lowpass");
  if (!o.order.empty()) p.order = integer(o.order, "--order", 1, 8);
  if (!o.disp_baseline.empty()) p.disp_baseline_degree = integer(o.disp_baseline, "--disp-baseline-degree", 0, 10);
  if (!o.peak.empty()) {
    p.peak_displacement = quantity(o.peak, Dimension::length, "--peak");
    if (!(p.peak_displacement > 0.0)) throw InputError("option --peak '" + o.peak + "' must be positive");
  }
  const ProcessedMotion m = process_to_displacement(g, p);
  const std::size_t id = peak_index(m.disp);
  std::printf("displacement: %zu samples over %.6g s (record %.6g s to %.6g s plus %.6g s pads), scale %.6g\n",
              m.disp.size(), m.time.back(), m.record_start, m.record_start + m.time.back() - 2.0 * p.pad, p.pad,
              m.scale);
  std::printf(
      "  peak %.4f mm at %.3f s, end %.4f mm (%.3f %% of peak), peak velocity %.2f mm/s, dominant "
      "frequency %.4f Hz\n",
      m.disp[id] * 1e3, m.time[id], m.disp.back() * 1e3, 100.0 * std::abs(m.disp.back() / m.disp[id]),
      peak_abs(m.vel) * 1e3, dominant_frequency(m.disp, m.dt));
  if (!o.out.empty()) {
    const std::string label = o.label.empty()
                                  ? "shear displacement (derived from " +
                                        std::filesystem::path(g.source).filename().string() + " " + g.column_name + ")"
                                  : o.label;
    char dt[32];
    std::snprintf(dt, sizeof dt, "%.6g", g.dt);
    write_drive(o.out, m, label, p.describe(), g.source,
                g.column_name + ", units " + layout.unit.text + ", dt " + dt + " s", o.record);
    std::printf("  -> %s\n", o.out.c_str());
  }
  return 0;
}

const CommandRegistrar reg{Command{
    "ground-motion", "load an accelerogram, make a displacement drive CSV from it, print SDOF peaks", false,
    [](CLI::App& sub) {
      auto o = std::make_shared<Options>();
      sub.allow_extras();  // unknown arguments are reported by the action (exit 2, with the valid options)
      sub.add_option("record", o->record, "accelerogram: whitespace columns or CSV (header allowed, # comments)");
      sub.add_option("--units", o->units, "unit of the values: g, m/s^2, or one unit as a quantity (\"9.81 m/s^2\")");
      sub.add_option("--column", o->column, "acceleration column: 1-based number or CSV header name (default: last)");
      sub.add_option("--time-column", o->time_column, "time column, 1-based; 0 = none, then --dt (default 1)");
      sub.add_option("--dt", o->dt, "time step when there is no time column, e.g. \"0.02 s\"");
      sub.add_option("--start", o->start, "window start in record time, e.g. \"40 s\" (default: first sample)");
      sub.add_option("--end", o->end, "window end in record time, e.g. \"80 s\" (default: last sample)");
      sub.add_option("--baseline-degree", o->baseline,
                     "degree of the polynomial removed from the acceleration; -1 = none (default 1)");
      sub.add_option("--taper", o->taper, "cosine taper at both ends of the window, e.g. \"3 s\" (default 0 s)");
      sub.add_option("--pad", o->pad, "zeros added at both ends before filtering, e.g. \"10 s\" (default 0 s)");
      sub.add_option("--highpass", o->highpass, "high-pass corner, e.g. \"0.2 Hz\" (default: none)");
      sub.add_option("--lowpass", o->lowpass, "low-pass corner, e.g. \"2 Hz\" (default: none)");
      sub.add_option("--order", o->order, "Butterworth order of each pass, 1..8 (default 2; applied forward and back)");
      sub.add_option("--disp-baseline-degree", o->disp_baseline,
                     "remove powers 2..N of time from the displacement; 0 = none (default 0)");
      sub.add_option("--peak", o->peak, "scale to this peak |displacement|, e.g. \"25.4 mm\" (default: unscaled)");
      sub.add_option("--out", o->out, "write the drive CSV (time_s,shear_disp_mm) here");
      sub.add_flag("--overwrite", o->overwrite, "replace the --out file if it exists");
      sub.add_option("--label", o->label, "text of the drive file's '# drive:' line");
      sub.add_option("--sdof-periods", o->periods,
                     "print linear SDOF peak displacements for these periods, e.g. 0.5,1,2 (s) or \"500 ms,1 s\"");
      sub.add_option("--damping", o->damping, "SDOF damping ratio, fraction of critical (default 0.05)");
      const CLI::App* self = &sub;
      return [o, self]() -> int { return run(*o, *self); };
    }}};

}  // namespace
}  // namespace rockdem
