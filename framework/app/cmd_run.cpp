// `rockdem run CASE.toml [--out DIR]`, or `--default` for the built-in direct-shear case. A
// laboratory-test case file (framework/lab/lab_case.hpp) runs as its DEM specimen
// (framework/lab/direct_shear_specimen.hpp).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <chrono>
#include <cstdlib>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "framework/app/command.hpp"
#include "framework/app/result_files.hpp"
#include "framework/app/plot_scripts.hpp"
#include "framework/parallel/mpi_communication.hpp"
#include "framework/parallel/mpi_env.hpp"
#include "framework/simulation/run_case.hpp"
#include "framework/app/cli_contract.hpp"
#include "framework/core/error.hpp"
#include "framework/core/threads.hpp"
#include "framework/core/interrupt.hpp"
#include "framework/io/case_reader.hpp"
#include "framework/io/checkpoint.hpp"
#include "framework/io/output_folder.hpp"
#include "framework/io/toml_values.hpp"
#include "framework/core/params.hpp"
#include "framework/core/units.hpp"
#include "framework/io/block_inspection.hpp"
#include "framework/lab/direct_shear_specimen.hpp"
#include "framework/lab/lab_case.hpp"
#include "rockdem_default_case.hpp"

namespace rockdem {
namespace {

namespace fs = std::filesystem;

// A figure of each stage's applied ground motion beside its CSV (motion_<n>_<stage>.png). The run's
// results do not depend on it: without Debian's python3-matplotlib the run still succeeds, with a note.
void plot_stage_motions(const fs::path& dir, bool quiet) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("motion_", 0) != 0 || e.path().extension() != ".csv") continue;
    const fs::path png = fs::path(e.path()).replace_extension(".png");
    try {
      const std::string script = find_plot_script("plot_motion.py", "ROCKDEM_PLOT_MOTION", "motion plot").string();
      if (run_debian_python({script, e.path().string(), "-o", png.string()}, "motion plot") != 0)
        std::cerr << "note: " << png.string() << " not drawn (plot_motion.py failed); the input is in " << name << "\n";
      else if (!quiet)
        std::cout << "  " << png.filename().string() << "  the ground motion applied (figure)\n";
    } catch (const std::exception& ex) {
      std::cerr << "note: " << png.string() << " not drawn (" << ex.what() << "); the input is in " << name << "\n";
    }
  }
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// SIGINT/SIGTERM ask the stepping loop to stop at the first contact detection after its current
// chunk of steps (run_case writes a checkpoint to go on from and the histories so far, and throws
// Interrupted). A second signal ends the process at once.
extern "C" void request_stop(int sig) {
  interrupt_signal().store(sig);
  std::signal(sig, SIG_DFL);
}

// The entries of `dir`, for a message ("history.h5, vtk/, ...").
std::string folder_listing(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename().string() + (e.is_directory(ec) ? "/" : ""));
  std::sort(names.begin(), names.end());
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "nothing" : s;
}

// Records how a failed run ended; a write failure here (the disk that stopped the run may be
// full) is reported but does not hide the error that ended the run.
template <class Record>
void record_after_error(Record& record, const std::string& status, int code) {
  try {
    record(status, code);
  } catch (const std::exception& e) {
    std::cerr << "rockdem: could not record the end of the run in the manifest: " << e.what() << "\n";
  }
}

// Runs the case and records its end (time, status, exit code) in the manifest and in the root
// attributes of the history files this run wrote, whatever way the run ends.
int run_with_manifest(Case& c, const fs::path& dir, bool quiet, const std::string& restart, Manifest& m, Communication& comm) {
  const auto started = fs::file_time_type::clock::now() - std::chrono::seconds(1);
  auto record = [&](const std::string& status, int code) {
    if (!comm.root()) return;  // process 0 writes the outputs
    close_manifest(dir, m, status, code);
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      const std::string name = e.path().filename().string();
      if (name.rfind("history", 0) == 0 && e.path().extension() == ".h5" && fs::last_write_time(e.path(), ec) >= started)
        stamp_hdf5(e.path(), m);
    }
  };
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  try {
    run_case(c, dir, quiet, restart, comm);
  } catch (const Interrupted& e) {
    record_after_error(record, "interrupted", e.exit_code());
    throw;
  } catch (const InstabilityError&) {
    record_after_error(record, "unstable", 3);
    throw;
  } catch (const InputError&) {
    record_after_error(record, "failed", 2);
    throw;
  } catch (const std::exception& e) {
    // A write failure (disk full, permission): say what is left in the folder.
    record_after_error(record, "failed", 1);
    throw std::runtime_error(std::string(e.what()) + "\n  the run stopped at step " + std::to_string(c.model.step) +
                             " (time " + std::to_string(c.model.time) + " s); kept in " + dir.string() + ": " +
                             folder_listing(dir) + " (the file being written may be incomplete)");
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  record("finished", 0);
  return 0;
}

// A restart into the folder of the run it continues: what that run wrote and this one will write
// again moves into before_restart_<n>/, so nothing is overwritten: history, manifest, case copy,
// final and interrupted states, records, figures, the checkpoints and applied motions of the
// stages still to run, the VTK frames after the restart's step (vtk/, with copies of the .pvd
// collections) and the drift results of the stages still to run (drift/, with copies of the
// files that cover every stage). What the completed stages wrote stays, when the checkpoint is
// this folder's own; the checkpoint restarted from is copied, not moved.
void set_earlier_run_aside(const fs::path& dir, const std::string& restart) {
  if (!fs::exists(dir / "manifest.json")) return;  // an empty folder: nothing came before
  const auto extra = read_checkpoint_scalars(restart);
  const auto it = extra.find("stages_completed");
  const long completed = it == extra.end() ? 0 : static_cast<long>(it->second);
  const long step = read_checkpoint_step(restart);
  int n = 1;
  while (fs::exists(dir / ("before_restart_" + std::to_string(n)))) ++n;
  const fs::path aside = dir / ("before_restart_" + std::to_string(n));
  std::error_code ec;
  const fs::path from = fs::weakly_canonical(restart, ec);
  const bool own = from.parent_path() == fs::weakly_canonical(dir, ec);
  // The number after a file's prefix ("stage_3_..." -> 3), -1 without one.
  const auto number_after = [](const std::string& name, const std::string& prefix) -> long {
    if (name.rfind(prefix, 0) != 0 || name.size() == prefix.size() || !std::isdigit(static_cast<unsigned char>(name[prefix.size()])))
      return -1;
    return std::atol(name.c_str() + prefix.size());
  };
  const auto entries = [](const fs::path& d) {
    std::vector<fs::path> v;
    if (fs::is_directory(d))
      for (const auto& e : fs::directory_iterator(d)) v.push_back(e.path());
    return v;
  };
  fs::create_directory(aside);
  for (const auto& p : entries(dir)) {
    const std::string name = p.filename().string();
    if (name == "joints" || name.rfind("before_restart_", 0) == 0) continue;
    if (name == "vtk" || name == "drift") {
      fs::create_directory(aside / name);
      for (const auto& q : entries(p)) {
        const std::string f = q.filename().string();
        const long k = name == "vtk" ? std::max(number_after(f, "blocks_"), number_after(f, "contacts_"))
                                     : std::max({number_after(f, "contacts_"), number_after(f, "joints_"), number_after(f, "blocks_")});
        const long limit = name == "vtk" ? step : completed;  // vtk frames by step, drift files by stage
        if (!own) fs::rename(q, aside / name / f);  // another run's: all of it
        else if (k < 0) fs::copy_file(q, aside / name / f);  // collections and tables of every stage
        else if (k > limit) fs::rename(q, aside / name / f);
      }
      continue;
    }
    if (own && (number_after(name, "stage_") >= 1 && number_after(name, "stage_") <= completed && p.extension() == ".h5")) continue;
    if (own && number_after(name, "motion_") >= 1 && number_after(name, "motion_") <= completed) continue;
    if (fs::weakly_canonical(p, ec) == from) fs::copy_file(p, aside / name);
    else fs::rename(p, aside / name);
  }
}

// The output folder of a run: refused if it holds something else (unless --overwrite), the
// earlier run's files set aside on a restart, and this run's manifest written.
void prepare_run_folder(const fs::path& dir, const std::string& restart, bool overwrite, bool use_default,
                        const std::string& file, const Case& c, Manifest& m) {
  prepare_output_folder(dir, !restart.empty() ? FolderUse::resume : overwrite ? FolderUse::overwrite : FolderUse::fresh, "--out");
  if (!restart.empty()) set_earlier_run_aside(dir, restart);
  m.command_line = command_line();
  m.case_file = use_default ? std::string("(built-in default case)") : file;
  m.case_text = use_default ? std::string(kDefaultCaseText) : read_text(file);
  for (const auto& st : c.stages) m.stages.push_back(st.name);
  m.restart = restart;
  m.started_utc = utc_now();
  write_manifest(dir, m);
}

const CommandRegistrar reg{Command{
    "run", "run a DEM case file (or the built-in default direct-shear case); under mpirun the blocks are shared among the processes", true,
    [](CLI::App& sub) {
      auto file = std::make_shared<std::string>();
      auto out = std::make_shared<std::string>();
      auto use_default = std::make_shared<bool>(false);
      auto quiet = std::make_shared<bool>(false);
      auto no_plots = std::make_shared<bool>(false);
      sub.add_option("case", *file, "case file (TOML)");
      sub.add_option("--out", *out, "output folder (default: rockdem-output/<case name>)");
      sub.add_flag("--default", *use_default, "run the built-in direct-shear case (test 9, 3 MPa, Coulomb slip)");
      sub.add_flag("--quiet", *quiet, "no progress output");
      sub.add_flag("--no-plots", *no_plots, "no figures of the ground motions applied (their CSV files are written all the same)");
      auto overwrite = std::make_shared<bool>(false);
      sub.add_flag("--overwrite", *overwrite,
                   "empty a non-empty --out folder first (only one an earlier rockdem run wrote, with a manifest.json); "
                   "with --write-case or --write-blocks: replace the files they write");
      auto restart = std::make_shared<std::string>();
      sub.add_option("--restart", *restart,
                     "continue from a checkpoint of an earlier run of the same case: a stage checkpoint (stage_<n>_<name>.h5), "
                     "one within a stage (checkpoint_step_<n>.h5, interrupted_state.h5), or final_state.h5 with stages added to "
                     "the case");
      auto velocity = std::make_shared<std::string>();
      auto mass_dt = std::make_shared<std::string>();
      auto nstages = std::make_shared<int>(0);
      auto write_case = std::make_shared<std::string>();
      sub.add_option("--shear-velocity", *velocity,
                     "laboratory-test cases: speed of the cycles in the DEM run, e.g. \"100 mm/s\" (the report's), or "
                     "\"lab\" for the stages' own velocities; default: the case's [dem] shear_velocity");
      sub.add_option("--mass-scaling-dt", *mass_dt,
                     "laboratory-test cases: scale masses so that this step is stable, e.g. \"1.2 ms\"; \"0 s\" = real masses");
      sub.add_option("--stages", *nstages, "laboratory-test cases: run only the first n test stages")->check(CLI::PositiveNumber);
      sub.add_option("--write-case", *write_case,
                     "laboratory-test cases: write the generated DEM case file (TOML) here and stop");
      auto write_blocks = std::make_shared<std::string>();
      sub.add_option("--write-blocks", *write_blocks,
                     "build the model, write its blocks for inspection to this folder (blocks.vtu, traces.vtu, "
                     "blocks.csv) and stop without running");
      auto checkpoint_every = std::make_shared<std::string>();
      sub.add_option("--checkpoint-every", *checkpoint_every,
                     "checkpoints within stages (checkpoint_step_<n>.h5, to --restart from), every \"N steps\" of the run or every "
                     "wall-clock time such as \"30 min\"; replaces the case's [output] checkpoint_every");
      auto joints = std::make_shared<std::vector<std::string>>();
      sub.add_option("--joint", *joints,
                     "NAME=FILE: the case's [[joints]] entry NAME takes its law, parameters and effects from FILE (a TOML "
                     "table with the keys of a [[joints]] entry, or the JSON of rockdem calibrate/diagnose); where it acts "
                     "stays as in the case; FILE is copied into the output folder (joints/); repeatable");
      auto excavations = std::make_shared<std::vector<std::string>>();
      sub.add_option("--excavate", *excavations,
                     "STAGE=NAME,...: the case's stage STAGE excavates these blocks or groups instead of its own excavate list "
                     "(STAGE= for none), e.g. an overbreak chosen for another realisation (--seed); repeatable");
      auto motions = std::make_shared<std::vector<std::string>>();
      sub.add_option("--motion", *motions,
                     "[STAGE=]NAME[,NAME]: the earthquake stage STAGE plays this [[motions]] entry instead of its own (two "
                     "names for a stage that plays two, each in its entry's direction); without STAGE= every stage that plays a motion does, e.g. --motion "
                     "northridge; repeatable");
      auto pgvs = std::make_shared<std::vector<std::string>>();
      sub.add_option("--pgv", *pgvs,
                     "[STAGE=]VALUE: the earthquake stage STAGE plays its motion scaled to this peak ground velocity, e.g. "
                     "--pgv event_2=\"1 m/s\" (replaces its motion_scale, pga or pgv); without STAGE= every stage that plays "
                     "a motion; repeatable");
      auto seed = std::make_shared<std::string>();
      sub.add_option("--seed", *seed,
                     "rock-mass cases: draw the joint sets with this seed instead of the case's [rock_mass] seed (another "
                     "realisation of the same joint statistics; a whole number from 0 to 2^63 - 1)");
      auto threads = std::make_shared<int>(1);
      sub.add_option("--threads", *threads,
                     "threads of each process for the zone, contact-law, contact-geometry and detection loops (the results "
                     "are the same on any number; under mpirun give each process that many cores, e.g. --bind-to none)")
          ->check(CLI::Range(1, 256))
          ->capture_default_str();
      auto imbalance = std::make_shared<double>(EngineSettings{}.imbalance_limit);
      sub.add_option("--imbalance-limit", *imbalance,
                     "under mpirun: share the blocks out again (METIS, moving as few as it can) when the largest process's work "
                     "exceeds the mean by this factor; 0 never (blocks that moved among another process's blocks still go to it). "
                     "The results are the same either way")
          ->check(CLI::Validator(
              [](std::string& v) -> std::string {
                char* end = nullptr;
                const double x = std::strtod(v.c_str(), &end);
                if (end != v.c_str() && *end == '\0' && (x == 0.0 || (x >= 1.0 && x <= 100.0))) return {};
                return "'" + v + "' is no load imbalance limit: give a factor from 1 to 100 (the largest process's work over the "
                       "mean, e.g. 1.2), or 0 never to share the blocks out again";
              },
              "FACTOR"))
          ->capture_default_str();
      return [file, out, use_default, quiet, no_plots, overwrite, restart, velocity, mass_dt, nstages, write_case,
              write_blocks, joints, checkpoint_every, threads, imbalance, seed, excavations, motions, pgvs]() -> int {
        // Under mpirun every process runs the case (its share of the blocks); process 0 writes.
        const std::unique_ptr<Communication> parallel = make_communication();
        Communication& comm = parallel ? *parallel : serial_communication();
        if (file->empty() && !*use_default) throw InputError("rockdem run: give a case file, or --default for the built-in case");
        const bool lab = !*use_default && fs::exists(*file) && is_lab_test_file(*file);
        const bool lab_options = !velocity->empty() || !mass_dt->empty() || *nstages > 0 || !write_case->empty();
        if (!lab && lab_options) {
          // A syntax error is the message to give, not "these options apply to laboratory-test
          // cases"; else the file and what makes it no laboratory-test case.
          std::string which = "--default is the built-in DEM case";
          if (!*use_default) {
            if (!fs::exists(*file)) throw InputError(*file + ": no such case file");
            const toml::table root = parse_toml_file(*file, "case file");
            std::vector<std::string> why;
            if (!root.contains("joint")) why.push_back("no [joint] table");
            if (!root.contains("stage")) why.push_back("no [[stage]] table");
            if (root.contains("blocks")) why.push_back("[[blocks]], as a DEM case has");
            std::string list;
            for (const auto& w : why) list += (list.empty() ? "" : ", ") + w;
            which = *file + " is no laboratory-test case file: it has " + list;
          }
          throw InputError(which + "; --shear-velocity, --mass-scaling-dt, --stages and --write-case apply to laboratory-test "
                           "case files ([joint] and [[stage]] tables, e.g. cases/direct_shear/test09_mohr_coulomb.toml)");
        }
        CaseOverrides overrides;
        std::map<std::string, std::string>& joint_files = overrides.joint_files;
        for (const auto& a : *joints) {
          const auto eq = a.find('=');
          if (eq == std::string::npos || eq == 0 || eq + 1 == a.size())
            throw InputError("--joint " + a + ": write NAME=FILE, e.g. --joint joints=cases/drift/laws/barton_bandis.toml");
          const std::string name = a.substr(0, eq), f = a.substr(eq + 1);
          if (!fs::is_regular_file(f)) throw InputError("--joint " + a + ": joint file '" + f + "' does not exist");
          if (!joint_files.emplace(name, f).second) throw InputError("--joint " + a + ": joint '" + name + "' is given twice");
        }
        if (!joint_files.empty() && (lab || *use_default))
          throw InputError("rockdem run: --joint applies to DEM case files with [[joints]] entries (a laboratory-test case "
                           "names its one joint in [joint])");
        // NAME,NAME,...: the names of a non-empty list, or `empty_name` thrown for a blank one.
        auto comma_list = [](const std::string& list, const std::string& empty_name) {
          std::vector<std::string> names;
          for (std::size_t at = 0; at <= list.size();) {
            const std::size_t comma = std::min(list.find(',', at), list.size());
            if (comma == at) throw InputError(empty_name);
            names.push_back(list.substr(at, comma - at));
            at = comma + 1;
          }
          return names;
        };
        for (const auto& a : *excavations) {
          const auto eq = a.find('=');
          if (eq == std::string::npos || eq == 0)
            throw InputError("--excavate " + a + ": write STAGE=NAME,... (blocks or groups; STAGE= for none), e.g. --excavate "
                             "excavate=drift");
          const std::string list = a.substr(eq + 1);
          std::vector<std::string> names;
          if (!list.empty()) names = comma_list(list, "--excavate " + a + ": an empty name in the list");
          if (!overrides.excavate.emplace(a.substr(0, eq), std::move(names)).second)
            throw InputError("--excavate " + a + ": stage '" + a.substr(0, eq) + "' is given twice");
        }
        if (!overrides.excavate.empty() && (lab || *use_default))
          throw InputError("rockdem run: --excavate applies to DEM case files with [[stages]] (a laboratory-test case "
                           "excavates nothing)");
        // [STAGE=]REST: the stage ("" for every stage that plays a motion) and the rest.
        auto stage_and_value = [](const std::string& a) -> std::pair<std::string, std::string> {
          const auto eq = a.find('=');
          if (eq == std::string::npos) return {"", a};
          return {a.substr(0, eq), a.substr(eq + 1)};
        };
        auto given_twice = [](const std::string& option, const std::string& stage, const std::string& what) {
          return InputError(option + ": " +
                            (stage.empty() ? "every stage is given " + what + " twice (once without STAGE=; STAGE=... for one stage)"
                                           : "stage '" + stage + "' is given " + what + " twice"));
        };
        if ((!motions->empty() || !pgvs->empty()) && (lab || *use_default))
          throw InputError("rockdem run: --motion and --pgv apply to DEM case files whose [[stages]] play [[motions]] (a "
                           "laboratory-test case is driven by its [[stage]] tables)");
        for (const auto& a : *motions) {
          auto [stage, list] = stage_and_value(a);
          if (a.find('=') == 0) throw InputError("--motion " + a + ": write [STAGE=]NAME, e.g. --motion event_2=northridge");
          std::vector<std::string> names = comma_list(list, "--motion " + a + ": an empty motion name; write [STAGE=]NAME or "
                                                                   "[STAGE=]H,V (names of the case's [[motions]] entries)");
          if (names.size() > 2)
            throw InputError("--motion " + a + ": a stage plays one motion, or two (horizontal, vertical), not " +
                             std::to_string(names.size()));
          if (!overrides.motion.emplace(stage, std::move(names)).second) throw given_twice("--motion " + a, stage, "a motion");
        }
        for (const auto& a : *pgvs) {
          auto [stage, value] = stage_and_value(a);
          if (a.find('=') == 0) throw InputError("--pgv " + a + ": write [STAGE=]VALUE, e.g. --pgv event_2=\"1 m/s\"");
          double v = 0.0;
          try {
            v = parse_quantity(value, Dimension::velocity);
          } catch (const InputError& e) {
            throw InputError("--pgv " + a + ": " + e.what() + " (a peak ground velocity, e.g. \"0.5 m/s\")");
          }
          if (!(v > 0.0)) throw InputError("--pgv " + a + ": the peak ground velocity must be above zero");
          if (!overrides.pgv.emplace(stage, value).second)
            throw given_twice("--pgv " + a, stage, "a peak ground velocity");
        }
        if (!seed->empty()) {
          std::int64_t n = -1;
          const char* end = seed->data() + seed->size();
          const auto [at, ec] = std::from_chars(seed->data(), end, n);
          if (ec != std::errc() || at != end || n < 0)
            throw InputError("--seed " + *seed + ": give a whole number from 0 to " + std::to_string(std::numeric_limits<std::int64_t>::max()) +
                             " (the seed of the case's [rock_mass] joint sets)");
          if (lab || *use_default)
            throw InputError("rockdem run: --seed applies to DEM case files with a [rock_mass] table (the seed of its joint "
                             "sets); " + (*use_default ? std::string("--default is the built-in direct-shear case")
                                                        : *file + " is a laboratory-test case"));
          overrides.rock_mass_seed = n;
        }
        Case c;
        if (lab) {
          const LabTest test = read_lab_test(*file);
          DirectShearOptions o;
          if (*velocity == "lab") o.shear_velocity = 0.0;
          else if (!velocity->empty()) o.shear_velocity = quantity_value(RawValue{*velocity, "--shear-velocity"}, Dimension::velocity, "--shear-velocity");
          if (!mass_dt->empty()) o.mass_scaling_dt = quantity_value(RawValue{*mass_dt, "--mass-scaling-dt"}, Dimension::time, "--mass-scaling-dt");
          o.stages = *nstages;
          if (!write_case->empty()) {
            if (!comm.root()) return 0;
            ResultFilePlan plan;
            plan.input("the case file", *file);
            plan.inputs("a drive file of the case", test.drive_files);
            plan.output("--write-case", *write_case);
            plan.check(*overwrite);
            std::ofstream os(*write_case);
            if (!os) throw InputError("--write-case " + *write_case + ": cannot open for writing");
            os << "# DEM specimen generated by `rockdem run --write-case` from " << *file << "\n" << direct_shear_case_table(test, o) << "\n";
            if (!*quiet) std::cout << "wrote " << *write_case << "\n";
            return 0;
          }
          c = direct_shear_case(test, o);
        } else {
          c = *use_default ? load_case_text(kDefaultCaseText, "built-in default case (cases/direct_shear/test09_coulomb.toml)", ".")
                           : load_case(*file, overrides);
        }
        if (!checkpoint_every->empty()) read_checkpoint_interval(*checkpoint_every, "--checkpoint-every", c.output);
        c.settings.threads = *threads;
        c.settings.imbalance_limit = *imbalance;
        c.output.updating_line = !launched_by_mpi();
        if (comm.root()) {
          // Threads beyond the cores this process may use take turns on them: worse than one.
          const int cores = usable_cores();
          if (*threads > 1 && cores > 0 && *threads > cores)
            c.warnings.push_back("--threads " + std::to_string(*threads) + ": this process may use " + std::to_string(cores) +
                                 (cores == 1 ? " core" : " cores") +
                                 " (its CPU affinity; Open MPI binds each of up to two processes to one core unless given --bind-to none or "
                                 "--map-by slot:PE=" + std::to_string(*threads) + "), so its threads will take turns");
        }
        // Before any output folder is made: a --write-blocks look at the case shows them too.
        if (comm.root())
          for (const auto& w : c.warnings) std::cerr << "rockdem: warning: " << w << "\n";
        if (!write_blocks->empty()) {
          if (!comm.root()) return 0;
          // A folder for inspection files: its three files are replaced only when asked.
          ResultFilePlan plan;
          if (!*use_default) plan.input("the case file", *file);
          for (const char* f : {"blocks.vtu", "traces.vtu", "blocks.csv"})
            plan.output("--write-blocks", (fs::path(*write_blocks) / f).string(), true);
          plan.check(*overwrite);
          const std::string summary = write_blocks_for_inspection(c, lab || *use_default ? "" : *file, *write_blocks);
          if (!*quiet) std::cout << summary << "\n";
          return 0;
        }
        const std::string stem = *use_default ? "default" : fs::path(*file).stem().string();
        const fs::path dir = out->empty() ? fs::path("rockdem-output") / stem : fs::path(*out);
        if (!restart->empty() && !fs::exists(*restart))
          throw InputError("--restart " + *restart + ": checkpoint file does not exist");
        if (!restart->empty() && *overwrite) throw InputError("--restart and --overwrite: a restart continues a folder, give one of them");
        // A restart the case cannot go on from is refused before the folder is touched.
        if (!restart->empty()) check_restart(c, *restart, comm.root());
        Manifest m;
        // Process 0 prepares the folder; a refusal there stops every process.
        std::string refused;
        if (comm.root()) {
          try {
            prepare_run_folder(dir, *restart, *overwrite, *use_default, *file, c, m);
          } catch (const InputError& e) {
            refused = e.what();
          } catch (const std::exception& e) {  // a file system error: every process must hear of it
            refused = "--out " + dir.string() + ": " + e.what();
          }
        }
        if (comm.root() && refused.empty()) {
          // What made the joints goes with the results (the manifest's command line names them).
          for (const auto& [name, f] : joint_files) {
            std::error_code ec;
            fs::create_directories(dir / "joints", ec);
            fs::copy_file(f, dir / "joints" / (name + fs::path(f).extension().string()), fs::copy_options::overwrite_existing, ec);
            if (ec) refused = "cannot copy --joint " + name + "=" + f + " into " + (dir / "joints").string() + ": " + ec.message();
          }
        }
        refused = comm.first_message(refused);
        if (!refused.empty()) throw InputError(refused);
        const int rc = run_with_manifest(c, dir, *quiet, *restart, m, comm);
        if (rc == 0 && comm.root() && !c.motions.empty() && !*no_plots) plot_stage_motions(dir, *quiet);
        return rc;
      };
    }}};

}  // namespace
}  // namespace rockdem
