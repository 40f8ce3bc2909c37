#include "framework/simulation/drift_results.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "framework/core/error.hpp"
#include "framework/geometry/polygon.hpp"
#include "framework/io/output_folder.hpp"
#include "framework/io/vtk_output.hpp"
#include "framework/model/block_outline.hpp"

namespace rockdem {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kWallNames[4] = {"crown", "invert", "left_springline", "right_springline"};

// "<n>_<stage>": the part of a stage's file names after their prefix (contacts_, joints_, blocks_).
std::string stage_tag(std::size_t stage_number, const std::string& name) { return std::to_string(stage_number) + "_" + name; }

double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Where the ray from `c` along `dir` leaves the polygon (its farthest crossing).
Vec2 ray_exit(const std::vector<Vec2>& poly, const Vec2& c, const Vec2& dir) {
  double best = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    const Vec2 e = b - a;
    const double den = dir.x() * e.y() - dir.y() * e.x();
    if (std::abs(den) < 1e-300) continue;
    const Vec2 w = a - c;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;   // along the ray
    const double s = (w.x() * dir.y() - w.y() * dir.x()) / den;  // along the edge
    if (s >= -1e-12 && s <= 1 + 1e-12 && t > best) best = t;
  }
  return c + best * dir;
}

// Hydraulic aperture of a joint from its normal displacement (opening positive): the aperture at
// zero normal displacement plus the opening, never below the residual aperture.
double aperture(const DriftSpec& d, double u_n) { return std::max(d.residual_aperture, d.initial_aperture + u_n); }

// A contact's share of its joint's length for the flow: a touching contact's length is its own
// part of the interface (the parts of the contacts of both blocks tile it); an open contact's is
// its own stretch, which the facing contacts of the other block cover again, hence half of it.
double flow_length(const Contact& c) { return c.response.open || c.pretouch_gap > 0.0 ? 0.5 * c.length : c.length; }

// The joint set a contact acts on: the label of the other block's edge, if it is a joint's trace
// (not a rock bridge or a glued cut); null otherwise.
const EdgeLabel* joint_of(const Model& m, const Contact& c) {
  const int label = m.blocks[static_cast<std::size_t>(c.other)].edge_label(c.edge);
  if (label < 0) return nullptr;
  const EdgeLabel& l = m.contacts.edge_labels[static_cast<std::size_t>(label)];
  return l.joint.empty() || l.bridge ? nullptr : &l;
}

std::string format(double v) {
  if (!std::isfinite(v)) return "nan";
  std::ostringstream os;
  os << std::setprecision(9) << v;
  return os.str();
}

}  // namespace

DriftResults::DriftResults(const Case& c, fs::path out) : c_(c), dir_(std::move(out) / "drift") {
  const DriftSpec& d = c.drift;
  Polygon outline(d.outline.begin(), d.outline.end());
  centre_ = polygon_centroid(outline);
  radius_ = std::sqrt(std::abs(signed_area(outline)) / std::numbers::pi);
  const Vec2 dirs[4] = {{0, 1}, {0, -1}, {-1, 0}, {1, 0}};
  for (int k = 0; k < 4; ++k) wall_points_[static_cast<std::size_t>(k)] = ray_exit(d.outline, centre_, dirs[k]);
  for (const EdgeLabel& l : c.model.contacts.edge_labels)
    if (!l.joint.empty() && !l.bridge && std::find(sets_.begin(), sets_.end(), l.joint) == sets_.end()) sets_.push_back(l.joint);
}

std::pair<double, double> DriftResults::since_reference(const Contact& c) const {
  const auto r = ref_.contacts.find(c.key);
  if (r == ref_.contacts.end()) return {c.response.u_s, c.response.u_n};
  return {c.response.u_s - r->second.first, c.response.u_n - r->second.second};
}

// The columns of events.csv after stage, name, kind and time, in the file's order; stage_ended
// fills exactly these (checked), the checkpoint keeps the rows in this order.
std::vector<std::string> DriftResults::columns() const {
  std::vector<std::string> cols{"fallen_area_m2", "fallen_blocks", "frame_rotation_rad", "frame_x_m", "frame_y_m",
                                "horizontal_convergence_m", "k_xx_m2", "k_xx_ratio", "k_xy_m2", "k_yy_m2", "k_yy_ratio",
                                "loosened_contacts", "loosened_extent_m", "max_slip_near_m", "unbalanced_ratio", "vertical_convergence_m"};
  for (const char* w : kWallNames) cols.push_back(std::string(w) + "_inward_m");
  for (const std::string& s : sets_)
    for (const char* f : {"max_slip_", "max_slip_near_", "mean_slip_near_", "max_opening_near_"}) cols.push_back(f + s + "_m");
  std::sort(cols.begin(), cols.end());
  return cols;
}

double DriftResults::distance_to_wall(const Vec2& p) const {
  const auto& o = c_.drift.outline;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < o.size(); ++i) d = std::min(d, segment_distance(p, o[i], o[(i + 1) % o.size()]));
  return point_in_polygon(p, o) ? -d : d;
}

void DriftResults::take_reference(const Model& m) {
  ref_ = Reference{};
  for (const Contact& c : m.contacts.items) ref_.contacts[c.key] = {c.response.u_s, c.response.u_n};
  for (const Block& b : m.blocks) {
    ref_.centroids[b.id] = polygon_centroid(block_outline(m, b));
    for (int i = b.first_gp; i < b.first_gp + b.n_gp; ++i) {
      const GridPoint& g = m.gp[static_cast<std::size_t>(i)];
      if (distance_to_wall(g.x) <= c_.drift.near) continue;
      ref_.far_block.push_back(b.id);
      ref_.far_local.push_back(g.local);
      ref_.far_x.push_back(g.x);
    }
  }
  // The wall points: the boundary gridpoint of a remaining block nearest to each, within a tenth
  // of the radius (none if the wall there has fallen in or the outline was not excavated).
  for (std::size_t k = 0; k < 4; ++k) {
    double best = 0.1 * radius_;
    for (const Block& b : m.blocks)
      for (int g : b.boundary) {
        const GridPoint& p = m.gp[static_cast<std::size_t>(g)];
        const double dist = (p.x - wall_points_[k]).norm();
        if (dist < best) {
          best = dist;
          ref_.wall_block[k] = b.id;
          ref_.wall_local[k] = p.local;
          ref_.wall_x[k] = p.x;
          ref_.wall_found[k] = true;
        }
      }
  }
  ref_.taken = true;
}

bool DriftResults::has_fallen(BlockId id) const {
  return std::any_of(fallen_.begin(), fallen_.end(), [&](const Fallen& f) { return f.id == id; });
}

void DriftResults::stage_ended(const Model& m, std::size_t index, double ratio) {
  const DriftSpec& d = c_.drift;
  if (index < d.reference_stage) return;
  if (index == d.reference_stage) {
    take_reference(m);
    fallen_.clear();
    rows_.clear();
  }
  if (!ref_.taken) throw InputError(c_.file + ": [drift] has no reference state (restart from a checkpoint written before it?)");
  const StageSpec& st = c_.stages[index];
  Row row;
  row.stage = index + 1;
  row.name = st.name;
  row.kind = index == d.reference_stage ? "reference" : !st.motions.empty() ? "event" : "rest";
  row.time = m.time;
  auto& v = row.values;
  v["unbalanced_ratio"] = ratio;

  // Joints: slip and opening since the reference, per set, near the drift and everywhere.
  const double near_area = std::numbers::pi * ((radius_ + d.near) * (radius_ + d.near) - radius_ * radius_);
  double kxx = 0, kyy = 0, kxy = 0, loosened_extent = 0.0, max_slip_near = 0.0;
  long loosened_count = 0;
  std::map<std::string, double> set_max_slip, set_max_slip_near, set_sum_slip_near, set_len_near, set_max_open_near;
  for (const std::string& s : sets_) set_max_slip[s] = set_max_slip_near[s] = set_sum_slip_near[s] = set_len_near[s] = set_max_open_near[s] = 0.0;
  const std::vector<JointRecord> joints = joint_records(m);
  for (const JointRecord& r : joints) {
    const std::string& set = sets_[static_cast<std::size_t>(r.set)];
    set_max_slip[set] = std::max(set_max_slip[set], std::abs(r.slip));
    if (std::abs(r.slip) > d.loosened || r.opening > d.loosened) {
      loosened_extent = std::max(loosened_extent, r.wall);
      ++loosened_count;
    }
    if (r.wall > d.near) continue;
    set_max_slip_near[set] = std::max(set_max_slip_near[set], std::abs(r.slip));
    set_sum_slip_near[set] += std::abs(r.slip) * r.length;
    set_len_near[set] += r.length;
    set_max_open_near[set] = std::max(set_max_open_near[set], r.opening);
    max_slip_near = std::max(max_slip_near, std::abs(r.slip));
    // Parallel plates (Snow 1969): each joint adds (a^3/12) per unit length times its length over
    // the area, along its direction t: k += (a^3/12) L/A (I - n n^T).
    const double w = r.aperture * r.aperture * r.aperture / 12.0 * r.flow_length / near_area;
    const Vec2& n = r.normal;
    kxx += w * (1.0 - n.x() * n.x());
    kyy += w * (1.0 - n.y() * n.y());
    kxy += w * (-n.x() * n.y());
  }
  if (index == d.reference_stage) ref_.k = {kxx, kyy, kxy};
  v["max_slip_near_m"] = max_slip_near;
  for (const std::string& s : sets_) {
    v["max_slip_" + s + "_m"] = set_max_slip[s];
    v["max_slip_near_" + s + "_m"] = set_max_slip_near[s];
    v["mean_slip_near_" + s + "_m"] = set_len_near[s] > 0.0 ? set_sum_slip_near[s] / set_len_near[s] : 0.0;
    v["max_opening_near_" + s + "_m"] = set_max_open_near[s];
  }
  v["loosened_contacts"] = static_cast<double>(loosened_count);
  v["loosened_extent_m"] = loosened_extent;
  v["k_xx_m2"] = kxx;
  v["k_yy_m2"] = kyy;
  v["k_xy_m2"] = kxy;
  v["k_xx_ratio"] = ref_.k[0] > 0.0 ? kxx / ref_.k[0] : kNaN;
  v["k_yy_ratio"] = ref_.k[1] > 0.0 ? kyy / ref_.k[1] : kNaN;

  // The rigid motion of the rock mass since the reference: an earthquake moves the whole model
  // with the ground (its residual displacement) and, with viscous boundaries that hold no rigid
  // mode, may turn it a little; neither is motion of the rock around the drift. The frame is the
  // rotation and translation that best map the far field's gridpoints from the reference onto
  // their present places (least squares: the 2D Kabsch/Procrustes solution); `back` takes a
  // present position into the reference's frame, where everything below is measured.
  std::map<BlockId, int> position;
  for (std::size_t i = 0; i < m.blocks.size(); ++i) position[m.blocks[i].id] = static_cast<int>(i);
  std::vector<std::pair<Vec2, Vec2>> pairs;  // (reference, now)
  for (std::size_t k = 0; k < ref_.far_x.size(); ++k)
    if (const auto it = position.find(ref_.far_block[k]); it != position.end()) {
      const Block& b = m.blocks[static_cast<std::size_t>(it->second)];
      pairs.emplace_back(ref_.far_x[k], m.gp[static_cast<std::size_t>(b.first_gp + static_cast<int>(ref_.far_local[k]))].x);
    }
  Vec2 pbar = Vec2::Zero(), qbar = Vec2::Zero();
  double theta = 0.0;
  if (!pairs.empty() && index != d.reference_stage) {  // at the reference the frame is the identity
    for (const auto& [p, q] : pairs) {
      pbar += p;
      qbar += q;
    }
    pbar /= static_cast<double>(pairs.size());
    qbar /= static_cast<double>(pairs.size());
    double sdot = 0.0, scross = 0.0;
    for (const auto& [p, q] : pairs) {
      const Vec2 a = p - pbar, b = q - qbar;
      sdot += a.dot(b);
      scross += a.x() * b.y() - a.y() * b.x();
    }
    theta = std::atan2(scross, sdot);
  }
  const double cs = std::cos(theta), sn = std::sin(theta);
  const auto back = [&](const Vec2& x) -> Vec2 {  // a Vec2, not an Eigen expression of temporaries
    const Vec2 r = x - qbar;
    return Vec2(cs * r.x() + sn * r.y(), -sn * r.x() + cs * r.y()) + pbar;
  };
  const Vec2 rc = centre_ - pbar;
  const Vec2 centre_moved = Vec2(cs * rc.x() - sn * rc.y(), sn * rc.x() + cs * rc.y()) + qbar - centre_;
  v["frame_x_m"] = centre_moved.x();
  v["frame_y_m"] = centre_moved.y();
  v["frame_rotation_rad"] = theta;
  std::vector<Vec2> centroid(m.blocks.size());
  std::vector<double> area(m.blocks.size());
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    const Polygon p = block_outline(m, m.blocks[i]);
    centroid[i] = back(polygon_centroid(p));
    area[i] = std::abs(signed_area(p));
  }
  // Each block's centroid displacement since the reference (NaN for a block made since), and
  // the blocks that are, at this stage's end, further than fall_displacement from where they were
  // and nearer the drift. A block counted before that has come back within that distance is no
  // longer counted (in the drift comparison a Continuously-Yielding block was 50 mm out at the
  // end of a rest, counted, and 43 mm out after the next stage, settled against its neighbours);
  // one that goes out again is counted from that stage. A block no longer in the model stays.
  std::vector<Vec2> moved(m.blocks.size(), Vec2::Constant(kNaN));
  std::vector<char> out(m.blocks.size(), 0);
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    const auto r = ref_.centroids.find(m.blocks[i].id);
    if (r == ref_.centroids.end()) continue;
    moved[i] = centroid[i] - r->second;
    out[i] = moved[i].norm() > d.fall_displacement && (centroid[i] - centre_).norm() < (r->second - centre_).norm();
  }
  std::erase_if(fallen_, [&](const Fallen& f) {
    const auto it = position.find(f.id);
    return it != position.end() && !out[static_cast<std::size_t>(it->second)];
  });
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    const Block& b = m.blocks[i];
    if (out[i] && !has_fallen(b.id)) fallen_.push_back({b.id, b.name, area[i], moved[i].norm(), index + 1});
  }
  double fallen_area = 0.0;
  for (Fallen& f : fallen_) {
    fallen_area += f.area;
    if (const auto it = position.find(f.id); it != position.end())
      f.displacement = (centroid[static_cast<std::size_t>(it->second)] - ref_.centroids[f.id]).norm();
  }
  v["fallen_blocks"] = static_cast<double>(fallen_.size());
  v["fallen_area_m2"] = fallen_area;

  // Convergence: each wall point's displacement towards the drift's centre line.
  std::array<double, 4> u{kNaN, kNaN, kNaN, kNaN};
  for (std::size_t k = 0; k < 4; ++k) {
    if (!ref_.wall_found[k]) continue;
    const auto it = position.find(ref_.wall_block[k]);
    if (it == position.end()) continue;
    // A wall point on a block that has fallen is no longer the drift's wall: its metres of fall
    // are in fallen_blocks, not convergence.
    if (has_fallen(ref_.wall_block[k])) continue;
    const Block& b = m.blocks[static_cast<std::size_t>(it->second)];
    const Vec2 x = m.gp[static_cast<std::size_t>(b.first_gp + static_cast<int>(ref_.wall_local[k]))].x;
    const Vec2 du = back(x) - ref_.wall_x[k];
    u[k] = 0.0 + (k == 0 ? -du.y() : k == 1 ? du.y() : k == 2 ? du.x() : -du.x());  // 0.0 +: no "-0"
  }
  for (std::size_t k = 0; k < 4; ++k) v[std::string(kWallNames[k]) + "_inward_m"] = u[k];
  v["vertical_convergence_m"] = u[0] + u[1];
  v["horizontal_convergence_m"] = u[2] + u[3];
  const std::vector<std::string> cols = columns();
  if (v.size() != cols.size() || !std::all_of(cols.begin(), cols.end(), [&](const std::string& k) { return v.count(k) > 0; }))
    throw std::logic_error("drift results: the columns of events.csv are out of step with DriftResults::columns()");
  rows_.push_back(std::move(row));
  write_files(m, index, joints, moved);
}

void DriftResults::write_files(const Model& m, std::size_t index, const std::vector<JointRecord>& joints,
                               const std::vector<Vec2>& moved) const {
  const DriftSpec& d = c_.drift;
  fs::create_directories(dir_);
  std::ostringstream head;
  head << "# rockdem drift-study results (docs/drift-study.md): case " << c_.file << ", opening '" << d.opening
       << "' (centre " << format(centre_.x()) << " " << format(centre_.y()) << " m, equivalent radius " << format(radius_)
       << " m)\n# measured from the end of stage '" << c_.stages[d.reference_stage].name << "'; near the drift: within "
       << format(d.near) << " m of its wall; apertures " << format(d.initial_aperture) << " m at zero normal displacement, "
       << format(d.residual_aperture) << " m residual; fallen: moved " << format(d.fall_displacement)
       << " m towards the drift; loosened: slip or opening over " << format(d.loosened) << " m\n";
  // What each earthquake played, as scaled (rockdem run --motion and --pgv change it without the
  // case file saying so): a series over levels or records is read back from here.
  std::string events;
  for (const StageSpec& st : c_.stages) {
    if (st.motions.empty()) continue;
    events += (events.empty() ? "" : "; ") + st.name + ":";
    for (const StageSpec::Motion& mo : st.motions) {
      const seismic::InputMotion& im = *c_.motions[static_cast<std::size_t>(mo.index)];
      events += " " + im.name + " at PGV " + format(mo.factor * im.pgv()) + " m/s";
    }
  }
  if (!events.empty()) head << "# events: " << events << "\n";
  {
    std::ostringstream os;
    os << head.str() << "stage,name,kind,time_s";
    const std::vector<std::string> cols = columns();
    for (const std::string& k : cols) os << "," << k;
    os << "\n";
    for (const Row& r : rows_) {
      os << r.stage << "," << r.name << "," << r.kind << "," << format(r.time);
      for (const std::string& k : cols) {
        const auto it = r.values.find(k);
        os << "," << format(it != r.values.end() ? it->second : kNaN);
      }
      os << "\n";
    }
    write_file_atomically(dir_ / "events.csv", os.str());
  }
  {
    std::ostringstream os;
    os << head.str() << "block_id,name,area_m2,displacement_m,stage,stage_name\n";
    for (const Fallen& f : fallen_)
      os << id_value(f.id) << "," << f.name << "," << format(f.area) << "," << format(f.displacement) << "," << f.stage << ","
         << c_.stages[f.stage - 1].name << "\n";
    write_file_atomically(dir_ / "fallen_blocks.csv", os.str());
  }
  std::ostringstream os;
  os << head.str() << "x_m,y_m,set,distance_to_wall_m,slip_m,opening_m,aperture_m,length_m,normal_x,normal_y,normal_stress_Pa,"
                      "shear_stress_Pa,state\n";
  for (const JointRecord& r : joints)
    os << format(r.x.x()) << "," << format(r.x.y()) << "," << sets_[static_cast<std::size_t>(r.set)] << ","
       << format(r.wall) << "," << format(r.slip) << "," << format(r.opening) << "," << format(r.aperture) << ","
       << format(r.length) << "," << format(r.normal.x()) << "," << format(r.normal.y()) << "," << format(r.sigma_n) << ","
       << format(r.tau) << "," << kContactStateNames[r.state] << "\n";
  write_file_atomically(dir_ / ("contacts_" + stage_tag(index + 1, c_.stages[index].name) + ".csv"), os.str());
  write_vtk(m, index, joints, moved);
}

// Every joint contact's results at the present state, in contact order (contacts_*.csv, joints_*.vtu).
std::vector<DriftResults::JointRecord> DriftResults::joint_records(const Model& m) const {
  std::map<std::string, int> set_index;
  for (std::size_t i = 0; i < sets_.size(); ++i) set_index[sets_[i]] = static_cast<int>(i);
  std::vector<JointRecord> out;
  for (const Contact& c : m.contacts.items) {
    const EdgeLabel* joint = joint_of(m, c);
    if (!joint) continue;
    JointRecord r;
    r.x = m.gp[static_cast<std::size_t>(c.point)].x;
    r.set = set_index.at(joint->joint);
    r.wall = distance_to_wall(r.x);
    std::tie(r.slip, r.opening) = since_reference(c);
    r.aperture = aperture(c_.drift, c.response.u_n);
    r.length = c.length;
    r.flow_length = flow_length(c);
    r.normal = c.normal;
    r.sigma_n = c.response.sigma_n;
    r.tau = c.response.tau;
    r.state = c.state_category();
    out.push_back(r);
  }
  return out;
}

// The same results as fields for ParaView, one file per stage and a collection over the stages
// (time = the stage's end): joints_<n>_<stage>.vtu (a point per joint contact, the columns of
// contacts_*.csv) and blocks_<n>_<stage>.vtu (a cell per block: its displacement since the
// reference in the far field's frame, and whether and when it fell).
void DriftResults::write_vtk(const Model& m, std::size_t index, const std::vector<JointRecord>& joints,
                             const std::vector<Vec2>& moved) const {
  const std::string tag = stage_tag(index + 1, c_.stages[index].name);
  std::vector<Vec2> pts, normal;
  std::vector<double> slip, opening, aperture_m, wall, length, sn, tau;
  std::vector<int> set, state;
  for (const JointRecord& r : joints) {
    pts.push_back(r.x);
    normal.push_back(r.normal);
    slip.push_back(r.slip);
    opening.push_back(r.opening);
    aperture_m.push_back(r.aperture);
    wall.push_back(r.wall);
    length.push_back(r.length);
    sn.push_back(r.sigma_n);
    tau.push_back(r.tau);
    set.push_back(r.set);
    state.push_back(r.state);
  }
  VtkFields jf;
  jf.scalars = {{"slip_m", slip},         {"opening_m", opening},          {"aperture_m", aperture_m},
                {"distance_to_wall_m", wall}, {"length_m", length},        {"normal_stress_Pa", sn},
                {"shear_stress_Pa", tau}};
  jf.vectors = {{"normal", normal}};
  jf.ints = {{"joint_set", set}, {"state", state}};
  jf.names = {{"joint_set_names", sets_}, {"state_names", {std::begin(kContactStateNames), std::end(kContactStateNames)}}};
  write_points_vtu(pts, jf, (dir_ / ("joints_" + tag + ".vtu")).string());

  std::map<BlockId, std::size_t> fell_in;
  for (const Fallen& f : fallen_) fell_in[f.id] = f.stage;
  std::vector<double> moved_m;
  std::vector<int> block_id, fallen, fallen_stage;
  for (std::size_t i = 0; i < m.blocks.size(); ++i) {
    moved_m.push_back(moved[i].norm());
    block_id.push_back(id_value(m.blocks[i].id));
    const auto it = fell_in.find(m.blocks[i].id);
    fallen.push_back(it != fell_in.end() ? 1 : 0);
    fallen_stage.push_back(it != fell_in.end() ? static_cast<int>(it->second) : -1);
  }
  VtkFields bf;
  bf.vectors = {{"displacement_m", moved}};
  bf.scalars = {{"moved_m", moved_m}};
  bf.ints = {{"block_id", block_id}, {"fallen", fallen}, {"fallen_stage", fallen_stage}};
  write_block_cells_vtu(m, bf, (dir_ / ("blocks_" + tag + ".vtu")).string());

  std::vector<VtkSeries::Entry> joint_steps, block_steps;
  for (const Row& r : rows_) {
    const std::string t = stage_tag(r.stage, r.name);
    joint_steps.push_back({r.time, static_cast<long>(r.stage), "joints_" + t + ".vtu"});
    block_steps.push_back({r.time, static_cast<long>(r.stage), "blocks_" + t + ".vtu"});
  }
  write_pvd_collection(dir_ / "joints.pvd", joint_steps);
  write_pvd_collection(dir_ / "blocks.pvd", block_steps);
}

CheckpointArrays DriftResults::saved_state() const {
  CheckpointArrays a;
  if (!ref_.taken) return a;
  auto& keys = a["drift_reference_contact_keys"];
  auto& disp = a["drift_reference_contact_us_un"];
  for (const auto& [k, us_un] : ref_.contacts) {
    keys.insert(keys.end(), {static_cast<double>(id_value(k.point_block)), static_cast<double>(k.point_local),
                             static_cast<double>(id_value(k.other_block)), static_cast<double>(k.side)});
    disp.insert(disp.end(), {us_un.first, us_un.second});
  }
  auto& cen = a["drift_reference_centroids"];
  for (const auto& [id, x] : ref_.centroids) cen.insert(cen.end(), {static_cast<double>(id_value(id)), x.x(), x.y()});
  auto& far = a["drift_reference_far_field"];
  for (std::size_t k = 0; k < ref_.far_x.size(); ++k)
    far.insert(far.end(), {static_cast<double>(id_value(ref_.far_block[k])), static_cast<double>(ref_.far_local[k]), ref_.far_x[k].x(), ref_.far_x[k].y()});
  auto& wall = a["drift_reference_wall"];
  for (std::size_t k = 0; k < 4; ++k)
    wall.insert(wall.end(), {ref_.wall_found[k] ? 1.0 : 0.0, static_cast<double>(id_value(ref_.wall_block[k])),
                             static_cast<double>(ref_.wall_local[k]), ref_.wall_x[k].x(), ref_.wall_x[k].y()});
  a["drift_reference_k"] = {ref_.k[0], ref_.k[1], ref_.k[2]};
  auto& fallen = a["drift_fallen"];
  for (const Fallen& f : fallen_) fallen.insert(fallen.end(), {static_cast<double>(id_value(f.id)), f.area, f.displacement, static_cast<double>(f.stage)});
  // The rows so far, column by column in the order of the first row's columns.
  auto& rows = a["drift_rows"];
  for (const Row& r : rows_) {
    rows.insert(rows.end(), {static_cast<double>(r.stage), r.time});
    for (const std::string& k : columns()) rows.push_back(r.values.count(k) ? r.values.at(k) : kNaN);
  }
  return a;
}

void DriftResults::restore_state(const CheckpointArrays& a, std::size_t stages_completed) {
  ref_ = Reference{};
  fallen_.clear();
  rows_.clear();
  const auto get = [&](const char* name) -> const std::vector<double>* {
    const auto it = a.find(name);
    return it == a.end() ? nullptr : &it->second;
  };
  const auto* keys = get("drift_reference_contact_keys");
  if (!keys) return;  // written before the reference stage ended
  const auto* disp = get("drift_reference_contact_us_un");
  for (std::size_t i = 0; i + 3 < keys->size(); i += 4) {
    ContactKey k{BlockId{static_cast<std::int32_t>((*keys)[i])}, static_cast<LocalIndex>((*keys)[i + 1]),
                 BlockId{static_cast<std::int32_t>((*keys)[i + 2])}, static_cast<std::int32_t>((*keys)[i + 3])};
    ref_.contacts[k] = {(*disp)[i / 2], (*disp)[i / 2 + 1]};
  }
  if (const auto* cen = get("drift_reference_centroids"))
    for (std::size_t i = 0; i + 2 < cen->size(); i += 3) ref_.centroids[BlockId{static_cast<std::int32_t>((*cen)[i])}] = {(*cen)[i + 1], (*cen)[i + 2]};
  if (const auto* far = get("drift_reference_far_field"))
    for (std::size_t i = 0; i + 3 < far->size(); i += 4) {
      ref_.far_block.push_back(BlockId{static_cast<std::int32_t>((*far)[i])});
      ref_.far_local.push_back(static_cast<LocalIndex>((*far)[i + 1]));
      ref_.far_x.emplace_back((*far)[i + 2], (*far)[i + 3]);
    }
  if (const auto* wall = get("drift_reference_wall"); wall && wall->size() == 20)
    for (std::size_t k = 0; k < 4; ++k) {
      const double* w = wall->data() + 5 * k;
      ref_.wall_found[k] = w[0] != 0.0;
      ref_.wall_block[k] = BlockId{static_cast<std::int32_t>(w[1])};
      ref_.wall_local[k] = static_cast<LocalIndex>(w[2]);
      ref_.wall_x[k] = {w[3], w[4]};
    }
  if (const auto* k = get("drift_reference_k"); k && k->size() == 3) ref_.k = {(*k)[0], (*k)[1], (*k)[2]};
  ref_.taken = true;
  if (const auto* f = get("drift_fallen"))
    for (std::size_t i = 0; i + 3 < f->size(); i += 4) {
      Fallen x;
      x.id = BlockId{static_cast<std::int32_t>((*f)[i])};
      x.area = (*f)[i + 1];
      x.displacement = (*f)[i + 2];
      x.stage = static_cast<std::size_t>((*f)[i + 3]);
      for (const Block& b : c_.model.blocks)
        if (b.id == x.id) x.name = b.name;
      fallen_.push_back(std::move(x));
    }
  // The rows: their columns are the ones this case makes (the same sets), in the map's order.
  if (const auto* rows = get("drift_rows")) {
    const std::vector<std::string> cols = columns();
    const std::size_t width = 2 + cols.size();
    for (std::size_t i = 0; i + width <= rows->size(); i += width) {
      Row r;
      r.stage = static_cast<std::size_t>((*rows)[i]);
      if (r.stage > stages_completed || r.stage == 0) break;
      r.time = (*rows)[i + 1];
      r.name = c_.stages[r.stage - 1].name;
      r.kind = r.stage - 1 == c_.drift.reference_stage ? "reference" : !c_.stages[r.stage - 1].motions.empty() ? "event" : "rest";
      for (std::size_t j = 0; j < cols.size(); ++j) r.values[cols[j]] = (*rows)[i + 2 + j];
      rows_.push_back(std::move(r));
    }
  }
}

}  // namespace rockdem
