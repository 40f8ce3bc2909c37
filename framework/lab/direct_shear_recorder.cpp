#include "framework/lab/direct_shear_recorder.hpp"

#include <vector>

#include <algorithm>
#include <sstream>

#include "framework/core/error.hpp"

namespace rockdem {
namespace fs = std::filesystem;

DirectShearRecorder::DirectShearRecorder(const Case& c, const Engine& e, History& h) : c_(c), e_(e) {
  ds_[0] = h.define("joint_shear_stress", "Pa", "loading-block contact force over the nominal joint length");
  ds_[1] = h.define("joint_shear_displacement", "m", "loading-block displacement in the shear stage");
  ds_[2] = h.define("joint_normal_displacement", "m", "top-block bottom face minus bottom-block top face, mean vertical displacement");
}

void DirectShearRecorder::stage_started(const std::string& name) {
  test_stage_ = 0;
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

void DirectShearRecorder::sample(History& h) {
  const Model& m = c_.model;
  const auto& d = c_.direct_shear;
  // In a decomposed run each loader's contact force comes from the process owning it, and the
  // displacements from process 0, where the recorder has made the state current; the sums below
  // add one non-zero part each, so the values are the serial run's.
  const Communication& comm = e_.communication();
  const bool here = !m.part.decomposed() || comm.root();
  std::vector<double> v{here ? m.blocks[d.loader].xc.x() - loader_x0_ : 0.0, here ? normal_disp() - normal0_ : 0.0};
  v.push_back(m.part.owns(d.loader) ? e_.contact_force_on(d.loader).x() : 0.0);
  for (int l : d.other_loaders) v.push_back(m.part.owns(l) ? e_.contact_force_on(l).x() : 0.0);
  comm.sum_held(v.data(), static_cast<int>(v.size()));
  double fx = v[2];
  for (std::size_t k = 3; k < v.size(); ++k) fx += v[k];
  const double tau = -fx / d.joint_length;
  const double us = v[0], un = v[1];
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
  h.set(ds_[0], tau);
  h.set(ds_[1], test_stage_ ? us : 0.0);
  h.set(ds_[2], test_stage_ ? un : 0.0);
  if (test_stage_) {
    MeasurementRow r;
    r.time_s = m.time - t0_;
    r.stage = test_stage_;
    r.normal_stress_MPa = d.normal_stresses[static_cast<std::size_t>(test_stage_ - 1)] / 1e6;
    r.shear_disp_mm = us * 1e3;
    r.shear_stress_MPa = tau / 1e6;
    r.normal_disp_mm = un * 1e3;
    record_.rows.push_back(r);
  }
}

std::map<std::string, std::vector<double>> DirectShearRecorder::saved_state() const {
  std::map<std::string, std::vector<double>> a;
  a["lab_record.t0"] = {t0_};
  // Where the stage under way measures from, for a checkpoint written within it.
  a["lab_record.stage_reference"] = {static_cast<double>(test_stage_), loader_x0_, normal0_};
  auto& t = a["lab_record.time_s"];
  auto& st = a["lab_record.stage"];
  auto& sd = a["lab_record.shear_disp_mm"];
  auto& ss = a["lab_record.shear_stress_MPa"];
  auto& nd = a["lab_record.normal_disp_mm"];
  auto& ns = a["lab_record.normal_stress_MPa"];
  for (const MeasurementRow& r : record_.rows) {
    t.push_back(r.time_s);
    st.push_back(r.stage);
    sd.push_back(r.shear_disp_mm);
    ss.push_back(r.shear_stress_MPa);
    nd.push_back(r.normal_disp_mm);
    ns.push_back(r.normal_stress_MPa);
  }
  return a;
}

void DirectShearRecorder::restore_state(const std::map<std::string, std::vector<double>>& a, const std::string& file) {
  const auto t0 = a.find("lab_record.t0");
  if (t0 == a.end()) return;
  if (t0->second.size() != 1) throw InputError(file + ": its joint test record is incomplete (/arrays/lab_record.t0)");
  const char* names[6] = {"lab_record.time_s", "lab_record.stage", "lab_record.shear_disp_mm", "lab_record.shear_stress_MPa",
                          "lab_record.normal_disp_mm", "lab_record.normal_stress_MPa"};
  const std::vector<double>* col[6];
  for (int k = 0; k < 6; ++k) {
    const auto it = a.find(names[k]);
    if (it == a.end() || (k > 0 && it->second.size() != col[0]->size()))
      throw InputError(file + ": its joint test record is incomplete (/arrays/" + names[k] + ")");
    col[k] = &it->second;
  }
  t0_ = t0->second.at(0);
  if (const auto ref = a.find("lab_record.stage_reference"); ref != a.end() && ref->second.size() == 3) {
    test_stage_ = static_cast<int>(ref->second[0]);
    loader_x0_ = ref->second[1];
    normal0_ = ref->second[2];
  }
  record_.rows.clear();
  for (std::size_t i = 0; i < col[0]->size(); ++i)
    record_.rows.push_back(MeasurementRow{(*col[0])[i], static_cast<int>((*col[1])[i]), (*col[5])[i], (*col[2])[i], (*col[3])[i],
                                          (*col[4])[i]});
}

fs::path DirectShearRecorder::write(const fs::path& dir) {
  return write_record(dir / (c_.direct_shear.specimen + ".csv"), "");
}

fs::path DirectShearRecorder::write_incomplete(const fs::path& dir) {
  return write_record(dir / (c_.direct_shear.specimen + ".incomplete.csv"),
                      "incomplete: the run stopped (see the message of rockdem run)");
}

double DirectShearRecorder::mean_y(const std::vector<int>& pts) const {
  double s = 0.0;
  for (int g : pts) s += c_.model.gp[g].x.y() - c_.model.gp[g].x0.y();
  return pts.empty() ? 0.0 : s / static_cast<double>(pts.size());
}
double DirectShearRecorder::normal_disp() const {
  return mean_y(c_.direct_shear.top_face) - mean_y(c_.direct_shear.bottom_face);
}

fs::path DirectShearRecorder::write_record(const fs::path& path, const std::string& status) {
  if (record_.rows.empty()) return {};
  record_.metadata = {{"specimen", c_.direct_shear.specimen},
                      {"joint_length_m", std::to_string(c_.direct_shear.joint_length)},
                      {"source", "rockdem"},
                      {"model", "dem"},
                      {"case", c_.file}};
  for (const auto& kv : c_.direct_shear.metadata) record_.metadata.push_back(kv);
  if (!status.empty()) record_.metadata.emplace_back("status", status);
  write_measurement_csv(path.string(), record_);
  return path;
}

}  // namespace rockdem
