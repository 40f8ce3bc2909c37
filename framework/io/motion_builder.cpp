// The case builder's part for seismic input: [[motions]] read, processed and checked against the
// mesh, and the motions each stage plays (docs/seismic-input.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/units.hpp"
#include "framework/io/case_builder.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
namespace {

seismic::GroundMotion load_record(const MotionSpec& s) {
  std::string format = s.format;
  if (format == "auto") {
    std::string ext = std::filesystem::path(s.file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    format = ext == ".at2" ? "peer_at2" : "columns";
  }
  if (!std::filesystem::exists(s.file)) throw InputError(s.file_where + ": record file '" + s.file + "' does not exist");
  return format == "peer_at2" ? seismic::load_peer_at2(s.file) : seismic::load_ground_motion(s.file, s.layout);
}

// The highest frequency the deformable zones carry with `n` zones per shear wavelength (the
// longest edge of each zone, its material's shear-wave speed); 0 when the model has no zones.
// Also the zone that sets it, for the message.
struct MeshLimit {
  double frequency = 0.0, zone_size = 0.0, cs = 0.0;
};
MeshLimit mesh_limit(const Model& m, double n) {
  MeshLimit lim;
  for (const Zone& z : m.zones) {
    const auto& mat = *m.materials[static_cast<std::size_t>(z.material)];
    const double cs = std::sqrt(mat.shear_modulus() / mat.density());
    // The zone's size as its longest edge: conservative (a square zone split in two triangles
    // counts as its diagonal), since the direction the waves cross a zone in is not known.
    double size = 0.0;
    for (int k = 0; k < 3; ++k)
      size = std::max(size, (m.gp[static_cast<std::size_t>(z.n[k])].x0 - m.gp[static_cast<std::size_t>(z.n[(k + 1) % 3])].x0).norm());
    const double f = seismic::mesh_frequency_limit(cs, size, n);
    if (lim.frequency == 0.0 || f < lim.frequency) lim = {f, size, cs};
  }
  return lim;
}

std::string hz(double f) {
  std::ostringstream os;
  os.precision(4);
  os << f << " Hz";
  return os.str();
}

}  // namespace

void CaseBuilder::add_motion(const MotionSpec& s) {
  if (std::any_of(c_.motions.begin(), c_.motions.end(), [&](const auto& m) { return m->name == s.name; }))
    throw InputError(s.where + ": a motion named '" + s.name + "' is defined twice");
  try {
    const seismic::GroundMotion record = load_record(s);
    // Strong-motion records are sampled every 0.005 to 0.02 s: their motion reaches 10 to 25 Hz.
    // A record sampled coarser than 0.05 s (below 10 Hz) cannot describe an earthquake: most often
    // its time column or `dt` is in another unit (ms read as s), which would also stretch the
    // event to hours of simulated time.
    constexpr double kCoarsestRecord = 0.05;
    if (record.dt > kCoarsestRecord) {
      const double carried = mesh_limit(c_.model, s.zones_per_wavelength).frequency;
      throw InputError(s.where + ": the record is sampled every " + format_quantity(record.dt, Dimension::time) +
                       " (it carries nothing above " + hz(0.5 / record.dt) + "), too coarse for an earthquake record " +
                       "(0.005 to 0.02 s, content up to 10-25 Hz" +
                       (carried > 0.0 ? "; the mesh here carries up to " + hz(carried) : std::string()) +
                       "). Check the time column's unit or `dt` (milliseconds read as seconds?)");
    }
    seismic::DisplacementProcessing p = s.processing;
    seismic::InputMotion motion = seismic::make_input_motion(record, p, s.scaling);
    // What the model can carry: a tenth (by default) of the shortest shear wavelength per zone.
    const MeshLimit lim = mesh_limit(c_.model, s.zones_per_wavelength);
    std::string mesh_note = "; no zones: rigid blocks carry no wavelength limit";
    if (lim.frequency > 0.0) {
      const double carried = p.f_high > 0.0 ? p.f_high : seismic::power_frequency(motion.acc, motion.dt, 0.99);
      const std::string why = "zones up to " + format_quantity(lim.zone_size, Dimension::length) + " with Cs = " +
                              format_quantity(lim.cs, Dimension::velocity) + " carry " +
                              std::to_string(static_cast<int>(s.zones_per_wavelength)) + " zones per wavelength up to " +
                              hz(lim.frequency);
      if (carried > lim.frequency) {
        if (s.refuse_above_mesh)
          throw InputError(s.where + ": the record carries frequencies up to " + hz(carried) +
                           (p.f_high > 0.0 ? " (filter.high)" : " (99 % of its power)") + ", above what the mesh carries: " +
                           why + ". Low-pass it (filter = { high = \"" + hz(lim.frequency) +
                           "\" }), use above_mesh = \"filter\", or make the zones smaller");
        p.f_high = lim.frequency;
        motion = seismic::make_input_motion(record, p, s.scaling);
        mesh_note = "; low-pass at " + hz(lim.frequency) + " by the mesh (" + why + ", the record carried " + hz(carried) + ")";
      } else {
        mesh_note = "; within the mesh limit (" + why + ")";
      }
    }
    motion.name = s.name;
    motion.type = s.type;
    motion.direction = s.direction;
    motion.processing += mesh_note;
    c_.motions.push_back(std::make_shared<const seismic::InputMotion>(std::move(motion)));
  } catch (const InputError& e) {
    const std::string what = e.what();
    // Messages from the record reader already name the file and line.
    throw InputError(what.rfind(s.file, 0) == 0 || what.rfind(s.where, 0) == 0 ? what : s.where + ": " + what);
  }
}

void CaseBuilder::resolve_motions(const StageInput& s, StageSpec& stage) const {
  for (std::size_t i = 0; i < s.motions.size(); ++i) {
    const auto it = std::find_if(c_.motions.begin(), c_.motions.end(), [&](const auto& m) { return m->name == s.motions[i]; });
    if (it == c_.motions.end())
      throw InputError(s.motion_wheres[i] + ": no motion named '" + s.motions[i] + "'; motions: " +
                       (c_.motions.empty() ? std::string("(none: add [[motions]])")
                                           : join_names(c_.motions, [](const auto& m) { return m->name; })));
    stage.motions.push_back({static_cast<int>(it - c_.motions.begin()), 1.0});
  }
  if (stage.motions.empty()) return;
  // A target peak scales the first motion to it; the others keep their ratio to the first.
  const double f = c_.motions[static_cast<std::size_t>(stage.motions.front().index)]->factor_for(s.motion_scaling);
  for (auto& m : stage.motions) m.factor = f;
  // A scaling that leaves the Earth's ground motions behind is a slip of a unit or a digit (pgv =
  // "50 m/s", motion_scale = 100), not a study: refused before a run that would only crush the
  // model. The largest recorded peaks are about 4 g, 3-4 m/s and 10 m (the 2008 Iwate-Miyagi
  // PGA; Chi-Chi 1999 TCU068's PGV and PGD); the limits sit above them.
  constexpr double kMaxPga = 5.0 * 9.80665, kMaxPgv = 5.0, kMaxPgd = 15.0;
  for (const auto& m : stage.motions) {
    const seismic::InputMotion& mo = *c_.motions[static_cast<std::size_t>(m.index)];
    const double pga = m.factor * mo.pga(), pgv = m.factor * mo.pgv(), pgd = m.factor * mo.pgd();
    std::vector<std::string> over;
    if (pgv > kMaxPgv) over.push_back("PGV " + format_quantity(pgv, Dimension::velocity) + " (more than 5 m/s)");
    if (pga > kMaxPga) over.push_back("PGA " + format_quantity(pga / 9.80665, Dimension::dimensionless) + " g (more than 5 g)");
    if (pgd > kMaxPgd) over.push_back("peak displacement " + format_quantity(pgd, Dimension::length) + " (more than 15 m)");
    if (over.empty()) continue;
    std::string what = over.front();
    for (std::size_t i = 1; i < over.size(); ++i) what += (i + 1 == over.size() ? " and " : ", ") + over[i];
    const std::string where = !s.motion_scaling_where.empty() ? s.motion_scaling_where : s.motion_wheres.front();
    throw InputError(where + ": stage '" + stage.name + "' would play motion '" + mo.name + "' at " + what +
                     ", beyond any recorded earthquake (the largest: about 4 g, 3-4 m/s, 10 m); the motion as read has PGA " +
                     format_quantity(mo.pga() / 9.80665, Dimension::dimensionless) + " g and PGV " + format_quantity(mo.pgv(), Dimension::velocity) +
                     ", scaled by " + format_quantity(m.factor, Dimension::dimensionless) +
                     ". Check the unit of the record ([[motions]] unit) and the target (e.g. pgv = \"0.5 m/s\", pga = \"0.3 g\")");
  }
}

void CaseBuilder::check_stage_motions() {
  for (const StageSpec& st : c_.stages) {
    std::vector<BoundaryCondition::StageMotion> played;
    for (const auto& m : st.motions) played.push_back({c_.motions[static_cast<std::size_t>(m.index)].get(), m.factor});
    int takers = 0;
    for (auto& bc : c_.conditions) {
      if (!bc->active_in(st.name)) continue;
      try {
        bc->set_motions(played);
      } catch (const InputError& e) {
        throw InputError(c_.file + ": stage '" + st.name + "': " + e.what());
      }
      takers += bc->takes_motions() ? 1 : 0;
      bc->set_motions({});
    }
    if (!played.empty() && takers == 0)
      throw InputError(c_.file + ": stage '" + st.name + "' plays motion '" + played.front().motion->name +
                       "' but no boundary takes it in that stage: add a [[boundary]] with type = \"seismic\" at the "
                       "model's base (and free_field on its sides) active in the stage");
  }
}

}  // namespace rockdem
