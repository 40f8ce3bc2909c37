// Running a DEM case: its stages in order, with histories (HDF5), VTK fields, the
// measurement-format CSV for direct-shear cases, checkpoints, and progress output. Used by
// `rockdem run` and by the tests, so that both exercise the same path.
#include "framework/simulation/run_case.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>

#include <unistd.h>

#include "framework/boundary/relax_condition.hpp"
#include "framework/core/error.hpp"
#include "framework/core/interrupt.hpp"
#include "framework/io/case_comparison.hpp"
#include "framework/io/checkpoint.hpp"
#include "framework/io/output_folder.hpp"
#include "framework/geometry/polygon.hpp"
#include "framework/model/block_outline.hpp"
#include "framework/io/vtk_output.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/in_situ.hpp"
#include "framework/simulation/drift_results.hpp"
#include "framework/simulation/excavate.hpp"
#include "framework/simulation/recorder.hpp"
#include "framework/simulation/stage.hpp"

namespace rockdem {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

std::string human_seconds(double s) {
  std::ostringstream os;
  if (!std::isfinite(s)) return "?";
  if (s < 60) os << std::fixed << std::setprecision(0) << s << " s";
  else if (s < 3600) os << std::fixed << std::setprecision(1) << s / 60 << " min";
  else os << std::fixed << std::setprecision(1) << s / 3600 << " h";
  return os.str();
}

// A block a stage's scale_off took out: the stage (index), the step, how far it had moved from
// where the stage found it [m] and its area [m2] then.
struct ScaledOff {
  std::size_t stage = 0;
  BlockId id{};
  std::string name;
  long step = 0;
  double moved = 0.0, area = 0.0;
};

// Checkpoints carry them as rows of (stage, block id, step, moved, area).
constexpr std::size_t kScaledOffColumns = 5;

std::vector<double> scaled_off_array(const std::vector<ScaledOff>& list) {
  std::vector<double> a;
  for (const ScaledOff& s : list)
    a.insert(a.end(), {static_cast<double>(s.stage), static_cast<double>(id_value(s.id)), static_cast<double>(s.step), s.moved, s.area});
  return a;
}

// The blocks a checkpoint says were scaled off, named from the case's model (which still has them).
std::vector<ScaledOff> scaled_off_from(const CheckpointArrays& a, const Case& c, const std::string& file) {
  std::vector<ScaledOff> out;
  const auto it = a.find("run.scaled_off");
  if (it == a.end()) return out;
  const std::vector<double>& v = it->second;
  if (v.size() % kScaledOffColumns != 0) throw InputError(file + ": its list of scaled-off blocks is damaged");
  for (std::size_t i = 0; i < v.size(); i += kScaledOffColumns) {
    ScaledOff s;
    if (!(v[i] >= 0.0 && v[i] < static_cast<double>(c.stages.size()) && v[i + 1] >= 0.0 && v[i + 1] < 2147483647.0))
      throw InputError(file + ": its list of scaled-off blocks is damaged (row " + std::to_string(i / kScaledOffColumns + 1) + ")");
    s.stage = static_cast<std::size_t>(v[i]);
    s.id = static_cast<BlockId>(static_cast<std::int32_t>(v[i + 1]));
    s.step = static_cast<long>(v[i + 2]);
    s.moved = v[i + 3];
    s.area = v[i + 4];
    const auto b = std::find_if(c.model.blocks.begin(), c.model.blocks.end(), [&](const Block& x) { return x.id == s.id; });
    if (b == c.model.blocks.end())
      throw InputError(file + ": it says block id " + std::to_string(id_value(s.id)) + " was scaled off, and this case has no such block");
    s.name = b->name;
    out.push_back(std::move(s));
  }
  return out;
}

// A block's position for scaling: the mean of its gridpoints (a rigid block's centre if it has none).
Vec2 block_mean(const Model& m, std::size_t b) {
  const Block& B = m.blocks[b];
  if (B.n_gp == 0) return B.xc;
  Vec2 sum = Vec2::Zero();
  for (int i = 0; i < B.n_gp; ++i) sum += m.gp[static_cast<std::size_t>(B.first_gp + i)].x;
  return sum / static_cast<double>(B.n_gp);
}

// A stage checkpoint written after an excavation holds fewer blocks than the case's model: the
// excavations of the completed stages are made again, one stage at a time, until the checkpoint
// fits (a restore that does not fit leaves the model untouched), and they must be exactly those
// of the stages the checkpoint completed.
CheckpointScalars read_after_excavations(Case& c, const std::string& restart, std::vector<ScaledOff>& scaled) {
  scaled = scaled_off_from(read_checkpoint_arrays(restart), c, restart);
  // The removals in the order the run made them: each stage's excavation at its start, then the
  // blocks its scale_off took out while it ran.
  struct Removal {
    std::size_t stage;
    std::vector<BlockId> ids;
    bool scaling;
  };
  std::vector<Removal> removals;
  for (std::size_t k = 0; k < c.stages.size(); ++k) {
    if (!c.stages[k].excavate.empty()) removals.push_back({k, c.stages[k].excavate, false});
    std::vector<BlockId> ids;
    for (const ScaledOff& s : scaled)
      if (s.stage == k) ids.push_back(s.id);
    if (!ids.empty()) removals.push_back({k, std::move(ids), true});
  }
  std::size_t made = 0;  // removals made again so far
  std::string first_error;
  CheckpointScalars extra;
  for (;;) {
    try {
      extra = read_checkpoint(c.model, restart);
      break;
    } catch (const InputError& e) {
      if (first_error.empty()) first_error = e.what();
      if (made == removals.size()) throw InputError(first_error);
      // Made again without a gradual release (the checkpoint holds what is left of one).
      take_out_blocks(c, c.conditions, removals[made++].ids);
    }
  }
  const auto it = extra.find("stages_completed");
  // Written within a stage: that stage's excavation has been made too.
  const double completed = (it == extra.end() ? 0.0 : it->second) + (extra.count("within_stage") ? 1.0 : 0.0);
  // Removals of the stages run that take out nothing (an excavation of blocks an earlier
  // scale_off took out) were made by the run as much as by this replay.
  const auto present = [&](const std::vector<BlockId>& ids) {
    return std::any_of(c.model.blocks.begin(), c.model.blocks.end(),
                       [&](const Block& b) { return std::find(ids.begin(), ids.end(), b.id) != ids.end(); });
  };
  while (made < removals.size() && static_cast<double>(removals[made].stage) < completed && !present(removals[made].ids)) ++made;
  for (std::size_t i = 0; i < removals.size(); ++i) {
    const std::size_t k = removals[i].stage;
    if (removals[i].scaling ? i >= made : (i < made) != (static_cast<double>(k) < completed))
      throw InputError(restart + ": the checkpoint's blocks do not follow this case's excavations (stage '" +
                       c.stages[k].name + "'); restart from a stage checkpoint of this case");
  }
  return extra;
}

// A restart continues the run that wrote its checkpoint: the case may add or change stages that
// had not run yet, and nothing else (a changed stiffness would make the continued run a hybrid
// that no case describes). The differences are named, key by key.
void check_same_case(const Case& c, const std::string& restart, std::size_t completed, bool root) {
  const auto texts = read_checkpoint_texts(restart);
  const auto it = texts.find("case_toml");
  if (it == texts.end()) {
    if (root)
      std::cerr << "rockdem: warning: " << restart << " does not record the case that wrote it (an older rockdem wrote it); "
                << "the case is not compared with it\n";
    return;
  }
  std::vector<std::string> diffs;
  try {
    diffs = restart_differences(it->second, c.source_toml, completed);
  } catch (const InputError& e) {
    throw InputError(restart + ": " + e.what());
  }
  if (diffs.empty()) return;
  std::string msg = restart + ": this case differs from the one that wrote the checkpoint in " + std::to_string(diffs.size()) +
                    (diffs.size() == 1 ? " value" : " values") + " that the stages run so far ran with:";
  for (std::size_t i = 0; i < diffs.size() && i < 8; ++i) msg += "\n    " + diffs[i];
  if (diffs.size() > 8) msg += "\n    ... and " + std::to_string(diffs.size() - 8) + " more";
  msg += "\n  a restart may change or add only the stages still to run (from stage " + std::to_string(completed + 1) +
         " on), with boundary conditions and motions that only they use; run the changed case from the start (values "
         "given on the command line, --pgv, --motion, --excavate and --seed, are part of the case: the manifest's "
         "command_line has those of the run that wrote the checkpoint)";
  throw InputError(msg);
}

}  // namespace

std::size_t check_restart(const Case& c, const std::string& restart, bool root) {
  const auto extra = read_checkpoint_scalars(restart);
  const bool within = extra.count("within_stage") != 0;
  // An older rockdem kept the state at a signal for inspection only.
  if (extra.count("interrupted") && !within)
    throw InputError(restart + ": the state of an interrupted run, kept for inspection; restarts continue from the end of "
                     "a stage (the stage_<n>_<name>.h5 files in the same folder)");
  const auto it = extra.find("stages_completed");
  const double lowest = within ? 0.0 : 1.0, highest = static_cast<double>(c.stages.size()) - (within ? 1.0 : 0.0);
  if (it == extra.end() || it->second < lowest || it->second > highest)
    throw InputError(restart + ": not a checkpoint this case can go on from (valid: the stage_<n>_<name>.h5, checkpoint_step_<n>.h5, "
                     "interrupted_state.h5 and final_state.h5 files a run of it writes" +
                     (it != extra.end() && it->second > static_cast<double>(c.stages.size())
                          ? "; this one completed " + std::to_string(static_cast<long>(it->second)) + " stages, the case has " +
                                std::to_string(c.stages.size())
                          : std::string()) +
                     ")");
  const auto first_stage = static_cast<std::size_t>(it->second);
  // Within a stage, that stage has run in part with the checkpoint's case: it must not change.
  check_same_case(c, restart, first_stage + (within ? 1 : 0), root);
  if (!within && first_stage == c.stages.size())
    throw InputError(restart + ": this checkpoint ends the case's last stage ('" + c.stages.back().name +
                     "'); nothing is left to run (add stages to the case to go on from it)");
  return first_stage;
}

namespace {

// Where a run resumed within a stage goes on: steps are run in chunks, after each of which the
// run samples and checks what it must; a checkpoint within a stage is written at a contact
// detection, which may fall inside a chunk.
struct StageResume {
  long chunk_start = 0;  // steps of the stage before the chunk under way
  long into_chunk = 0;   // steps of that chunk already run
  long vtk_every = 0;    // the stage's VTK interval (it depends on the time step at its start)
};

// The stage a run begins with: the first, or after a restart the one following the stages its
// checkpoint completed, or the one it was written within (the model state is read back from it).
std::size_t read_restart(Case& c, const std::string& restart, std::optional<StageResume>& resume, std::vector<ScaledOff>& scaled) {
  if (restart.empty()) return 0;
  const std::size_t first_stage = check_restart(c, restart, false);  // rockdem run has warned already
  const CheckpointScalars extra = read_after_excavations(c, restart, scaled);
  if (extra.count("within_stage")) {
    const auto get = [&](const char* k) {
      const auto it = extra.find(k);
      if (it == extra.end() || !(it->second >= 0.0 && it->second < 1e15))
        throw InputError(restart + ": its '" + std::string(k) + "' is missing or damaged");
      return static_cast<long>(it->second);
    };
    resume = StageResume{get("stage_chunk_start"), get("stage_into_chunk"), get("stage_vtk_every")};
    if (resume->into_chunk > 10 || resume->vtk_every < 1 || resume->chunk_start % 10 != 0)
      throw InputError(restart + ": its place within the stage is damaged (chunk start " + std::to_string(resume->chunk_start) +
                       ", " + std::to_string(resume->into_chunk) + " steps into it, VTK every " + std::to_string(resume->vtk_every) + ")");
  }
  return first_stage;
}

// Progress output (none when quiet). Every line goes straight to std::cout in the order of the
// run: a step line leaves the stream's precision set for the lines after it, as it always has.
// On a terminal the step lines overwrite each other (one line that updates); in a pipe or a file,
// and under mpirun (OutputSpec::updating_line), each is a line of its own, for logs and scripts.
class Progress {
 public:
  Progress(const Case& c, bool quiet) : c_(c), quiet_(quiet), terminal_(c.output.updating_line && isatty(fileno(stdout)) != 0) {}
  bool quiet() const { return quiet_; }

  // Ends an updating step line, so that what follows starts on a line of its own.
  void end_line() {
    if (!pending_) return;
    std::cout << "\n" << std::flush;
    pending_ = false;
  }

  void restarted(const std::string& restart, std::size_t first_stage, bool within) {
    if (quiet_) return;
    std::cout << "restarting from " << restart << (within ? " within stage " : " after stage ") << first_stage + (within ? 1 : 0)
              << " (step " << c_.model.step << ", time " << c_.model.time << " s)\n";
  }

  // A checkpoint written within a stage.
  void checkpoint_written(const fs::path& path) {
    if (quiet_) return;
    end_line();
    std::cout << "  checkpoint " << path.filename().string() << " (step " << c_.model.step << ")\n";
  }

  void run_started(const fs::path& out) {
    wall0_ = Clock::now();
    if (!quiet_) std::cout << "rockdem: " << c_.title << "\n  case: " << c_.file << "\n  output: " << out.string() << "\n";
  }

  void stage_started(const Engine& e, const StageRunner& stage, std::size_t index, long contacts, bool resumed) {
    if (quiet_) return;
    end_line();
    const StageSpec& st = stage.spec();
    stage_label_ = st.name + " " + std::to_string(index + 1) + "/" + std::to_string(c_.stages.size());
    std::cout << "stage " << index + 1 << "/" << c_.stages.size() << " '" << st.name << "'"
              << (resumed ? " resumed at step " + std::to_string(c_.model.step) + " (stage time " + std::to_string(e.stage_time()) + " s)"
                          : std::string())
              << ": time step " << e.dt() << " s, "
              << (st.until == StageSpec::Until::equilibrium ? "until equilibrium" : std::to_string(stage.planned_steps()) + " steps")
              << ", " << contacts << " contacts";
    if (e.added_mass_fraction() > 0.0) std::cout << ", masses scaled (+" << 100.0 * e.added_mass_fraction() << " % of the model's)";
    std::cout << "\n";
    for (const auto& bc : e.conditions())
      if (bc->active_in(st.name)) std::cout << "  " << bc->describe(c_.model) << "\n";
  }

  // The stage's steps begin now (its rate is measured from here).
  void stepping_started() { stage_wall0_ = last_print_ = Clock::now(); }

  // After `n` steps of the stage: a line (step, simulated time, rate, time left) at most every
  // [output] progress_seconds; true when one was printed.
  bool steps_done(const Engine& e, const StageRunner& stage, long n) {
    const auto now = Clock::now();
    const double since = std::chrono::duration<double>(now - last_print_).count();
    if (quiet_ || !(since >= c_.output.progress_seconds)) return false;
    last_print_ = now;
    const double el = std::chrono::duration<double>(now - stage_wall0_).count();
    const double rate = static_cast<double>(n) / el;
    const double left = stage.seconds_left(n, rate);
    // The stage is named on every line: in a log the stage's header is far above.
    std::cout << (terminal_ ? "\r" : "") << "  " << stage_label_ << "  step " << c_.model.step << "  t = " << std::setprecision(6) << c_.model.time
              << " s  " << std::setprecision(3) << rate << " steps/s  ratio " << e.unbalanced_ratio()
              << (std::isfinite(left) ? "  left ~" + human_seconds(left) : std::string())
              << (terminal_ ? "\x1b[K" : "\n") << std::flush;  // erase the rest of the previous line
    pending_ = terminal_;
    return true;
  }

  // The summary of a completed run; `csv` is the joint test record, if any.
  void finished(const fs::path& out, const fs::path& csv) {
    const double wall = std::chrono::duration<double>(Clock::now() - wall0_).count();
    if (quiet_) return;
    end_line();
    std::cout << "done: " << c_.model.step << " steps, simulated " << c_.model.time << " s in " << human_seconds(wall) << "\n"
              << "outputs in " << out.string() << ":\n"
              << "  history.h5        histories (h5py: f['history/time'], f['history/<name>'];"
                 " plot: /usr/bin/python3 scripts/plot_history.py " << (out / "history.h5").string() << ")\n"
              << "  vtk/blocks.pvd    blocks and zones for ParaView (File > Open, Apply; colour by stress or displacement)\n"
              << "  vtk/contacts.pvd  contact points (normal/shear stress, slip state)\n"
              << "  final_state.h5    checkpoint of the final state\n";
    if (!csv.empty()) std::cout << "  " << csv.filename().string() << "  joint test record in the measurement format\n";
    if (fs::exists(out / "drift" / "events.csv"))
      std::cout << "  drift/            the drift study's results per stage (events.csv, contacts_*.csv, fallen_blocks.csv,"
                   " blocks.pvd, joints.pvd; docs/drift-study.md)\n";
    if (fs::exists(out / "scaled_off.csv"))
      std::cout << "  scaled_off.csv    the blocks scale_off took out (stage, step, block, how far each had moved)\n";
    for (std::size_t i = 0; i < c_.stages.size(); ++i)
      if (!c_.stages[i].motions.empty())
        std::cout << "  motion_" << i + 1 << "_" << c_.stages[i].name << ".csv  the ground motion applied in that stage\n";
  }

 private:
  const Case& c_;
  bool quiet_;
  bool terminal_;        // stdout is a terminal
  bool pending_ = false;  // an updating step line has not been ended yet
  std::string stage_label_;  // "event_1 3/6": the stage the progress lines are about
  Clock::time_point wall0_, stage_wall0_, last_print_;
};

// What the parts of one run share.
struct Run {
  Case& c;
  const fs::path& out;
  Engine& engine;
  Recorder& rec;
  VtkSeries& vtk;
  Progress& progress;
  Communication& comm;
  DriftResults* drift = nullptr;  // [drift]: the study's results at every stage end
  // Within the stage under way: its excavation relax (if any), and a checkpoint or a signal waiting
  // for the next contact detection.
  RelaxCondition* relax = nullptr;
  bool checkpoint_due = false;
  int signal = 0;
  long signal_wait = 0;  // steps run since the signal
  long last_checkpoint_step = 0;
  Clock::time_point last_checkpoint_wall = Clock::now();
  std::vector<fs::path> checkpoints;  // written by this run, oldest first
  bool owners_due = false;  // a check of the blocks' owners waits for the next contact detection
  // Scaling (a stage's scale_off): where each block was when the stage under way began (by id),
  // and the blocks taken out so far in the run, in order.
  std::map<BlockId, Vec2> scale_from{};
  std::vector<ScaledOff> scaled_off{};
  std::set<BlockId> kept_loose{};  // held blocks past the stage's scale_off, warned of
  long scaled_at = -1;  // the stage's step count at its last removal: its end is not asked then
  bool root() const { return comm.root(); }
};

// Runs `write` on process 0 with the whole model's state current there (a decomposed run collects
// it first and then goes back to stepping with its own contacts); a serial run just writes.
// A write that fails on process 0 (a full disk) is raised on every process, so that none goes
// on stepping and waits for process 0 in the next exchange.
template <class F>
void with_whole_model(Run& r, F&& write) {
  if (!r.c.model.part.decomposed()) {
    write();
    return;
  }
  ContactList local;
  r.comm.collect(r.c.model, 0, &local);
  std::string error;
  bool input_error = false;
  if (r.root()) {
    try {
      write();
    } catch (const InputError& e) {
      error = e.what();
      input_error = true;
    } catch (const std::exception& e) {
      error = e.what();
    }
    r.c.model.contacts.restore(std::move(local));
  }
  const bool input = r.comm.max(input_error ? 1.0 : 0.0) > 0.0;
  error = r.comm.first_message(error);
  if (error.empty()) return;
  if (input) throw InputError(error);
  throw std::runtime_error(error);
}

// Contacts in the whole model (each counted by the process owning its point).
long contact_count(const Run& r) {
  const Model& m = r.c.model;
  double n = 0.0;
  for (const Contact& c : m.contacts.items) n += m.part.owns(m.gp[static_cast<std::size_t>(c.point)].block) ? 1.0 : 0.0;
  r.comm.sum(&n, 1);
  return static_cast<long>(n);
}

// Every process writes its own piece (VtkSeries::write): no collect.
void write_vtk(Run& r) { r.vtk.write(r.c.model, r.comm); }

// The state boundary conditions carry from stage to stage (forces held by quiet boundaries, the
// free field's motion), by the condition's position in the case.
CheckpointArrays condition_states(const Engine& e) {
  CheckpointArrays a;
  for (std::size_t i = 0; i < e.conditions().size(); ++i)
    if (auto s = e.conditions()[i]->saved_state(); !s.empty()) a["condition_" + std::to_string(i)] = std::move(s);
  return a;
}

void restore_condition_states(Engine& e, const std::string& restart) {
  for (const auto& [name, state] : read_checkpoint_arrays(restart)) {
    if (name.rfind("condition_", 0) != 0) continue;
    const std::size_t i = std::stoul(name.substr(10));
    if (i >= e.conditions().size())
      throw InputError(restart + ": the checkpoint holds the state of boundary condition " + std::to_string(i + 1) +
                       ", which this case does not have");
    e.conditions()[i]->restore_state(state);
  }
}

// The input actually applied in a stage that plays ground motions: <out>/motion_<n>_<stage>.csv,
// with each motion's acceleration, velocity and displacement after processing and scaling.
void write_stage_motions(const Run& r, std::size_t index) {
  const StageSpec& st = r.c.stages[index];
  if (st.motions.empty() || !r.root()) return;
  const fs::path path = r.out / ("motion_" + std::to_string(index + 1) + "_" + st.name + ".csv");
  std::ofstream os(path);
  os << "# rockdem: ground motions applied in stage '" << st.name << "' (time from the stage start)\n";
  double duration = 0.0, dt = 1e300;
  for (const auto& m : st.motions) {
    const auto& mo = *r.c.motions[static_cast<std::size_t>(m.index)];
    os << "# motion: " << mo.name << " | source: " << mo.source << " | type: " << seismic::motion_type_name(mo.type)
       << " | direction: " << (mo.direction == 0 ? "x" : "y") << " | stage factor: " << m.factor
       << " | PGA " << m.factor * mo.pga() << " m/s2, PGV " << m.factor * mo.pgv() << " m/s | processing: " << mo.processing << "\n";
    duration = std::max(duration, mo.duration());
    dt = std::min(dt, mo.dt);
  }
  os << "time_s";
  for (const auto& m : st.motions) {
    const std::string n = r.c.motions[static_cast<std::size_t>(m.index)]->name;
    os << "," << n << "_acc_mps2," << n << "_vel_mps," << n << "_disp_m";
  }
  os << "\n";
  os.precision(9);
  const auto rows = static_cast<long>(std::llround(duration / dt));
  for (long k = 0; k <= rows; ++k) {
    const double t = static_cast<double>(k) * dt;
    os << t;
    for (const auto& m : st.motions) {
      const auto& mo = *r.c.motions[static_cast<std::size_t>(m.index)];
      os << "," << m.factor * mo.acceleration(t) << "," << m.factor * mo.velocity(t) << "," << m.factor * mo.displacement(t);
    }
    os << "\n";
  }
  if (!os) throw InputError("cannot write " + path.string());
}

// A checkpoint a restart continues from, after `completed` stages: the model, what the boundary
// conditions and the engine carry between steps, the histories and records so far, and the case.
// At a stage's end the drift results take that stage's row first (on the whole model).
// `within`: written within stage `completed` + 1 (what it carries from step to step goes too).
void write_restartable(Run& r, const fs::path& path, std::size_t completed, bool stage_end,
                       const StageResume* within = nullptr, bool interrupted = false) {
  CheckpointArrays engine_state = r.engine.saved_state();  // collective
  if (within) engine_state.merge(r.engine.saved_stage_state());  // collective
  with_whole_model(r, [&] {
    if (stage_end && r.drift) r.drift->stage_ended(r.c.model, completed - 1, r.engine.unbalanced_ratio());
    CheckpointArrays arrays = condition_states(r.engine);
    arrays.merge(engine_state);
    arrays.merge(r.rec.saved_state());
    if (r.drift) arrays.merge(r.drift->saved_state());
    if (!r.scaled_off.empty()) arrays["run.scaled_off"] = scaled_off_array(r.scaled_off);
    CheckpointScalars scalars{{"stages_completed", static_cast<double>(completed)}};
    if (within) {
      scalars.insert({{"within_stage", 1.0},
                      {"stage_chunk_start", static_cast<double>(within->chunk_start)},
                      {"stage_into_chunk", static_cast<double>(within->into_chunk)},
                      {"stage_vtk_every", static_cast<double>(within->vtk_every)}});
      if (interrupted) scalars["interrupted"] = 1.0;
      if (r.relax) arrays["stage.relax"] = r.relax->progress();
      if (!r.scale_from.empty()) {
        auto& from = arrays["stage.scale_from"];
        for (const auto& [id, x] : r.scale_from) from.insert(from.end(), {static_cast<double>(id_value(id)), x.x(), x.y()});
      }
    }
    write_checkpoint(r.c.model, path.string(), scalars, arrays, {{"case_toml", r.c.source_toml}});
  });
}

// A checkpoint asked for within a stage ([output] checkpoint_every, "N steps" or wall-clock, or
// at a signal), written now that the engine has just detected contacts. The newest
// [output] checkpoint_keep of this run's are kept. A signal then ends the run (Interrupted).
void write_pending(Run& r, std::size_t index, long chunk_start, long into_chunk, long vtk_every) {
  const StageResume at{chunk_start, into_chunk, vtk_every};
  if (r.signal) {
    write_restartable(r, r.out / "interrupted_state.h5", index, false, &at, true);
    throw Interrupted(r.signal, "");
  }
  const fs::path path = r.out / ("checkpoint_step_" + std::to_string(r.c.model.step) + ".h5");
  write_restartable(r, path, index, false, &at);
  r.checkpoint_due = false;
  r.last_checkpoint_step = r.c.model.step;
  r.last_checkpoint_wall = Clock::now();
  r.progress.checkpoint_written(path);
  if (!r.root()) return;
  r.checkpoints.push_back(path);
  const auto keep = static_cast<std::size_t>(r.c.output.checkpoint_keep);
  while (keep > 0 && r.checkpoints.size() > keep) {
    std::error_code ec;
    fs::remove(r.checkpoints.front(), ec);
    r.checkpoints.erase(r.checkpoints.begin());
  }
}

// After a chunk of steps: whether a checkpoint within the stage is due (the same answer on every
// process: the wall clock is process 0's).
bool checkpoint_due(Run& r) {
  const OutputSpec& o = r.c.output;
  bool due = o.checkpoint_steps > 0 && r.c.model.step - r.last_checkpoint_step >= o.checkpoint_steps;
  if (o.checkpoint_seconds > 0.0) {
    const double since = std::chrono::duration<double>(Clock::now() - r.last_checkpoint_wall).count();
    double wall = r.root() && since >= o.checkpoint_seconds ? 1.0 : 0.0;
    if (r.c.model.part.decomposed()) wall = r.comm.max(wall);
    due = due || wall > 0.0;
  }
  return due;
}

// The checkpoint at the end of a stage (<out>/stage_<n>_<name>.h5).
void write_stage_checkpoint(Run& r, std::size_t index) {
  write_restartable(r, r.out / ("stage_" + std::to_string(index + 1) + "_" + r.c.stages[index].name + ".h5"), index + 1, true);
  // A checkpoint within the next stage counts its interval from here.
  r.last_checkpoint_step = r.c.model.step;
  r.last_checkpoint_wall = Clock::now();
}

// Steps of a stage between checks of the blocks' owners in a decomposed run (Engine::rebalance):
// a check costs a pass over the contacts and two small exchanges.
constexpr long kOwnerCheckSteps = 100;

// At a contact detection: the blocks change owner if the communication says so; said on screen.
void check_owners(Run& r) {
  r.owners_due = false;
  const OwnerChange ch = r.engine.rebalance(r.c.settings.imbalance_limit);
  if (ch.owner.empty() || !r.root() || r.progress.quiet()) return;
  r.progress.end_line();
  std::ostringstream os;
  os.precision(4);
  os << "step " << r.c.model.step << ": ";
  if (ch.repartitioned) {
    os << "blocks shared out again (METIS, load imbalance " << ch.imbalance_before << " -> " << ch.imbalance_after << "): " << ch.moved
       << (ch.moved == 1 ? " block" : " blocks") << " moved";
  } else {
    os << ch.moved << (ch.moved == 1 ? " block" : " blocks") << " moved to the process whose blocks " << (ch.moved == 1 ? "it touches" : "they touch")
       << " (";
    for (std::size_t k = 0; k < ch.strays.size() && k < 5; ++k)
      os << (k ? ", " : "") << r.c.model.blocks[static_cast<std::size_t>(ch.strays[k])].name;
    os << (ch.strays.size() > 5 ? ", ..." : "") << ")";
  }
  os << " in " << ch.seconds << " s";
  std::cout << os.str() << "\n";
}

// The positions a stage's scale_off measures from: each block's when the stage begins (the whole
// model's state is current on every process then), or, resumed within the stage, those the
// checkpoint kept.
void start_scaling(Run& r, std::size_t index, const CheckpointArrays* saved, const std::string& restart) {
  r.scale_from.clear();
  r.kept_loose.clear();
  r.scaled_at = -1;
  if (!(r.c.stages[index].scale_off > 0.0)) return;
  const Model& m = r.c.model;
  if (!saved) {
    for (std::size_t b = 0; b < m.blocks.size(); ++b) r.scale_from[m.blocks[b].id] = block_mean(m, b);
    return;
  }
  const auto it = saved->find("stage.scale_from");
  if (it == saved->end() || it->second.size() % 3 != 0)
    throw InputError(restart + ": it holds no positions for stage '" + r.c.stages[index].name + "''s scale_off, or they are damaged");
  const std::vector<double>& v = it->second;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
    if (!(v[i] >= 0.0 && v[i] < 2147483647.0))
      throw InputError(restart + ": the positions it holds for stage '" + r.c.stages[index].name + "''s scale_off are damaged");
    r.scale_from[static_cast<BlockId>(static_cast<std::int32_t>(v[i]))] = Vec2(v[i + 1], v[i + 2]);
  }
}

// <out>/scaled_off.csv: every block a scale_off took out so far (a case with scale_off only).
void write_scaled_off(const Run& r) {
  if (!r.root() || std::none_of(r.c.stages.begin(), r.c.stages.end(), [](const StageSpec& s) { return s.scale_off > 0.0; })) return;
  std::ostringstream os;
  os << "# rockdem: blocks taken out by a stage's scale_off (moved further than it from where the stage found them)\n"
     << "stage,stage_name,step,block,block_id,moved_m,area_m2\n";
  os.precision(9);
  for (const ScaledOff& s : r.scaled_off)
    os << s.stage + 1 << "," << r.c.stages[s.stage].name << "," << s.step << "," << s.name << "," << s.id << "," << s.moved << "," << s.area << "\n";
  write_file_atomically(r.out / "scaled_off.csv", os.str());
}

// Steps between two looks for loose blocks in a stage with scale_off.
constexpr long kScaleCheckSteps = 100;

// A stage's scale_off, after a chunk of steps: the blocks that have moved further than it from
// where the stage found them, but those the case holds (Case::held_blocks), are taken out, and
// said on screen and in scaled_off.csv; true if any was. Each block's distance comes from its owner.
bool scale_off(Run& r, std::size_t index) {
  const double limit = r.c.stages[index].scale_off;
  Model& m = r.c.model;
  // The distance of each block beyond the limit, negative for a block the case holds.
  std::vector<double> moved(m.blocks.size(), 0.0);
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    const BlockId id = m.blocks[b].id;
    if (!m.part.owns(static_cast<int>(b))) continue;
    const auto from = r.scale_from.find(id);
    if (from == r.scale_from.end()) continue;
    const double x = (block_mean(m, b) - from->second).norm();
    if (x > limit) moved[b] = std::binary_search(r.c.held_blocks.begin(), r.c.held_blocks.end(), id) ? -x : x;
  }
  if (m.part.decomposed()) r.comm.sum_held(moved.data(), static_cast<int>(moved.size()));
  std::vector<BlockId> ids;
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    if (moved[b] > 0.0) ids.push_back(m.blocks[b].id);
    // A loose block the case holds stays, and may keep the stage from its equilibrium: said once.
    if (moved[b] < 0.0 && r.kept_loose.insert(m.blocks[b].id).second && r.root()) {
      r.progress.end_line();
      std::cerr << "rockdem: warning: block '" << m.blocks[b].name << "' has moved " << -moved[b] << " m in stage '"
                << r.c.stages[index].name << "', more than its scale_off, and is not taken out: a [[boundary]], [[histories]] "
                << "or [direct_shear] entry names it or acts on it\n";
    }
  }
  if (ids.empty()) return false;
  const std::size_t first = r.scaled_off.size();
  r.engine.take_out([&] {
    for (std::size_t b = 0; b < m.blocks.size(); ++b)
      if (moved[b] > 0.0)
        r.scaled_off.push_back({index, m.blocks[b].id, m.blocks[b].name, m.step, moved[b], std::abs(signed_area(block_outline(m, m.blocks[b])))});
    return take_out_blocks(r.c, r.engine.conditions(), ids);
  });
  for (BlockId id : ids) r.scale_from.erase(id);
  // The blocks' work left with them: the owners are checked at the next detection.
  r.owners_due = m.part.decomposed();
  write_scaled_off(r);  // now: a run that stops later keeps the record
  if (!r.root() || r.progress.quiet()) return true;
  r.progress.end_line();
  std::ostringstream os;
  os.precision(3);
  os << "step " << m.step << ": scaled off " << ids.size() << (ids.size() == 1 ? " block" : " blocks") << " that moved more than "
     << limit << " m in stage '" << r.c.stages[index].name << "':";
  for (std::size_t k = first; k < r.scaled_off.size(); ++k)
    os << (k > first ? "," : "") << " " << r.scaled_off[k].name << " (" << r.scaled_off[k].moved << " m, " << r.scaled_off[k].area << " m2)";
  std::cout << os.str() << "\n";
  return true;
}

// `resume`: the stage is taken up from a checkpoint written within it (`restart`): its
// excavation was made before, its relax, clock and the conditions' state come from the file.
void run_stage(Run& r, const StageJointModels& joints, std::size_t index, const StageResume* resume = nullptr,
               const std::string& restart = "") {
  // A stage starts from the whole model's state on every process: an excavation removes blocks
  // and relaxes the forces of their contacts, and boundaries that hold their static reactions
  // take them from the forces of every block they touch.
  if (r.c.model.part.decomposed()) r.comm.collect(r.c.model, -1);
  std::unique_ptr<BoundaryCondition> relax;
  CheckpointArrays saved;
  if (resume) {
    saved = read_checkpoint_arrays(restart);
    if (const auto it = saved.find("stage.relax"); it != saved.end()) {
      auto rc = RelaxCondition::from_progress(it->second, r.c.model.gp.size());
      rc->stages = {r.c.stages[index].name};
      relax = std::move(rc);
    }
  } else {
    excavate(r.c, r.engine.conditions(), r.c.stages[index], &relax);
  }
  r.relax = relax ? static_cast<RelaxCondition*>(relax.get()) : nullptr;
  if (relax) r.engine.add_condition(std::move(relax));
  const StageRunner stage(r.c, r.engine, joints, index, resume != nullptr);
  if (resume) {
    // The stage's setup began the column clocks and the like afresh: where they were comes back.
    restore_condition_states(r.engine, restart);
    r.engine.resume_stage(saved, restart);
  }
  start_scaling(r, index, resume ? &saved : nullptr, restart);
  write_stage_motions(r, index);
  if (resume) r.rec.stage_resumed(static_cast<int>(index) + 1);
  else r.rec.stage_started(static_cast<int>(index) + 1, stage.spec().name);
  const long vtk_every = resume ? resume->vtk_every
                         : r.c.output.vtk_interval > 0 ? r.c.output.vtk_interval
                                                       : std::max(100L, stage.planned_steps() / 25);
  r.progress.stage_started(r.engine, stage, index, contact_count(r), resume != nullptr);
  if (!resume) {  // a resumed stage's first frame and sample were written by the run it continues
    write_vtk(r);
    r.rec.sample();
  }
  r.progress.stepping_started();
  // An excavation takes the removed blocks' work from the processes that held them: the owners
  // are checked at the stage's first detection, and then every kOwnerCheckSteps steps.
  r.owners_due = r.c.model.part.decomposed();
  const long chunk = 10;
  auto last_flush = Clock::now();
  long n = resume ? resume->chunk_start : 0;  // steps of the stage before the chunk under way
  long into = resume ? resume->into_chunk : 0;
  // A resumed chunk is run to its end before the stage's end condition is asked again, as the
  // uninterrupted run did.
  // Nor is it asked right after blocks were taken out: the last step's ratios are from before.
  for (bool resumed = resume != nullptr; resumed || n == r.scaled_at || !stage.done(n); resumed = false) {
    long left = chunk - into;
    // A checkpoint or a signal waits for a contact detection (the next is at most [time]
    // refresh_interval steps away), so that a run restarted from it repeats this one exactly.
    // So does a check of the blocks' owners (a change of owner needs a detection made on the new
    // owners; made again where the run has just made one, it changes nothing).
    auto at_detection = [&] {
      if (r.owners_due) check_owners(r);
      if (r.checkpoint_due || r.signal) write_pending(r, index, n, chunk - left, vtk_every);
    };
    if ((r.checkpoint_due || r.signal || r.owners_due) && r.engine.just_refreshed() && !resumed) at_detection();
    // Single steps without the state check a whole chunk ends with, which the last call makes
    // (run_steps(0) only checks): the checks fall where a run without checkpoints has them.
    while ((r.checkpoint_due || r.signal || r.owners_due) && left > 0) {
      r.engine.run_steps(1, false);
      --left;
      // A detection is at most [time] refresh_interval steps away; a signal does not wait for more
      // than 1,000 (a very long interval): then it makes one, and the restart repeats this run
      // from there, not the run without the signal.
      if (r.signal && ++r.signal_wait >= 1000 && !r.engine.just_refreshed()) r.engine.refresh_contacts();
      if (r.engine.just_refreshed()) at_detection();
    }
    r.engine.run_steps(left);
    into = 0;
    n += chunk;
    if (r.c.stages[index].scale_off > 0.0 && n % kScaleCheckSteps < chunk && scale_off(r, index)) r.scaled_at = n;
    if (n % r.c.output.history_interval < chunk) r.rec.sample();
    if (n % vtk_every < chunk) write_vtk(r);
    // The history on disk keeps up with what the user has been shown, and, quiet or not, is never
    // more than a few seconds behind, so a killed run leaves a readable history.
    const bool shown = r.progress.steps_done(r.engine, stage, n);
    if (shown || Clock::now() - last_flush > std::chrono::seconds(2)) {
      r.rec.flush();
      last_flush = Clock::now();
    }
    if (!r.checkpoint_due) r.checkpoint_due = checkpoint_due(r);
    if (r.c.model.part.decomposed() && n % kOwnerCheckSteps < chunk) r.owners_due = true;
    // Every process stops at the same step (a signal may reach them a little apart).
    const int sig = r.c.model.part.decomposed() ? static_cast<int>(r.comm.max(interrupt_signal().load())) : interrupt_signal().load();
    if (sig) r.signal = sig;
  }
  r.relax = nullptr;
  if (!stage.unconverged().empty() && r.comm.root()) {
    r.progress.end_line();
    std::cerr << "rockdem: warning: " << stage.unconverged() << "\n";
  }
  r.rec.sample();
  write_vtk(r);
  write_scaled_off(r);
  write_stage_checkpoint(r, index);
}

// After an instability: writes the last good state (and the joint record so far) and returns
// the error to throw, naming what was written.
InstabilityError stopped_unstable(Run& r, const InstabilityError& e) {
  r.progress.end_line();
  r.engine.restore(r.engine.last_good());
  const auto path = (r.out / "last_good_state.h5").string();
  with_whole_model(r, [&] { write_checkpoint(r.c.model, path); });  // the state first: it is what to go on from
  write_vtk(r);
  r.rec.close();
  // The joint record up to here is kept, marked incomplete.
  std::string record;
  if (DirectShearRecorder* ds = r.rec.direct_shear(); ds && r.root()) {
    const fs::path partial = ds->write_incomplete(r.out);
    if (!partial.empty()) record = ", the joint record up to then in " + partial.string();
  }
  return InstabilityError(std::string(e.what()) + "\n  last good state (step " + std::to_string(r.c.model.step) +
                          ") written to " + path + " and " + (r.out / "vtk").string() + record);
}

// After SIGINT/SIGTERM, once the state reached has been written as a checkpoint to go on from
// (interrupted_state.h5, at the first contact detection after the signal: write_pending): the
// fields there, the histories and the joint record so far; returns the error to throw, saying
// how to go on.
Interrupted stopped_by_signal(Run& r, int sig, std::size_t stage_index) {
  r.progress.end_line();
  const auto path = (r.out / "interrupted_state.h5").string();
  // No VTK frame here: a restart from the checkpoint writes the series on, and one more frame
  // would make it differ from the uninterrupted run's (the state is in the checkpoint).
  r.rec.close();
  if (DirectShearRecorder* ds = r.rec.direct_shear(); ds && r.root()) ds->write_incomplete(r.out);
  return Interrupted(sig, std::string(sig == 2 ? "interrupted (SIGINT)" : "terminated (SIGTERM)") + " at step " +
                              std::to_string(r.c.model.step) + " (time " + std::to_string(r.c.model.time) + " s) in stage " +
                              std::to_string(stage_index + 1) + " '" + r.c.stages[stage_index].name + "'; state written to " +
                              path + ", histories so far in " + r.out.string() +
                              "\n  to go on from there, run the same case again with --out " + r.out.string() + " --restart " + path +
                              " (or with another --out)");
}

// The outputs of a completed run, its summary and its result.
RunResult finish(Run& r) {
  write_restartable(r, r.out / "final_state.h5", r.c.stages.size(), false);
  r.rec.close();
  DirectShearRecorder* ds = r.rec.direct_shear();
  const fs::path csv = ds && r.root() ? ds->write(r.out) : fs::path();
  r.progress.finished(r.out, csv);
  RunResult result;
  result.history = std::move(r.rec.history());
  if (ds) result.lab = std::move(ds->record());
  result.lab_csv = csv;
  return result;
}

}  // namespace

RunResult run_case(Case& c, const fs::path& out, bool quiet, const std::string& restart, Communication& comm) {
  if (comm.root()) fs::create_directories(out);
  quiet = quiet || !comm.root();
  std::optional<StageResume> resume;
  std::vector<ScaledOff> scaled;
  const std::size_t first_stage = read_restart(c, restart, resume, scaled);
  const StageJointModels joints(c);
  if (first_stage < c.stages.size()) joints.put_in_force(c, first_stage);
  Engine engine(c.model, c.settings, comm);
  for (auto& bc : c.conditions) engine.add_condition(std::move(bc));
  c.conditions.clear();
  // A restart's history begins with the samples its checkpoint carries (an earlier history in
  // the same folder has been moved aside: run_case.hpp).
  Recorder rec(c, engine, out / "history.h5");
  VtkSeries vtk(out / "vtk");
  Progress progress(c, quiet);
  if (!restart.empty()) {
    const CheckpointArrays saved = read_checkpoint_arrays(restart);
    engine.restore_state(saved, restart);
    rec.restore_state(saved, restart);
    restore_condition_states(engine, restart);
    vtk.resume(c.model.time);
    progress.restarted(restart, first_stage, resume.has_value());
  }
  std::optional<DriftResults> drift;
  if (c.drift.enabled) {
    drift.emplace(c, out);
    if (!restart.empty()) drift->restore_state(read_checkpoint_arrays(restart), first_stage);
  }
  progress.run_started(out);
  Run r{c, out, engine, rec, vtk, progress, comm, drift ? &*drift : nullptr, nullptr, false, 0, 0, c.model.step, Clock::now(), {}};
  r.scaled_off = std::move(scaled);
  // A restart reads the state the field started; a new run starts from the field.
  if (restart.empty() && c.in_situ) {
    const InSituReport rep = initialise_in_situ(c.model, *c.in_situ, c.settings.detection);
    if (!quiet)
      std::cout << "in-situ stress: " << rep.zones << " zones, " << rep.contacts << " contacts pre-loaded (largest error "
                << rep.worst_error << " Pa" << (rep.at_strength ? ", " + std::to_string(rep.at_strength) + " at their shear strength" : "")
                << ")\n";
  }
  if (comm.size() > 1) {
    const DecompositionReport d = comm.decompose(c.model, 2.0 * c.settings.detection.distance);
    if (!quiet) {
      std::cout << "decomposed over " << d.processes << " processes (METIS, " << d.seconds << " s): blocks";
      for (long b : d.blocks) std::cout << " " << b;
      std::cout << "; " << d.cut_pairs << " block pairs split; load imbalance " << d.imbalance << "\n";
    }
  }
  std::size_t si = first_stage;
  try {
    for (; si < c.stages.size(); ++si) run_stage(r, joints, si, si == first_stage && resume ? &*resume : nullptr, restart);
  } catch (const InstabilityError& e) {
    throw stopped_unstable(r, e);
  } catch (const Interrupted& e) {
    throw stopped_by_signal(r, e.signal(), si);
  } catch (...) {
    progress.end_line();  // the error message starts on a line of its own
    throw;
  }
  // A signal that came in the last chunks of the run found no step left to stop at.
  if (r.signal && !quiet) std::cout << "rockdem: the signal came as the run ended; its results are complete\n";
  const std::string spent = comm.time_report();
  progress.end_line();
  if (!quiet && !spent.empty()) std::cout << spent << "\n";
  return finish(r);
}

}  // namespace rockdem
