#include "framework/mechanics/history_quantities.hpp"

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/mechanics/engine.hpp"

namespace rockdem {

HistoryQuantities& HistoryQuantities::instance() {
  static HistoryQuantities q;
  return q;
}

namespace {

double contact_force(const Model&, const Engine& e, const HistoryTarget& t) {
  return e.contact_force_on(t.block)[t.component];
}

double block_displacement(const Model& m, const Engine&, const HistoryTarget& t) {
  const Block& b = m.blocks[t.block];
  return t.component == 2 ? b.theta : (b.xc - b.xc0)[t.component];
}

double block_velocity(const Model& m, const Engine&, const HistoryTarget& t) { return m.blocks[t.block].vc[t.component]; }

double face_displacement(const Model& m, const Engine&, const HistoryTarget& t) {
  double sum = 0.0;
  for (int g : t.points) sum += (m.gp[g].x - m.gp[g].x0)[t.component];
  return t.points.empty() ? 0.0 : sum / static_cast<double>(t.points.size());
}

const std::vector<std::string> kXY{"x", "y"};

// The energy balance's terms (energy_balance.hpp), in the order of `energy`'s components.
double energy_term(const Model&, const Engine& e, const HistoryTarget& t) {
  const EnergyTerms& b = e.energy();
  const double terms[] = {b.kinetic, b.strain, b.contact, b.gravity_work, b.boundary_work, b.slip, b.damping, b.work_in(),
                          b.accounted(), b.imbalance(), b.refresh};
  return terms[t.component];
}

// name, unit, description, needs block, rigid only, needs face, components, reduction, measure
const HistoryQuantityRegistrar contact_force_q{HistoryQuantity{
    "contact_force", "N/m", "sum of the contact forces on a block, x or y", true, false, false, kXY,
    Reduction::owner, contact_force}};
const HistoryQuantityRegistrar block_displacement_q{HistoryQuantity{
    "block_displacement", "m", "rigid-block centroid displacement, x or y [m], or rotation [rad]", true, true,
    false, {"x", "y", "rotation"}, Reduction::state, block_displacement}};
const HistoryQuantityRegistrar block_velocity_q{HistoryQuantity{
    "block_velocity", "m/s", "rigid-block centroid velocity, x or y", true, true, false, kXY, Reduction::state,
    block_velocity}};
const HistoryQuantityRegistrar face_displacement_q{HistoryQuantity{
    "face_displacement", "m", "mean displacement of the gridpoints of a block face, x or y", true, false, true, kXY,
    Reduction::state, face_displacement}};
const HistoryQuantityRegistrar unbalanced_ratio_q{HistoryQuantity{
    "unbalanced_ratio", "", "unbalanced force over applied force", false, false, false, {}, Reduction::global,
    [](const Model&, const Engine& e, const HistoryTarget&) { return e.unbalanced_ratio(); }}};
const HistoryQuantityRegistrar block_unbalanced_ratio_q{HistoryQuantity{
    "block_unbalanced_ratio", "", "largest unbalanced-force ratio of a single free rigid block", false, false, false, {},
    Reduction::global, [](const Model&, const Engine& e, const HistoryTarget&) { return e.block_unbalanced_ratio(); }}};
const HistoryQuantityRegistrar max_speed_q{HistoryQuantity{
    "max_speed", "m/s", "largest gridpoint speed in the model (a check: far above the input's and free fall's, it is numerical)",
    false, false, false, {}, Reduction::global, [](const Model&, const Engine& e, const HistoryTarget&) { return e.max_speed(); }}};
const HistoryQuantityRegistrar kinetic_energy_q{HistoryQuantity{
    "kinetic_energy", "J/m", "kinetic energy of the model", false, false, false, {}, Reduction::global,
    [](const Model&, const Engine& e, const HistoryTarget&) { return e.kinetic_energy(); }}};
const HistoryQuantityRegistrar energy_q{HistoryQuantity{
    "energy", "J/m",
    "energy balance since the first sample: kinetic (whole-step, physical masses), strain (work taken by the zones), "
    "contact (elastic energy in the contacts, change), gravity_work, boundary_work, slip (dissipated by joint slip), "
    "damping (dissipated), work_in (gravity + boundary), accounted (stored + dissipated), imbalance (work_in - accounted), "
    "refresh (not a term: the contacts' elastic energy the contact refreshes changed, which no force did and so is in "
    "the imbalance)",
    false, false, false,
    {"kinetic", "strain", "contact", "gravity_work", "boundary_work", "slip", "damping", "work_in", "accounted",
     "imbalance", "refresh"},
    Reduction::global, energy_term}};
const HistoryQuantityRegistrar energy_balance_error_q{HistoryQuantity{
    "energy_balance_error", "",
    "energy imbalance (work in - stored - dissipated) over the largest magnitude any term has reached", false, false,
    false, {}, Reduction::global, [](const Model&, const Engine& e, const HistoryTarget&) { return e.energy().error; }}};
const HistoryQuantityRegistrar time_step_q{HistoryQuantity{
    "time_step", "s", "time step", false, false, false, {}, Reduction::global,
    [](const Model&, const Engine& e, const HistoryTarget&) { return e.dt(); }}};

}  // namespace
}  // namespace rockdem
