#include "framework/io/case_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "framework/contact/detection.hpp"
#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/units.hpp"
#include "framework/geometry/mesh.hpp"
#include "framework/geometry/rock_mass.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
namespace {

Polygon block_shape(const BlockSpec& s) {
  if (s.rectangle) {
    const auto& r = *s.rectangle;
    if (!(r.width > 0 && r.height > 0)) throw InputError(s.shape_where + ": width and height must be positive");
    Polygon p = {{r.x0, r.y0}, {r.x0 + r.width, r.y0}, {r.x0 + r.width, r.y0 + r.height}, {r.x0, r.y0 + r.height}};
    // A width or height far below the corner's coordinates vanishes when added to them.
    if (!is_simple(p))
      throw InputError(s.shape_where + ": the rectangle's corners coincide in double precision (a width or height " +
                       "too small against its corner's coordinates); valid: a side at least about 1e-15 of the coordinates");
    return p;
  }
  if (!is_simple(s.polygon)) throw InputError(s.shape_where + ": the polygon intersects itself");
  return s.polygon;
}

TriMesh block_mesh(const BlockSpec& s, const Polygon& shape) {
  const auto rect = s.rectangle.value_or(BlockSpec::Rectangle{});
  if (s.zones) {
    if (!s.rectangle) throw InputError(s.zones_where + ": zones = [nx, ny] is for rectangles; use zone_size for polygons");
    return mesh_rectangle(rect.x0, rect.y0, rect.width, rect.height, (*s.zones)[0], (*s.zones)[1]);
  }
  if (s.mesh == BlockSpec::Mesh::unstructured) return mesh_polygon(shape, s.zone_size);
  if (!s.rectangle)
    throw InputError(s.mesh_where + ": a structured mesh needs rectangle = [...]; use mesh = \"unstructured\" for polygons");
  return mesh_rectangle(rect.x0, rect.y0, rect.width, rect.height,
                        std::max(1, static_cast<int>(std::lround(rect.width / s.zone_size))),
                        std::max(1, static_cast<int>(std::lround(rect.height / s.zone_size))));
}

// Whether nothing of the model lies above x, a point of edge `edge` of block `block`: no other
// boundary edge (of any block, that one's included) crosses the vertical through x higher than
// x, less `tol` (a neighbour lying on the edge is above it).
bool nothing_above(const Model& m, int block, int edge, const Vec2& x, double tol) {
  for (std::size_t b = 0; b < m.blocks.size(); ++b) {
    const auto& loop = m.blocks[b].boundary;
    const std::size_t n = loop.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (static_cast<int>(b) == block && static_cast<int>(i) == edge) continue;
      const Vec2 p = m.gp[static_cast<std::size_t>(loop[i])].x, q = m.gp[static_cast<std::size_t>(loop[(i + 1) % n])].x;
      if ((p.x() - x.x()) * (q.x() - x.x()) > 0.0) continue;  // both ends on one side of the vertical
      const double y = p.x() == q.x() ? std::max(p.y(), q.y()) : p.y() + (x.x() - p.x()) * (q.y() - p.y()) / (q.x() - p.x());
      if (y > x.y() - tol) return false;
    }
  }
  return true;
}

// Whether selected edges are on the model's top: facing up (more up than sideways, so that the
// top of a slope counts) with nothing of the model above them. Neither the floor of an opening
// (the rock above it) nor a block's top under another block is the model's top, and a quiet
// boundary there makes no couple with the base input.
bool on_models_top(const Model& m, const std::vector<FaceSelection>& sels) {
  double size = 0.0;
  for (const auto& g : m.gp) size = std::max(size, g.x.cwiseAbs().maxCoeff());
  const double tol = 1e-9 * std::max(size, 1.0);
  for (const FaceSelection& sel : sels) {
    const auto& loop = m.blocks[static_cast<std::size_t>(sel.block)].boundary;
    const std::size_t n = loop.size();
    for (int i : sel.edges) {
      const Vec2 a = m.gp[static_cast<std::size_t>(loop[static_cast<std::size_t>(i)])].x,
                 b = m.gp[static_cast<std::size_t>(loop[(static_cast<std::size_t>(i) + 1) % n])].x;
      const Vec2 d = b - a;  // counter-clockwise: the outward normal is (d.y, -d.x)
      if (-d.x() > std::abs(d.y()) && nothing_above(m, sel.block, i, 0.5 * (a + b), tol)) return true;
    }
  }
  return false;
}

// "left" or "right": the side a free-field column is on (the outward normal of its edges).
std::string column_side(const Model& m, const std::vector<FaceSelection>& sels) {
  for (const FaceSelection& sel : sels) {
    if (sel.edges.empty()) continue;
    const auto& loop = m.blocks[static_cast<std::size_t>(sel.block)].boundary;
    const auto i = static_cast<std::size_t>(sel.edges.front());
    const double dy = m.gp[static_cast<std::size_t>(loop[(i + 1) % loop.size()])].x.y() - m.gp[static_cast<std::size_t>(loop[i])].x.y();
    return dy > 0.0 ? "right" : "left";  // counter-clockwise: going up on the right side
  }
  return "?";
}

bool active_in(const std::vector<std::string>& stages, const std::string& stage) {
  return stages.empty() || std::find(stages.begin(), stages.end(), stage) != stages.end();
}

std::string quoted_list(const std::vector<std::string>& names) {
  return join_names(names, [](const std::string& n) { return "'" + n + "'"; });
}

}  // namespace

CaseBuilder::CaseBuilder(const std::string& file, const std::string& title) {
  c_.file = file;
  c_.title = title;
}

void CaseBuilder::model_settings(const ModelSettingsSpec& s) {
  Model& m = c_.model;
  if (s.gravity) m.gravity = *s.gravity;
  m.contacts.rounding = s.rounding;
  m.contacts.tolerance = s.tolerance;
  c_.settings.detection.distance = s.rounding + s.tolerance;
}

void CaseBuilder::time(const TimeSpec& s) {
  c_.settings.dt_safety = s.dt_safety;
  c_.settings.fixed_dt = s.fixed_dt;
  c_.settings.mass_scaling_dt = s.mass_scaling_dt;
  c_.settings.refresh_interval = s.refresh_interval;
  c_.settings.velocity_limit = s.velocity_limit;
}

void CaseBuilder::add_material(const MaterialSpec& s) {
  const auto& entry = RockMaterialRegistry::instance().get(s.model, "rock material", s.model_where);
  materials_[s.name] = static_cast<int>(c_.model.materials.size());
  c_.model.materials.push_back(entry.make(s.params, s.where));
}

void CaseBuilder::add_joint(const JointSpec& s) {
  Model& m = c_.model;
  m.contacts.models.push_back(make_joint_model(s.law, s.params, s.effects, s.law_where));
  m.contacts.model_names.push_back(s.name);
  joints_.push_back(s);
}

int CaseBuilder::group_index(const std::string& group) {
  auto it = groups_.find(group);
  if (it != groups_.end()) return it->second;
  const int i = static_cast<int>(groups_.size());
  groups_[group] = i;
  return i;
}

int CaseBuilder::material_index(const BlockSpec& s) const {
  auto it = materials_.find(s.material);
  if (it == materials_.end())
    throw InputError(s.material_where + ": unknown material '" + s.material + "'; defined materials: " +
                     (materials_.empty() ? "(none: add [[materials]])" : join_keys(materials_)));
  return it->second;
}

void CaseBuilder::add_block(const BlockSpec& s) {
  Model& m = c_.model;
  if (std::find(c_.block_names.begin(), c_.block_names.end(), s.name) != c_.block_names.end())
    throw InputError(s.where + ": a block named '" + s.name + "' already exists");
  const int group = group_index(s.group.empty() ? s.name : s.group);
  const Polygon shape = block_shape(s);
  std::vector<int> corners;
  const int material = s.rigid ? -1 : material_index(s);  // named before the mesh is made, as mistakes go
  try {
    if (s.rigid) {
      add_rigid_block(m, shape, s.density, s.name, group);
      for (std::size_t i = 0; i < shape.size(); ++i) corners.push_back(static_cast<int>(i));
    } else {
      const TriMesh mesh = block_mesh(s, shape);
      add_deformable_block(m, mesh, material, s.name, group);
      corners = mesh.corners;
    }
  } catch (const InputError& e) {
    // The mesher and the model's checks know the block, not the file: say where it is written.
    const std::string what = e.what();
    if (!c_.file.empty() && what.rfind(c_.file, 0) == 0) throw;  // already says where (e.g. the shape's key)
    throw InputError(s.where + ": " + what);
  }
  if (!s.edge_labels.empty()) label_edges(s, shape, corners);
  c_.block_names.push_back(s.name);
}

// Rock-mass edge labels onto the last block's boundary loop, each label once in the model's table.
void CaseBuilder::label_edges(const BlockSpec& s, const Polygon& shape, const std::vector<int>& corners) {
  auto& table = c_.model.contacts.edge_labels;
  std::vector<int> labels;
  for (const auto& l : s.edge_labels) {
    if (!l) {
      labels.push_back(-1);
      continue;
    }
    auto it = std::find(table.begin(), table.end(), *l);
    if (it == table.end()) it = table.insert(table.end(), *l);
    labels.push_back(static_cast<int>(it - table.begin()));
    if (!l->joint.empty()) edge_joint_names_.insert(l->joint);
  }
  if (labels.size() != shape.size())
    throw InputError(s.where + ": " + std::to_string(labels.size()) + " edge labels for " + std::to_string(shape.size()) +
                     " polygon edges");
  Block& b = c_.model.blocks.back();
  b.edge_joint = loop_edge_labels(labels, corners, b.boundary.size(), signed_area(shape) < 0.0);
}

// Overlapping blocks at the start are an input error (touching along an edge is fine). Only
// pairs whose boxes meet are tested (the contact broad phase), so large models stay cheap.
void CaseBuilder::check_overlaps() const {
  const Model& m = c_.model;
  for (const auto& [i, j] : broad_phase(m, 0.0)) {
    Polygon a, b;
    for (int g : m.blocks[i].boundary) a.push_back(m.gp[g].x);
    for (int g : m.blocks[j].boundary) b.push_back(m.gp[g].x);
    if (polygons_overlap(a, b, 1e-9 * std::sqrt(std::abs(signed_area(a)))))
      throw InputError(c_.file + ": blocks '" + m.blocks[i].name + "' and '" + m.blocks[j].name +
                       "' overlap at the start (intersection area " + std::to_string(intersection_area(a, b)) +
                       " m^2); blocks may touch but not overlap");
  }
}

void CaseBuilder::assign_joint_groups() {
  auto& contacts = c_.model.contacts;
  contacts.group_names.resize(groups_.size());
  for (const auto& [g, i] : groups_) contacts.group_names[static_cast<std::size_t>(i)] = g;
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const auto& [a, b] = joints_[j].between;
    auto ga = groups_.find(a), gb = groups_.find(b);
    const bool any_a = a == "*", any_b = b == "*";
    if ((!any_a && ga == groups_.end()) || (!any_b && gb == groups_.end()))
      throw InputError(c_.file + ": joint '" + contacts.model_names[j] + "' names a block group '" +
                       (ga == groups_.end() ? a : b) + "' that no block has; groups: " + join_keys(groups_) +
                       " (or \"*\" for any)");
    contacts.assignments.push_back({any_a ? -1 : ga->second, any_b ? -1 : gb->second, static_cast<int>(j),
                                    joint_labels(joints_[j])});
  }
}

// The edge labels a [[joints]] entry with joint_sets or bridges acts at (none: a group entry).
std::vector<int> CaseBuilder::joint_labels(const JointSpec& s) const {
  std::vector<int> labels;
  if (s.joint_sets.empty() && !s.bridges) return labels;
  for (const auto& name : s.joint_sets)
    if (!edge_joint_names_.count(name))
      throw InputError(s.joint_sets_where + ": joint '" + s.name + "' names joint set '" + name +
                       "' that no block edge lies on; joint sets and named joints of the rock mass: " +
                       (edge_joint_names_.empty() ? "(none: add [rock_mass] with joint sets)" : join_names(edge_joint_names_)));
  const auto& table = c_.model.contacts.edge_labels;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const bool named = s.joint_sets.empty() ||
                       std::find(s.joint_sets.begin(), s.joint_sets.end(), table[i].joint) != s.joint_sets.end();
    if (named && table[i].bridge == s.bridges) labels.push_back(static_cast<int>(i));
  }
  // An entry whose labels no edge has would otherwise act as a group entry everywhere.
  if (labels.empty()) labels.push_back(-2);
  return labels;
}

void CaseBuilder::finish_blocks() {
  if (c_.model.blocks.empty()) throw InputError(c_.file + ": the case defines no blocks; add [[blocks]]");
  check_overlaps();
  assign_joint_groups();
}

void CaseBuilder::in_situ(const InSituSpec& s) {
  const Model& m = c_.model;
  StressField f;
  f.surcharge = s.surcharge;
  f.k = s.k;
  f.sxy = s.sxy;
  double top = -std::numeric_limits<double>::infinity();
  for (const auto& g : m.gp) top = std::max(top, g.x.y());
  const double size = std::max(1.0, std::abs(top));
  f.surface = s.surface.value_or(top);
  if (s.surface && *s.surface < top - 1e-9 * size)
    throw InputError(s.surface_where + ": the datum (surface = " + std::to_string(*s.surface) +
                     " m) lies below the top of the model (y = " + std::to_string(top) +
                     " m): the rock above it would be in vertical tension; give surface >= the top of the model");
  const double g = -m.gravity.y();
  if (m.gravity.x() != 0.0)
    throw InputError(s.where + ": the in-situ field grows with depth along y, but [model] gravity has an x component; "
                     "use a vertical gravity [\"0 m/s2\", \"-9.81 m/s2\"]");
  auto block_density = [&](const Block& b) { return b.rigid ? b.density : m.materials[m.zones[b.first_zone].material]->density(); };
  if (g == 0.0) {
    if (s.density && *s.density > 0.0)
      throw InputError(s.density_where + ": the model has no gravity, so a stress that grows with depth (density > 0) "
                       "would not be balanced; leave out density or set [model] gravity");
    f.density = 0.0;
  } else {
    // Only the blocks' own density balances gravity: the field's gradient must be theirs.
    const double rho = s.density ? *s.density : block_density(m.blocks.front());
    for (const Block& b : m.blocks)
      if (std::abs(block_density(b) - rho) > 1e-9 * rho)
        throw InputError((s.density ? s.density_where : s.where) + ": the field's vertical gradient is density * g with "
                         "density = " + format_quantity(rho, Dimension::density) + ", but block '" + b.name + "' has density " +
                         format_quantity(block_density(b), Dimension::density) + ", so gravity would not be balanced; give the "
                         "blocks' density (a field by region is not available yet)");
    f.density = rho;
    f.gravity = g;
  }
  c_.in_situ = f;
}

void CaseBuilder::add_region_boundary(const BoundarySpec& s) {
  const Model& m = c_.model;
  if (s.face_given)
    throw InputError(s.face_where + ": a condition on a region (box or line) takes every boundary gridpoint in it; "
                     "'face' is for a condition on one block (block = ..., face = ...)");
  const ConditionKind& kind = ConditionKinds::instance().get(s.type, s.type_where);
  const auto selections = select_region(m, *s.region);
  if (selections.empty())
    throw InputError(s.region_where + ": no boundary gridpoint of any block lies in the region; check its coordinates "
                     "and units (or the line's tolerance)");
  {
    RegionCondition rc{{}, static_cast<bool>(kind.make_spanning), s.stages, s.where};
    for (const FaceSelection& sel : selections) rc.blocks.push_back(sel.block);
    region_conditions_.push_back(std::move(rc));
  }
  if (kind.make_spanning) {
    ConditionInput in{m, selections.front(), m.blocks[selections.front().block].rigid, s.values, s.where};
    in.stress_field = c_.in_situ ? &*c_.in_situ : nullptr;
    in.by_region = true;
    auto bc = kind.make_spanning(in, selections);
    bc->stages = s.stages;
    c_.conditions.push_back(std::move(bc));
    note_column_top(s, selections);
    return;
  }
  for (const FaceSelection& sel : selections) {
    ConditionInput in{m, sel, m.blocks[sel.block].rigid, s.values, s.where};
    in.stress_field = c_.in_situ ? &*c_.in_situ : nullptr;
    in.by_region = true;
    auto bc = kind.make(in);
    bc->stages = s.stages;
    c_.conditions.push_back(std::move(bc));
  }
  note_column_top(s, selections);
}

void CaseBuilder::add_boundary(const BoundarySpec& s) {
  if (s.region) return add_region_boundary(s);
  const Model& m = c_.model;
  const int block = c_.block_index(s.block, s.block_where);
  const std::string& block_name = m.blocks[block].name;
  named_conditions_.push_back({block, s.stages, s.where});
  FaceSelection sel = select_outer_face(m, block, face_direction(s.face, s.face_where), outer_face_tolerance(m, block));
  if (sel.points.empty())
    throw InputError(s.where + ": face '" + s.face + "' of block '" + block_name + "' has no gridpoints");
  const bool rigid = m.blocks[block].rigid;
  const ConditionKinds& kinds = ConditionKinds::instance();
  if (const ConditionKind* k = kinds.find(s.type); k && k->whole_rigid_block && rigid && s.face_given)
    throw InputError(s.face_where + ": block '" + block_name + "' is rigid; a " + s.type +
                     " condition acts on the whole rigid block, so leave out 'face'");
  const ConditionKind& kind = kinds.get(s.type, s.type_where);
  ConditionInput in{m, std::move(sel), rigid, s.values, s.where};
  in.stress_field = c_.in_situ ? &*c_.in_situ : nullptr;
  auto bc = kind.make_spanning ? kind.make_spanning(in, {in.selection}) : kind.make(in);
  bc->stages = s.stages;
  c_.conditions.push_back(std::move(bc));
  note_column_top(s, {in.selection});
}

void CaseBuilder::note_column_top(const BoundarySpec& s, const std::vector<FaceSelection>& selections) {
  if (s.type != "quiet" && s.type != "free_field") return;
  TopCondition t;
  t.free_field = s.type == "free_field";
  const auto top = s.values.find("top");  // checked by the kind when it made the condition
  t.quiet_top = t.free_field && top != s.values.end() && !top->second.names.empty() && top->second.names.front() == "quiet";
  t.selections = selections;
  t.stages = s.stages;
  t.where = s.where;
  top_conditions_.push_back(std::move(t));
}

// A free-field column's top must be as the model's top in the stages they share (docs/seismic-
// input.md, "Free-field sides"). Free column tops under a quiet model top leave the couple of the
// base input and the top's dashpots unbalanced, and the whole model turns; a quiet column top
// under a top that reflects drives the side with another free field than the model's. Both run
// and are warned of, not refused: a study may keep them on purpose (cases/drift/small.toml keeps
// free tops, docs/drift-study.md).
void CaseBuilder::check_column_tops() {
  if (std::none_of(top_conditions_.begin(), top_conditions_.end(), [](const TopCondition& t) { return t.free_field; })) return;
  std::vector<const TopCondition*> quiet_tops;
  for (const auto& t : top_conditions_)
    if (!t.free_field && on_models_top(c_.model, t.selections)) quiet_tops.push_back(&t);
  for (const auto& ff : top_conditions_) {
    if (!ff.free_field) continue;
    std::vector<std::string> stages, quiet_wheres;
    for (const auto& stage : c_.stages) {
      if (!active_in(ff.stages, stage.name)) continue;
      bool quiet = false;
      for (const TopCondition* q : quiet_tops)
        if (active_in(q->stages, stage.name)) {
          quiet = true;
          if (std::find(quiet_wheres.begin(), quiet_wheres.end(), q->where) == quiet_wheres.end()) quiet_wheres.push_back(q->where);
        }
      if (quiet != ff.quiet_top) stages.push_back(stage.name);
    }
    if (stages.empty()) continue;
    const std::string in_stages = (stages.size() == 1 ? "stage " : "stages ") + quoted_list(stages);
    const std::string which = ff.where + " (free_field, " + column_side(c_.model, ff.selections) + " side): ";
    if (!ff.quiet_top)
      c_.warnings.push_back(
          which + "its column's top is \"free\" but the model's top is quiet (the quiet boundar" +
          (quiet_wheres.size() == 1 ? "y " : "ies ") + join_names(quiet_wheres) +
          ") in " + in_stages + ": the base input and the top's dashpots make a couple that free column tops leave "
          "unbalanced, and the whole model turns (docs/seismic-input.md, \"Free-field sides\"); set top = \"quiet\" in "
          "this boundary");
    else
      c_.warnings.push_back(
          which + "its column's top is \"quiet\" but no quiet boundary is on the model's top in " + in_stages +
          ": the column lets out through its top the waves the model's top reflects, so the side is driven by another "
          "free field than the model's (docs/seismic-input.md, \"Free-field sides\"); leave out top (\"free\", the "
          "default) or put a quiet boundary on the model's top in " + (stages.size() == 1 ? "that stage" : "those stages"));
  }
}

void CaseBuilder::resolve_excavation(const StageInput& s, StageSpec& stage) {
  const Model& m = c_.model;
  for (std::size_t i = 0; i < s.excavate.size(); ++i) {
    const std::string& name = s.excavate[i];
    std::vector<int> found;
    for (std::size_t b = 0; b < m.blocks.size(); ++b)
      if (m.blocks[b].name == name) found.push_back(static_cast<int>(b));
    if (found.empty()) {
      if (auto g = groups_.find(name); g != groups_.end())
        for (std::size_t b = 0; b < m.blocks.size(); ++b)
          if (m.blocks[b].group == g->second) found.push_back(static_cast<int>(b));
    }
    if (found.empty())
      throw InputError(s.excavate_wheres[i] + ": stage '" + stage.name + "' excavates '" + name +
                       "', which is neither a block nor a block group; groups: " + join_keys(groups_));
    for (int b : found) {
      for (const auto& earlier : c_.stages)
        if (std::count(earlier.excavate.begin(), earlier.excavate.end(), m.blocks[b].id))
          throw InputError(s.excavate_wheres[i] + ": block '" + m.blocks[b].name + "' is already excavated by stage '" +
                           earlier.name + "'");
      if (!std::count(stage.excavate.begin(), stage.excavate.end(), m.blocks[b].id)) stage.excavate.push_back(m.blocks[b].id);
    }
  }
  if (stage.excavate.size() >= m.blocks.size())
    throw InputError(s.excavate_wheres.front() + ": stage '" + stage.name + "' would excavate every block");
}

// Whether a condition limited to `stages` (none: every stage) acts in stage k or a later one.
bool CaseBuilder::acts_from(const std::vector<std::string>& stages, std::size_t k) const {
  if (stages.empty()) return true;
  for (std::size_t j = k; j < c_.stages.size(); ++j)
    if (std::count(stages.begin(), stages.end(), c_.stages[j].name)) return true;
  return false;
}

// The stage (by index) that excavates a block, or -1.
int CaseBuilder::excavated_by(int block) const {
  const BlockId id = c_.model.blocks[block].id;
  for (std::size_t k = 0; k < c_.stages.size(); ++k)
    if (std::count(c_.stages[k].excavate.begin(), c_.stages[k].excavate.end(), id)) return static_cast<int>(k);
  return -1;
}

void CaseBuilder::add_stage(const StageInput& s) {
  StageSpec stage = s.stage;
  if (stage.scale_off > 0.0) scale_off_wheres_[stage.name] = s.scale_off_where;
  resolve_excavation(s, stage);
  resolve_motions(s, stage);
  for (const auto& change : s.joint_changes) {
    auto def = std::find_if(joints_.begin(), joints_.end(), [&](const JointSpec& j) { return j.name == change.joint; });
    if (def == joints_.end())
      throw InputError(change.where + ": no joint named '" + change.joint + "'; joints: " + join_names(joints_, &JointSpec::name));
    // The joint's parameters as in [[joints]], with the stage's changes over them.
    RawValues merged = def->params;
    for (const auto& [key, value] : change.params) merged[key] = value;
    stage.joint_models.emplace_back(static_cast<int>(def - joints_.begin()),
                                    make_joint_model(def->law, merged, def->effects, change.where));
  }
  c_.stages.push_back(std::move(stage));
}

// In the case's order (the order they run in), not the set's alphabetical one.
std::string CaseBuilder::stage_list() const { return join_names(c_.stages, [](const auto& s) -> const auto& { return s.name; }); }

void CaseBuilder::finish_stages() {
  if (c_.stages.empty()) throw InputError(c_.file + ": the case defines no stages; add [[stages]]");
  for (const auto& s : c_.stages) stage_names_.insert(s.name);
  for (const auto& bc : c_.conditions)
    for (const auto& s : bc->stages)
      if (!stage_names_.count(s))
        throw InputError(c_.file + ": a boundary condition names stage '" + s + "' that does not exist; stages: " +
                         stage_list());
  // A condition on a block must end before the stage that excavates it.
  for (const auto& nc : named_conditions_) {
    const int k = excavated_by(nc.block);
    if (k < 0) continue;
    if (acts_from(nc.stages, static_cast<std::size_t>(k)))
      throw InputError(nc.where + ": the condition acts on block '" + c_.model.blocks[nc.block].name + "', which stage '" +
                       c_.stages[static_cast<std::size_t>(k)].name + "' excavates (stages." +
                       c_.stages[static_cast<std::size_t>(k)].name + ".excavate), but it is active in that stage or "
                       "later; limit it to earlier stages with stages = [...] or do not excavate the block");
  }
  check_region_conditions();
  check_stage_motions();
  check_column_tops();
}

// An excavation takes a region condition's gridpoints on the blocks it removes. Losing some of
// them is what excavating at a boundary means (a warning says which); losing all of them, or any
// block of a free-field column, would silently leave that side of the model free from then on (a
// case excavating blocks by the names of another realisation of its rock mass lost its far
// field's right half, and with it a fixed side, and its rock fell out of the model).
void CaseBuilder::check_region_conditions() {
  const Model& m = c_.model;
  for (const RegionCondition& rc : region_conditions_) {
    for (std::size_t k = 0; k < c_.stages.size(); ++k) {
      const StageSpec& st = c_.stages[k];
      // The blocks stage k excavates, and those still there after it.
      std::vector<std::string> names, kept;
      for (int b : rc.blocks) {
        const int by = excavated_by(b);
        if (by == static_cast<int>(k)) names.push_back(m.blocks[static_cast<std::size_t>(b)].name);
        else if (by < 0 || by > static_cast<int>(k)) kept.push_back(m.blocks[static_cast<std::size_t>(b)].name);
      }
      if (names.empty() || !acts_from(rc.stages, k)) continue;
      const std::string what = rc.where + ": stage '" + st.name + "' excavates " + (names.size() == 1 ? "block " : "blocks ") +
                               join_names(names) + ", on which this boundary acts";
      const std::string fix = "; limit the boundary to earlier stages with stages = [...], or do not excavate " +
                              std::string(names.size() == 1 ? "that block" : "those blocks") +
                              " (with a rock mass, excavate its openings or groups: its numbered blocks are other blocks in "
                              "another realisation)";
      if (rc.spanning)
        throw InputError(what + ": a free-field column runs beside all of its blocks and cannot lose one" + fix);
      if (kept.empty())
        throw InputError(what + ", and no other block: it would act on nothing from that stage on, and the model would lose "
                         "that support without a word" + fix);
      c_.warnings.push_back(what + "; it acts on " + join_names(kept) + " from that stage on");
    }
  }
}

int CaseBuilder::component_index(const HistoryQuantity& q, const HistoryInput& s) {
  if (q.components.empty()) {
    if (s.component)
      throw InputError(s.component_where + ": quantity '" + q.name + "' has no components; remove the 'component' key");
    return 0;
  }
  const std::string component = s.component.value_or(q.components.front());
  const auto c = std::find(q.components.begin(), q.components.end(), component);
  if (c == q.components.end())
    throw InputError(s.component_where + ": unknown component '" + component + "'; valid: " + join_names(q.components));
  return static_cast<int>(c - q.components.begin());
}

void CaseBuilder::add_history(const HistoryInput& s) {
  const Model& m = c_.model;
  HistorySpec h;
  h.name = s.name;
  h.quantity = &HistoryQuantities::instance().get(s.quantity, s.quantity_where);
  const HistoryQuantity& q = *h.quantity;
  h.unit = s.unit.value_or(q.unit);
  h.description = s.description;
  h.scale = s.scale;
  if (q.needs_point) {
    if (!s.at) throw InputError(s.quantity_where + ": quantity '" + q.name + "' is measured by location: give at = [x, y]");
    h.target.at = *s.at;
    h.target.segment = s.to.has_value();
    if (s.to) h.target.to = *s.to;
  }
  if (q.needs_block) {
    h.target.block = c_.block_index(s.block, s.block_where);
    if (const int k = excavated_by(h.target.block); k >= 0)
      throw InputError(s.block_where + ": history '" + s.name + "' measures block '" + s.block + "', which stage '" +
                       c_.stages[static_cast<std::size_t>(k)].name + "' excavates (stages." +
                       c_.stages[static_cast<std::size_t>(k)].name + ".excavate); measure a block that remains");
    const Block& b = m.blocks[h.target.block];
    if (q.rigid_only && !b.rigid)
      throw InputError(s.quantity_where + ": '" + q.name + "' is for rigid blocks; block '" + b.name +
                       "' is deformable: use face_displacement");
    if (q.needs_face)
      h.target.points = select_outer_face(m, h.target.block, face_direction(s.face, s.face_where),
                                          outer_face_tolerance(m, h.target.block)).points;
  }
  // Every quantity's component, the model-wide ones' too (an energy history's was once read
  // nowhere, so each recorded the kinetic energy whatever its `component` said).
  h.target.component = component_index(q, s);
  c_.histories.push_back(std::move(h));
}

void CaseBuilder::direct_shear(const DirectShearInput& s) {
  const Model& m = c_.model;
  auto& d = c_.direct_shear;
  d.enabled = true;
  d.specimen = s.specimen;
  d.joint_length = s.joint_length;
  d.loader = c_.block_index(s.loader, s.loader_where);
  d.top = c_.block_index(s.top, s.top_where);
  d.bottom = c_.block_index(s.bottom, s.bottom_where);
  d.shear_stages = s.shear_stages;
  d.normal_stresses = s.normal_stresses;
  for (const auto& stage : d.shear_stages)
    if (!stage_names_.count(stage))
      throw InputError(s.where + ": no stage named '" + stage + "'; stages: " + stage_list());
  d.top_face = select_face(m, d.top, {0, -1}).points;
  d.bottom_face = select_face(m, d.bottom, {0, 1}).points;
  if (!m.blocks[d.loader].rigid) throw InputError(s.loader_where + ": the loading block must be rigid");
  for (std::size_t i = 0; i < s.other_loaders.size(); ++i) {
    const int b = c_.block_index(s.other_loaders[i], s.other_loader_wheres[i]);
    if (!m.blocks[b].rigid) throw InputError(s.other_loader_wheres[i] + ": a loading block must be rigid");
    d.other_loaders.push_back(b);
  }
}

void CaseBuilder::drift(const DriftInput& s) {
  DriftSpec& d = c_.drift;
  const int b = c_.block_index(s.opening, s.opening_where);
  const Block& blk = c_.model.blocks[static_cast<std::size_t>(b)];
  // The stage that excavates the opening: results are counted from its end at the earliest.
  std::size_t excavated = c_.stages.size();
  for (std::size_t k = 0; k < c_.stages.size() && excavated == c_.stages.size(); ++k)
    for (BlockId id : c_.stages[k].excavate)
      if (id == blk.id) excavated = k;
  if (excavated == c_.stages.size())
    throw InputError(s.opening_where + ": no stage excavates '" + s.opening + "' (give the opening's block in a stage's 'excavate')");
  d.reference_stage = excavated;
  if (!s.reference_stage.empty()) {
    std::size_t k = 0;
    while (k < c_.stages.size() && c_.stages[k].name != s.reference_stage) ++k;
    if (k == c_.stages.size())
      throw InputError(s.reference_where + ": no stage named '" + s.reference_stage + "'; stages: " + stage_list());
    if (k < excavated)
      throw InputError(s.reference_where + ": stage '" + s.reference_stage + "' comes before the opening is excavated (stage '" +
                       c_.stages[excavated].name + "'); the reference must be that stage or a later one");
    d.reference_stage = k;
  }
  // Scaling belongs to making the opening: a block that comes loose after the reference state is
  // a result of the study (fallen_blocks), and taking it out would hide it.
  for (std::size_t k = d.reference_stage + 1; k < c_.stages.size(); ++k)
    if (c_.stages[k].scale_off > 0.0)
      throw InputError(scale_off_wheres_.at(c_.stages[k].name) + ": stage '" + c_.stages[k].name + "' comes after the drift's reference stage ('" +
                       c_.stages[d.reference_stage].name + "'); blocks that come loose then are counted as fallen, not scaled off "
                       "(scale_off belongs to the excavation stages, up to the reference)");
  d.enabled = true;
  d.opening = s.opening;
  d.outline.clear();
  for (int g : blk.boundary) d.outline.push_back(c_.model.gp[static_cast<std::size_t>(g)].x0);
  d.near = s.near;
  d.initial_aperture = s.initial_aperture;
  d.residual_aperture = s.residual_aperture;
  d.fall_displacement = s.fall_displacement;
  d.loosened = s.loosened;
}

void CaseBuilder::output(const OutputSpec& s) { c_.output = s; }

Case CaseBuilder::finish() {
  std::set<int> held;
  for (const NamedCondition& n : named_conditions_) held.insert(n.block);
  for (const RegionCondition& rc : region_conditions_) held.insert(rc.blocks.begin(), rc.blocks.end());
  for (const HistorySpec& h : c_.histories)
    if (h.target.block >= 0) held.insert(h.target.block);
  const DirectShearSpec& ds = c_.direct_shear;
  for (int b : {ds.loader, ds.top, ds.bottom})
    if (b >= 0) held.insert(b);
  held.insert(ds.other_loaders.begin(), ds.other_loaders.end());
  c_.held_blocks.clear();
  for (int b : held) c_.held_blocks.push_back(c_.model.blocks[static_cast<std::size_t>(b)].id);
  std::sort(c_.held_blocks.begin(), c_.held_blocks.end());
  return std::move(c_);
}

Case build_case(const CaseSpec& spec) {
  CaseBuilder b(spec.file, spec.title);
  b.model_settings(spec.model);
  if (spec.time) b.time(*spec.time);
  for (const auto& s : spec.materials) b.add_material(s);
  for (const auto& s : spec.joints) b.add_joint(s);
  for (const auto& s : spec.blocks) b.add_block(s);
  b.finish_blocks();
  if (spec.in_situ) b.in_situ(*spec.in_situ);
  for (const auto& s : spec.motions) b.add_motion(s);
  for (const auto& s : spec.boundaries) b.add_boundary(s);
  for (const auto& s : spec.stages) b.add_stage(s);
  b.finish_stages();
  for (const auto& s : spec.histories) b.add_history(s);
  if (spec.direct_shear) b.direct_shear(*spec.direct_shear);
  if (spec.drift) b.drift(*spec.drift);
  if (spec.output) b.output(*spec.output);
  return b.finish();
}

}  // namespace rockdem
