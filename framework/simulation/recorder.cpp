#include "framework/simulation/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "framework/core/error.hpp"

namespace rockdem {
namespace fs = std::filesystem;

Recorder::Recorder(const Case& c, const Engine& e, const fs::path& history_file) : c_(c), e_(e) {
  stage_id_ = h_.define("stage", "", "index of the stage (1-based)");
  for (const auto& s : c.histories) h_.define(s.name, s.unit, s.description);
  if (c.direct_shear.enabled) {
    ds_[0] = h_.define("joint_shear_stress", "Pa", "loading-block contact force over the nominal joint length");
    ds_[1] = h_.define("joint_shear_displacement", "m", "loading-block displacement in the shear stage");
    ds_[2] = h_.define("joint_normal_displacement", "m", "top-block bottom face minus bottom-block top face, mean vertical displacement");
  }
  h_.open(history_file.string());
}

void Recorder::stage_started(int index, const std::string& name) {
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

void Recorder::sample() {
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

double Recorder::mean_y(const std::vector<int>& pts) const {
  double s = 0.0;
  for (int g : pts) s += c_.model.gp[g].x.y() - c_.model.gp[g].x0.y();
  return pts.empty() ? 0.0 : s / static_cast<double>(pts.size());
}
double Recorder::normal_disp() const { return mean_y(c_.direct_shear.top_face) - mean_y(c_.direct_shear.bottom_face); }

double Recorder::value(const HistorySpec& s) const {
  const Model& m = c_.model;
  switch (s.quantity) {
    case HistorySpec::Quantity::contact_force: return e_.contact_force_on(s.block)[s.component];
    case HistorySpec::Quantity::block_displacement: {
      const Block& b = m.blocks[s.block];
      return s.component == 2 ? b.theta : (b.xc - b.xc0)[s.component];
    }
    case HistorySpec::Quantity::block_velocity: return m.blocks[s.block].vc[s.component];
    case HistorySpec::Quantity::face_displacement: {
      double sum = 0.0;
      for (int g : s.points) sum += (m.gp[g].x - m.gp[g].x0)[s.component];
      return s.points.empty() ? 0.0 : sum / static_cast<double>(s.points.size());
    }
    case HistorySpec::Quantity::unbalanced_ratio: return e_.unbalanced_ratio();
    case HistorySpec::Quantity::kinetic_energy: return e_.kinetic_energy();
    case HistorySpec::Quantity::time_step: return e_.dt();
  }
  return 0.0;
}

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

}  // namespace rockdem
