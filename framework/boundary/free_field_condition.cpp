#include "framework/boundary/free_field_condition.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "framework/boundary/condition_kinds.hpp"
#include "framework/boundary/quiet_condition.hpp"
#include "framework/core/error.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {

FreeFieldCondition::FreeFieldCondition(std::vector<FaceSelection> sels, std::vector<Node> nodes,
                                       std::vector<Element> elements, std::vector<Spring> springs,
                                       std::vector<SideEdge> edges, Ends ends, bool hold_static)
    : sels_(std::move(sels)),
      nodes_(std::move(nodes)),
      elements_(std::move(elements)),
      springs_(std::move(springs)),
      edges_(std::move(edges)),
      rigid_base_(ends.rigid_base),
      quiet_top_(ends.quiet_top),
      hold_static_(hold_static) {
  const int top = static_cast<int>(nodes_.size()) - 1;  // nodes are sorted by height
  for (std::size_t i = 0; i < elements_.size(); ++i)
    if (elements_[i].b == top) top_element_ = static_cast<int>(i);
  // Gershgorin bound on the column's own stable step (its nodes have no other stiffness).
  std::vector<double> k(nodes_.size(), 0.0);
  for (const Element& e : elements_) {
    const double ke = 2.0 * (e.lambda + 2.0 * e.shear) / e.length;
    k[static_cast<std::size_t>(e.a)] += ke;
    k[static_cast<std::size_t>(e.b)] += ke;
  }
  for (const Spring& s : springs_) {
    const double ks = 2.0 * std::max(s.kn, s.ks);
    k[static_cast<std::size_t>(s.a)] += ks;
    k[static_cast<std::size_t>(s.b)] += ks;
  }
  stable_dt_ = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (k[i] > 0.0) stable_dt_ = std::min(stable_dt_, 0.5 * 2.0 * std::sqrt(nodes_[i].mass / k[i]));
}

std::string FreeFieldCondition::describe(const Model& m) const {
  std::ostringstream os;
  os << "free field beside " << sels_.size() << " block(s) from '" << m.blocks[sels_.front().block].name << "': "
     << nodes_.size() << " nodes, " << elements_.size() << " elements, " << springs_.size() << " joint springs, "
     << (rigid_base_ ? "rigid" : "compliant") << " base, " << (quiet_top_ ? "quiet" : "free") << " top"
     << (hold_static_ ? ", static reactions held" : "");
  return os.str();
}

void FreeFieldCondition::set_motions(const std::vector<StageMotion>& motions) {
  if (!rigid_base_)
    for (const auto& sm : motions)
      if (sm.motion->type == seismic::MotionType::within)
        throw InputError("motion '" + sm.motion->name + "' is a within record, which the free field's compliant base "
                         "cannot take: give it base = \"rigid\" as the model's");
  motions_ = motions;
  time_ = 0.0;
}

// The column starts again from rest with the reactions of the stage before the next active one:
// the stages in between (a return to equilibrium on fixed boundaries) settled the model, and the
// column carries only the motion since.
void FreeFieldCondition::deactivated() {
  held_ = false;
  hold_.clear();
  for (Node& n : nodes_) n.u = n.v = n.f = Vec2::Zero();
}

void FreeFieldCondition::setup(Model& m) {
  if (!hold_static_ || held_) return;
  held_ = true;
  hold_.resize(nodes_.size());
  // Taken away from the gridpoint once held (see QuietCondition::setup: a corner shared with the base).
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    hold_[i] = -m.gp[static_cast<std::size_t>(nodes_[i].gp)].f;
    m.gp[static_cast<std::size_t>(nodes_[i].gp)].f.setZero();
  }
}

Vec2 FreeFieldCondition::element_strain(const Element& e) const {
  return (nodes_[static_cast<std::size_t>(e.b)].u - nodes_[static_cast<std::size_t>(e.a)].u) / e.length;
}

void FreeFieldCondition::column_forces(double t) {
  for (Node& n : nodes_) n.f.setZero();
  for (const Element& e : elements_) {
    const Vec2 s = element_strain(e);
    const Vec2 stress(e.shear * s.x(), (e.lambda + 2.0 * e.shear) * s.y());  // (sigma_xy, sigma_yy)
    nodes_[static_cast<std::size_t>(e.a)].f += stress;
    nodes_[static_cast<std::size_t>(e.b)].f -= stress;
  }
  for (const Spring& s : springs_) {
    const Vec2 du = nodes_[static_cast<std::size_t>(s.b)].u - nodes_[static_cast<std::size_t>(s.a)].u;
    const Vec2 f(s.ks * du.x(), s.kn * du.y());
    nodes_[static_cast<std::size_t>(s.a)].f += f;
    nodes_[static_cast<std::size_t>(s.b)].f -= f;
  }
  if (!rigid_base_) {
    // The base element's impedance, per unit width of column.
    const Element& e = *std::find_if(elements_.begin(), elements_.end(), [&](const Element& x) { return x.a == kBase; });
    Node& b = nodes_[static_cast<std::size_t>(kBase)];
    const Vec2 dv = base_input(motions_, t, rigid_base_) - b.v;
    b.f += e.rho * Vec2(e.cs() * dv.x(), e.cp() * dv.y());
  }
  if (quiet_top_) {
    // Waves going up leave through the top, as they leave the model's quiet top: the column's
    // side shear then balances the moment of the base input against the model's top dashpots.
    const Element& e = elements_[static_cast<std::size_t>(top_element_)];
    Node& n = nodes_.back();
    n.f -= e.rho * Vec2(e.cs() * n.v.x(), e.cp() * n.v.y());
  }
}

void FreeFieldCondition::end_step(const Model&, double dt) {
  // The column is much cheaper than the model, so it sub-steps when the model's step is above its
  // own stable one (a stiff joint spring on a light node).
  const int sub = std::max(1, static_cast<int>(std::ceil(dt / stable_dt_)));
  const double h = dt / sub;
  for (int k = 0; k < sub; ++k) {
    column_forces(time_);
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      Node& n = nodes_[i];
      n.v += n.f / n.mass * h;
    }
    if (rigid_base_) nodes_[static_cast<std::size_t>(kBase)].v = base_input(motions_, time_ + h, rigid_base_);
    for (Node& n : nodes_) n.u += n.v * h;
    time_ += h;
  }
}

double FreeFieldCondition::forces(Model& m, double) {
  double applied = 0.0;
  for (const SideEdge& se : edges_) {
    const Element& e = elements_[static_cast<std::size_t>(se.element)];
    const Vec2 d = m.gp[static_cast<std::size_t>(se.gb)].x - m.gp[static_cast<std::size_t>(se.ga)].x;
    const double len = d.norm();
    const Vec2 tn = d / len, nrm(tn.y(), -tn.x());
    const Vec2 s = element_strain(e);
    const double sxx = e.lambda * s.y(), syy = (e.lambda + 2.0 * e.shear) * s.y(), sxy = e.shear * s.x();
    const Vec2 traction(sxx * nrm.x() + sxy * nrm.y(), sxy * nrm.x() + syy * nrm.y());
    for (auto [g, k] : {std::pair{se.ga, se.na}, std::pair{se.gb, se.nb}}) {
      if (!m.part.owns(m.gp[static_cast<std::size_t>(g)].block)) continue;  // another process's (partition.hpp)
      const Node& n = nodes_[static_cast<std::size_t>(k)];
      const Vec2 dv = n.v - m.gp[static_cast<std::size_t>(g)].v;
      const Vec2 f = 0.5 * len * (traction + e.rho * (e.cp() * dv.dot(nrm) * nrm + e.cs() * dv.dot(tn) * tn));
      m.gp[static_cast<std::size_t>(g)].f += f;
      applied += f.norm();
    }
  }
  if (held_)
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (!m.part.owns(m.gp[static_cast<std::size_t>(nodes_[i].gp)].block)) continue;
      m.gp[static_cast<std::size_t>(nodes_[i].gp)].f += hold_[i];
      applied += hold_[i].norm();
    }
  return applied;
}

void FreeFieldCondition::add_dashpots(const Model& m, std::vector<double>& c) const {
  for (const SideEdge& se : edges_) {
    const Element& e = elements_[static_cast<std::size_t>(se.element)];
    const double half = 0.5 * (m.gp[static_cast<std::size_t>(se.gb)].x - m.gp[static_cast<std::size_t>(se.ga)].x).norm();
    c[static_cast<std::size_t>(se.ga)] += e.rho * e.cp() * half;
    c[static_cast<std::size_t>(se.gb)] += e.rho * e.cp() * half;
  }
}

std::vector<double> FreeFieldCondition::saved_state() const {
  std::vector<double> s{held_ ? 1.0 : 0.0};
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    const Vec2 h = held_ ? hold_[i] : Vec2::Zero();
    s.insert(s.end(), {n.u.x(), n.u.y(), n.v.x(), n.v.y(), h.x(), h.y()});
  }
  s.push_back(time_);  // the column's clock: a run resumed within a stage goes on from it
  return s;
}

void FreeFieldCondition::restore_state(const std::vector<double>& s) {
  if (s.empty()) return;
  // Checkpoints written before the column's clock travelled in them hold one value less.
  if (s.size() != 1 + 6 * nodes_.size() && s.size() != 2 + 6 * nodes_.size())
    throw InputError("checkpoint: the free-field column's state does not match its " + std::to_string(nodes_.size()) + " nodes");
  if (s.size() == 2 + 6 * nodes_.size()) time_ = s.back();
  held_ = s[0] != 0.0;
  hold_.assign(nodes_.size(), Vec2::Zero());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const double* p = &s[1 + 6 * i];
    nodes_[i].u = Vec2(p[0], p[1]);
    nodes_[i].v = Vec2(p[2], p[3]);
    hold_[i] = Vec2(p[4], p[5]);
  }
}

bool FreeFieldCondition::renumber(const Renumbering& r) {
  // The side's blocks are far-field rock; excavating one of them removes the column.
  for (auto& sel : sels_)
    if (!rockdem::renumber(sel, r)) return false;
  if (r.gp.empty()) return true;
  for (Node& n : nodes_) n.gp = r.gp[static_cast<std::size_t>(n.gp)];
  for (SideEdge& e : edges_) {
    e.ga = r.gp[static_cast<std::size_t>(e.ga)];
    e.gb = r.gp[static_cast<std::size_t>(e.gb)];
  }
  return true;
}

namespace {

// The zone of a deformable block that has both gridpoints as corners.
int zone_with(const Model& m, const Block& b, int ga, int gb) {
  for (int z = b.first_zone; z < b.first_zone + b.n_zone; ++z) {
    const auto& n = m.zones[static_cast<std::size_t>(z)].n;
    const bool a = std::count(n.begin(), n.end(), ga) > 0, c = std::count(n.begin(), n.end(), gb) > 0;
    if (a && c) return z;
  }
  return -1;
}

// The label of the joint between the two blocks at a crossing gridpoint: the label of an edge of
// the lower block at that point that is not on the side (its top face along the joint).
int crossing_label(const Model& m, int block, int gp, const std::vector<int>& side_edges) {
  const Block& b = m.blocks[static_cast<std::size_t>(block)];
  const int n = static_cast<int>(b.boundary.size());
  for (int i = 0; i < n; ++i) {
    const bool touches = b.boundary[static_cast<std::size_t>(i)] == gp || b.boundary[static_cast<std::size_t>((i + 1) % n)] == gp;
    if (touches && std::find(side_edges.begin(), side_edges.end(), i) == side_edges.end()) return b.edge_label(i);
  }
  return -1;
}

std::unique_ptr<BoundaryCondition> make_free_field(const ConditionInput& in, const std::vector<FaceSelection>& all) {
  const Model& m = in.model;
  bool rigid_base = false;
  if (const ConditionValue* v = in.value("base")) {
    const std::string& s = v->names.front();
    if (s != "compliant" && s != "rigid")
      throw InputError(v->where + ": unknown base '" + s + "'; valid: compliant, rigid (as the model's seismic base)");
    rigid_base = s == "rigid";
  }
  bool quiet_top = false;
  if (const ConditionValue* v = in.value("top")) {
    const std::string& s = v->names.front();
    if (s != "free" && s != "quiet")
      throw InputError(v->where + ": unknown top '" + s + "'; valid: free, quiet (as the model's top: quiet when a quiet "
                       "boundary is on it)");
    quiet_top = s == "quiet";
  }
  for (const char* k : {"cp", "cs", "density"})
    if (const ConditionValue* v = in.value(k))
      throw InputError(v->where + ": a free field takes the elastic constants of the zones beside the side; '" + k +
                       "' is for quiet boundaries on rigid blocks");
  using Node = FreeFieldCondition::Node;
  std::vector<Node> nodes;
  std::vector<FreeFieldCondition::SideEdge> edges;
  std::vector<FreeFieldCondition::Element> elements;
  std::vector<int> node_block;
  double top = -std::numeric_limits<double>::max(), bottom = std::numeric_limits<double>::max();
  for (const FaceSelection& sel : all) {
    const Block& b = m.blocks[static_cast<std::size_t>(sel.block)];
    if (b.rigid)
      throw InputError(in.where + ": block '" + b.name + "' on the free-field side is rigid; the free field needs "
                       "deformable blocks along the side (their zones give the column's elastic constants). Use "
                       "type = \"quiet\" on rigid blocks");
    for (int g : sel.points) {
      nodes.push_back(Node{g, 0.0, Vec2::Zero(), Vec2::Zero(), Vec2::Zero()});
      node_block.push_back(sel.block);
      top = std::max(top, m.gp[static_cast<std::size_t>(g)].x.y());
      bottom = std::min(bottom, m.gp[static_cast<std::size_t>(g)].x.y());
    }
  }
  const double height = top - bottom;
  if (!(height > 0.0)) throw InputError(in.where + ": the free-field side has no height");
  // Nodes by height; at a joint crossing the lower block's point comes first.
  std::vector<std::size_t> order(nodes.size());
  std::iota(order.begin(), order.end(), 0);
  auto y = [&](std::size_t i) { return m.gp[static_cast<std::size_t>(nodes[i].gp)].x.y(); };
  std::map<int, double> block_y;
  for (std::size_t i = 0; i < nodes.size(); ++i) block_y[node_block[i]] += y(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (std::abs(y(a) - y(b)) > 1e-9 * height) return y(a) < y(b);
    return block_y[node_block[a]] < block_y[node_block[b]];
  });
  std::vector<Node> sorted;
  std::vector<int> sorted_block;
  std::map<int, int> node_of;
  for (std::size_t i : order) {
    node_of[nodes[i].gp] = static_cast<int>(sorted.size());
    sorted.push_back(nodes[i]);
    sorted_block.push_back(node_block[i]);
  }
  // Elements from the side edges, which must be vertical.
  double side_normal = 0.0;
  for (const FaceSelection& sel : all) {
    const Block& b = m.blocks[static_cast<std::size_t>(sel.block)];
    const int nb = static_cast<int>(b.boundary.size());
    for (int i : sel.edges) {
      const int ga = b.boundary[static_cast<std::size_t>(i)], gb = b.boundary[static_cast<std::size_t>((i + 1) % nb)];
      const Vec2 d = m.gp[static_cast<std::size_t>(gb)].x - m.gp[static_cast<std::size_t>(ga)].x;
      if (std::abs(d.x()) > 1e-6 * d.norm())
        throw InputError(in.where + ": the free field needs a vertical side; an edge of block '" + b.name + "' on it runs from (" +
                         std::to_string(m.gp[static_cast<std::size_t>(ga)].x.x()) + ", " +
                         std::to_string(m.gp[static_cast<std::size_t>(ga)].x.y()) + ") to (" +
                         std::to_string(m.gp[static_cast<std::size_t>(gb)].x.x()) + ", " +
                         std::to_string(m.gp[static_cast<std::size_t>(gb)].x.y()) + ")");
      const double nx = d.y() > 0 ? 1.0 : -1.0;  // outward normal x of a counter-clockwise edge
      if (side_normal != 0.0 && nx != side_normal)
        throw InputError(in.where + ": the free-field region takes edges facing both left and right; give one side per condition");
      side_normal = nx;
      const int z = zone_with(m, b, ga, gb);
      if (z < 0) throw InputError(in.where + ": no zone of block '" + b.name + "' lies along its side edge " + std::to_string(i));
      const auto& mat = *m.materials[static_cast<std::size_t>(m.zones[static_cast<std::size_t>(z)].material)];
      FreeFieldCondition::Element e;
      const bool up = d.y() > 0;
      e.a = node_of.at(up ? ga : gb);
      e.b = node_of.at(up ? gb : ga);
      e.length = std::abs(d.y());
      e.rho = mat.density();
      e.shear = mat.shear_modulus();
      e.lambda = mat.bulk_modulus() - 2.0 * e.shear / 3.0;
      const double share = 0.5 * e.rho * e.length;
      sorted[static_cast<std::size_t>(e.a)].mass += share;
      sorted[static_cast<std::size_t>(e.b)].mass += share;
      edges.push_back({ga, gb, static_cast<int>(elements.size()), node_of.at(ga), node_of.at(gb)});
      elements.push_back(e);
    }
  }
  // Joint springs between coincident nodes of different blocks.
  std::vector<FreeFieldCondition::Spring> springs;
  for (std::size_t i = 0; i + 1 < sorted.size(); ++i) {
    const double ya = m.gp[static_cast<std::size_t>(sorted[i].gp)].x.y(), yb = m.gp[static_cast<std::size_t>(sorted[i + 1].gp)].x.y();
    if (std::abs(yb - ya) > 1e-9 * height || sorted_block[i] == sorted_block[i + 1]) continue;
    const int lower = sorted_block[i], upper = sorted_block[i + 1];
    std::vector<int> lower_side;
    for (const FaceSelection& sel : all)
      if (sel.block == lower) lower_side = sel.edges;
    const int label = crossing_label(m, lower, sorted[i].gp, lower_side);
    const auto& store = m.contacts;
    const auto& jm = *store.models[static_cast<std::size_t>(store.model_for(
        m.blocks[static_cast<std::size_t>(lower)].group, m.blocks[static_cast<std::size_t>(upper)].group, label))];
    springs.push_back({static_cast<int>(i), static_cast<int>(i + 1), jm.initial_kn(), jm.initial_ks()});
  }
  for (std::size_t i = 0; i < sorted.size(); ++i)
    if (!(sorted[i].mass > 0.0))
      throw InputError(in.where + ": the free-field side has a gridpoint with no side edge (the region must cover whole edges)");
  if (std::none_of(elements.begin(), elements.end(), [](const auto& e) { return e.a == 0; }))
    throw InputError(in.where + ": the lowest point of the free-field side has no side edge above it");
  return std::make_unique<FreeFieldCondition>(all, std::move(sorted), std::move(elements), std::move(springs),
                                              std::move(edges), FreeFieldCondition::Ends{rigid_base, quiet_top},
                                              hold_static_reactions(in));
}

std::unique_ptr<BoundaryCondition> make_single(const ConditionInput& in) { return make_free_field(in, {in.selection}); }

std::vector<ConditionKey> free_field_keys() {
  std::vector<ConditionKey> k{{"base", ConditionKey::Type::choice, Dimension::dimensionless,
                               "compliant (default) or rigid: the column's base, as the model's seismic base"},
                              {"top", ConditionKey::Type::choice, Dimension::dimensionless,
                               "free (default) or quiet: the column's top, as the model's top (quiet when a quiet "
                               "boundary lets waves leave through it)"}};
  for (auto& d : dashpot_keys()) k.push_back(std::move(d));
  return k;
}

const ConditionKindRegistrar free_field_kind{60, ConditionKind{
    "free_field", "a 1D far-field column beside a vertical side, driving it through dashpots (deformable blocks)",
    free_field_keys(), false, make_single, make_free_field}};

}  // namespace
}  // namespace rockdem
