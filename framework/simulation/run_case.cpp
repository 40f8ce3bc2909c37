// Running a DEM case: its stages in order, with histories (HDF5), VTK fields, the
// measurement-format CSV for direct-shear cases, checkpoints, and progress output. Used by
// `rockdem run` and by the tests, so that both exercise the same path.
#include "framework/simulation/run_case.hpp"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "framework/core/error.hpp"
#include "framework/io/checkpoint.hpp"
#include "framework/io/vtk_output.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {
namespace fs = std::filesystem;
namespace {

std::string human_seconds(double s) {
  std::ostringstream os;
  if (!std::isfinite(s)) return "?";
  if (s < 60) os << std::fixed << std::setprecision(0) << s << " s";
  else if (s < 3600) os << std::fixed << std::setprecision(1) << s / 60 << " min";
  else os << std::fixed << std::setprecision(1) << s / 3600 << " h";
  return os.str();
}

// Samples the case's histories and, for direct-shear cases, the measurement-format columns.
class Recorder {
 public:
  Recorder(const Case& c, const Engine& e, const fs::path& history_file) : c_(c), e_(e) {
    stage_id_ = h_.define("stage", "", "index of the stage (1-based)");
    for (const auto& s : c.histories) h_.define(s.name, s.unit, s.description);
    if (c.direct_shear.enabled) {
      ds_[0] = h_.define("joint_shear_stress", "Pa", "loading-block contact force over the nominal joint length");
      ds_[1] = h_.define("joint_shear_displacement", "m", "loading-block displacement in the shear stage");
      ds_[2] = h_.define("joint_normal_displacement", "m", "top-block bottom face minus bottom-block top face, mean vertical displacement");
    }
    h_.open(history_file.string());
  }

  void stage_started(int index, const std::string& name) {
    stage_ = index;
    test_stage_ = 0;
    if (!c_.direct_shear.enabled) return;
    const auto& names = c_.direct_shear.shear_stages;
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) return;
    test_stage_ = static_cast<int>(it - names.begin()) + 1;
    const Model& m = c_.model;
    loader_x0_ = m.blocks[c_.direct_shear.loader].xc.x();
    normal0_ = normal_disp();
    // The file's time runs from the start of the first shear stage and never goes back.
    if (std::isnan(t0_)) t0_ = m.time;
  }

  void sample() {
    const Model& m = c_.model;
    h_.set(stage_id_, stage_);
    for (std::size_t i = 0; i < c_.histories.size(); ++i) h_.set(static_cast<int>(i) + 1, value(c_.histories[i]) * c_.histories[i].scale);
    if (c_.direct_shear.enabled) {
      const auto& d = c_.direct_shear;
      double fx = e_.contact_force_on(d.loader).x();
      for (int l : d.other_loaders) fx += e_.contact_force_on(l).x();
      const double tau = -fx / d.joint_length;
      const double us = m.blocks[d.loader].xc.x() - loader_x0_;
      const double un = normal_disp() - normal0_;
      // A joint that dilates beyond the detection distance loses its contacts (points meeting on
      // the dilated joint are not found) and the specimen collapses: stop, rather than record
      // something that is no longer the joint law's.
      if (test_stage_ && un > c_.settings.detection.distance) {
        std::ostringstream os;
        os << "the joint has dilated " << un * 1e3 << " mm in test stage " << test_stage_ << " (time " << m.time
           << " s), more than the contact detection distance (" << c_.settings.detection.distance * 1e3
           << " mm) within which the specimen keeps its joint contacts; raise [model] detection_tolerance (for a "
              "laboratory-test case [dem] detection_tolerance, up to 20 mm), or run this law with `rockdem element`";
        throw InstabilityError(os.str());
      }
      h_.set(ds_[0], tau);
      h_.set(ds_[1], test_stage_ ? us : 0.0);
      h_.set(ds_[2], test_stage_ ? un : 0.0);
      if (test_stage_) {
        MeasurementRow r;
        r.time_s = m.time - t0_;
        r.stage = test_stage_;
        r.normal_stress_MPa = d.normal_stresses[static_cast<std::size_t>(test_stage_ - 1)] / 1e6;
        r.shear_disp_mm = us * 1e3;
        r.shear_stress_MPa = tau / 1e6;
        r.normal_disp_mm = un * 1e3;
        lab_.rows.push_back(r);
      }
    }
    h_.commit(m.time, m.step);
  }

  void close() { h_.close(); }
  void flush() { h_.flush(); }
  MeasurementFile& lab() { return lab_; }
  History& history() { return h_; }

 private:
  double mean_y(const std::vector<int>& pts) const {
    double s = 0.0;
    for (int g : pts) s += c_.model.gp[g].x.y() - c_.model.gp[g].x0.y();
    return pts.empty() ? 0.0 : s / static_cast<double>(pts.size());
  }
  double normal_disp() const { return mean_y(c_.direct_shear.top_face) - mean_y(c_.direct_shear.bottom_face); }

  double value(const HistorySpec& s) const {
    return s.quantity->measure(c_.model, e_, s.target);
  }

  const Case& c_;
  const Engine& e_;
  History h_;
  int stage_id_ = 0;
  int ds_[3] = {-1, -1, -1};
  int stage_ = 0;
  int test_stage_ = 0;  // 1-based test stage of the current shear stage, 0 outside them
  double loader_x0_ = 0.0, normal0_ = 0.0, t0_ = NAN;
  MeasurementFile lab_;
};

void write_lab_record(const Case& c, MeasurementFile& f, const fs::path& path, const std::string& status) {
  f.metadata = {{"specimen", c.direct_shear.specimen},
                {"joint_length_m", std::to_string(c.direct_shear.joint_length)},
                {"source", "rockdem"},
                {"model", "dem"},
                {"case", c.file}};
  for (const auto& kv : c.direct_shear.metadata) f.metadata.push_back(kv);
  if (!status.empty()) f.metadata.emplace_back("status", status);
  write_measurement_csv(path.string(), f);
}

}  // namespace

RunResult run_case(Case& c, const fs::path& out, bool quiet, const std::string& restart) {
  fs::create_directories(out);
  std::size_t first_stage = 0;
  if (!restart.empty()) {
    const auto extra = read_checkpoint(c.model, restart);
    const auto it = extra.find("stages_completed");
    if (it == extra.end() || it->second < 1 || it->second > static_cast<double>(c.stages.size()))
      throw InputError(restart + ": not a stage checkpoint of this case (valid: the stage_<n>_<name>.h5 files a run of it writes)");
    first_stage = static_cast<std::size_t>(it->second);
    if (first_stage == c.stages.size()) throw InputError(restart + ": this checkpoint ends the last stage; nothing left to run");
  }
  // Joint models in force at each stage: the case's, replaced by a stage's `joints` values from
  // that stage on (also when a restart begins in the middle of the list).
  const auto case_joint_models = c.model.contacts.models;
  auto put_joint_models_in_force = [&](std::size_t stage) {
    c.model.contacts.models = case_joint_models;
    for (std::size_t s = 0; s <= stage; ++s)
      for (const auto& [index, model] : c.stages[s].joint_models) c.model.contacts.models[static_cast<std::size_t>(index)] = model;
  };
  if (first_stage < c.stages.size()) put_joint_models_in_force(first_stage);
  Engine engine(c.model, c.settings);
  for (auto& bc : c.conditions) engine.add_condition(std::move(bc));
  c.conditions.clear();
  // A restart never overwrites the history of the run it continues.
  Recorder rec(c, engine, out / (restart.empty() ? std::string("history.h5")
                                                 : "history_from_stage_" + std::to_string(first_stage + 1) + ".h5"));
  VtkSeries vtk(out / "vtk");
  if (!restart.empty()) {
    vtk.resume(c.model.time);
    if (!quiet) std::cout << "restarting from " << restart << " after stage " << first_stage << " (time " << c.model.time << " s)\n";
  }
  const auto wall0 = std::chrono::steady_clock::now();
  if (!quiet) std::cout << "rockdem: " << c.title << "\n  case: " << c.file << "\n  output: " << out.string() << "\n";
  try {
    for (std::size_t si = first_stage; si < c.stages.size(); ++si) {
      const StageSpec& st = c.stages[si];
      put_joint_models_in_force(si);
      engine.begin_stage(st.name, st.damping);
      rec.stage_started(static_cast<int>(si) + 1, st.name);
      double duration = st.duration;
      if (st.until == StageSpec::Until::duration && st.auto_duration) {
        duration = 0.0;
        for (const auto& bc : engine.conditions())
          if (bc->active_in(st.name))
            if (const auto* v = dynamic_cast<const VelocityCondition*>(bc.get())) duration = std::max(duration, v->duration());
        if (!(duration > 0.0 && std::isfinite(duration)))
          throw InputError(c.file + ": stage '" + st.name + "' has duration = \"auto\" but no finite velocity history is active in it");
      }
      const long planned = st.until == StageSpec::Until::steps ? st.steps
                           : st.until == StageSpec::Until::duration ? static_cast<long>(std::ceil(duration / engine.dt()))
                                                                    : st.max_steps;
      const long vtk_every = c.output.vtk_interval > 0 ? c.output.vtk_interval : std::max(100L, planned / 25);
      if (!quiet)
        std::cout << "stage " << si + 1 << "/" << c.stages.size() << " '" << st.name << "': time step " << engine.dt()
                  << " s, " << (st.until == StageSpec::Until::equilibrium ? "until equilibrium" : std::to_string(planned) + " steps")
                  << ", " << c.model.contacts.items.size() << " contacts\n";
      if (!quiet)
        for (const auto& bc : engine.conditions())
          if (bc->active_in(st.name)) std::cout << "  " << bc->describe(c.model) << "\n";
      vtk.write(c.model);
      rec.sample();
      auto last_print = std::chrono::steady_clock::now();
      const auto stage_wall0 = last_print;
      long n = 0;
      for (;;) {
        bool done = false;
        switch (st.until) {
          case StageSpec::Until::steps: done = n >= st.steps; break;
          case StageSpec::Until::duration: done = engine.stage_time() >= duration - 0.5 * engine.dt(); break;
          case StageSpec::Until::equilibrium:
            done = (n >= 100 && engine.unbalanced_ratio() < st.ratio);
            if (!done && n >= st.max_steps)
              throw InstabilityError("stage '" + st.name + "' did not reach equilibrium (unbalanced-force ratio " +
                                     std::to_string(engine.unbalanced_ratio()) + " > " + std::to_string(st.ratio) +
                                     ") within max_steps = " + std::to_string(st.max_steps));
            break;
        }
        if (done) break;
        const long chunk = 10;
        engine.run_steps(chunk);
        n += chunk;
        if (n % c.output.history_interval < chunk) rec.sample();
        if (n % vtk_every < chunk) vtk.write(c.model);
        const auto now = std::chrono::steady_clock::now();
        const double since = std::chrono::duration<double>(now - last_print).count();
        if (!quiet && since >= c.output.progress_seconds) {
          last_print = now;
          const double el = std::chrono::duration<double>(now - stage_wall0).count();
          const double rate = static_cast<double>(n) / el;
          double left = NAN;
          if (st.until == StageSpec::Until::duration) left = (duration - engine.stage_time()) / engine.dt() / rate;
          if (st.until == StageSpec::Until::steps) left = static_cast<double>(st.steps - n) / rate;
          std::cout << "  step " << c.model.step << "  t = " << std::setprecision(6) << c.model.time << " s  "
                    << std::setprecision(3) << rate << " steps/s  ratio " << engine.unbalanced_ratio()
                    << (std::isfinite(left) ? "  left ~" + human_seconds(left) : std::string()) << "\n"
                    << std::flush;
          rec.flush();
        }
      }
      rec.sample();
      vtk.write(c.model);
      write_checkpoint(c.model, (out / ("stage_" + std::to_string(si + 1) + "_" + st.name + ".h5")).string(),
                       {{"stages_completed", static_cast<double>(si + 1)}});
    }
  } catch (const InstabilityError& e) {
    engine.restore(engine.last_good());
    const auto path = (out / "last_good_state.h5").string();
    write_checkpoint(c.model, path);
    vtk.write(c.model);
    rec.close();
    // The joint record up to here is kept, marked incomplete.
    std::string record;
    if (c.direct_shear.enabled && !rec.lab().rows.empty()) {
      const fs::path partial = out / (c.direct_shear.specimen + ".incomplete.csv");
      write_lab_record(c, rec.lab(), partial, "incomplete: the run stopped (see the message of rockdem run)");
      record = ", the joint record up to then in " + partial.string();
    }
    throw InstabilityError(std::string(e.what()) + "\n  last good state (step " + std::to_string(c.model.step) +
                           ") written to " + path + " and " + (out / "vtk").string() + record);
  }
  write_checkpoint(c.model, (out / "final_state.h5").string());
  rec.close();
  fs::path csv;
  if (c.direct_shear.enabled && !rec.lab().rows.empty()) {
    csv = out / (c.direct_shear.specimen + ".csv");
    write_lab_record(c, rec.lab(), csv, "");
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (!quiet) {
    std::cout << "done: " << c.model.step << " steps, simulated " << c.model.time << " s in " << human_seconds(wall) << "\n"
              << "outputs in " << out.string() << ":\n"
              << "  history.h5        histories (h5py: f['history/time'], f['history/<name>'];"
                 " plot: /usr/bin/python3 scripts/plot_history.py " << (out / "history.h5").string() << ")\n"
              << "  vtk/blocks.pvd    blocks and zones for ParaView (File > Open, Apply; colour by stress or displacement)\n"
              << "  vtk/contacts.pvd  contact points (normal/shear stress, slip state)\n"
              << "  final_state.h5    checkpoint of the final state\n";
    if (!csv.empty()) std::cout << "  " << csv.filename().string() << "  joint test record in the measurement format\n";
  }
  RunResult result;
  result.history = std::move(rec.history());
  result.lab = std::move(rec.lab());
  result.lab_csv = csv;
  return result;
}


}  // namespace rockdem
