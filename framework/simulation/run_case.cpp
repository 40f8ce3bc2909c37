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
#include "framework/simulation/recorder.hpp"
#include "framework/simulation/stage.hpp"

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
  const StageJointModels joints(c);
  if (first_stage < c.stages.size()) joints.put_in_force(c, first_stage);
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
      const StageRunner stage(c, engine, joints, si);
      const StageSpec& st = stage.spec();
      rec.stage_started(static_cast<int>(si) + 1, st.name);
      const long planned = stage.planned_steps();
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
      while (!stage.done(n)) {
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
          const double left = stage.seconds_left(n, rate);
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
    if (DirectShearRecorder* ds = rec.direct_shear()) {
      const fs::path partial = ds->write_incomplete(out);
      if (!partial.empty()) record = ", the joint record up to then in " + partial.string();
    }
    throw InstabilityError(std::string(e.what()) + "\n  last good state (step " + std::to_string(c.model.step) +
                           ") written to " + path + " and " + (out / "vtk").string() + record);
  }
  write_checkpoint(c.model, (out / "final_state.h5").string());
  rec.close();
  DirectShearRecorder* ds = rec.direct_shear();
  const fs::path csv = ds ? ds->write(out) : fs::path();
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
  if (ds) result.lab = std::move(ds->record());
  result.lab_csv = csv;
  return result;
}


}  // namespace rockdem
