#pragma once
// The boundary kind "free_field": a one-dimensional column of the far field run beside a vertical
// side of the model, which drives the side through dashpots, so that a model can be narrow
// without the waves it scatters reflecting from its sides (Cundall et al. 1980, as in FLAC and
// UDEC). Equations, assumptions and limits: docs/seismic-input.md.
#include <vector>

#include "framework/boundary/conditions.hpp"

namespace rockdem {

// The column has a node at the height of every gridpoint of the side, elements between them with
// the elastic constants of the zone next to each side edge, and, where a joint crosses the side
// (two coincident gridpoints of different blocks), a spring with the joint's initial normal and
// shear stiffness (the free field stays elastic: the far-field joint neither slips nor opens).
// It is laterally uniform: vertical waves only (shear for x motions, compression for y ones).
// Its base takes the same motions as the model's (compliant with stress input, or rigid), its top
// is free or quiet, as the model's top must be (a quiet model top above free column tops makes a
// couple that turns the whole model), and it starts from rest: it carries the dynamic part of the motion only, the static
// stress being held by the reactions taken at the start (as QuietCondition).
//
// On the model's side gridpoint g of a side edge with outward normal n, tangent t and length L:
//   f = L/2 [ sigma_ff n + rho (Cp ((v_ff - v).n) n + Cs ((v_ff - v).t) t) ]
// (the far field's traction and dashpots on the velocity relative to it).
class FreeFieldCondition final : public BoundaryCondition {
 public:
  struct Node {
    int gp = -1;            // the model gridpoint beside it
    double mass = 0.0;      // per unit width of column [kg/m per m]
    Vec2 u = Vec2::Zero(), v = Vec2::Zero(), f = Vec2::Zero();
  };
  struct Element {  // a column segment between nodes a (below) and b (above)
    int a = 0, b = 0;
    double length = 0.0, rho = 0.0, lambda = 0.0, shear = 0.0;  // [m, kg/m3, Pa, Pa]
    double cp() const { return std::sqrt((lambda + 2.0 * shear) / rho); }
    double cs() const { return std::sqrt(shear / rho); }
  };
  struct Spring {  // a joint crossing the side: nodes a (below) and b (above), stiffness [Pa/m]
    int a = 0, b = 0;
    double kn = 0.0, ks = 0.0;
  };
  struct SideEdge {  // a model edge on the side, the element beside it, its ends' nodes
    int ga = 0, gb = 0, element = 0, na = 0, nb = 0;
  };
  struct Ends {  // the column's base and top
    bool rigid_base = false;  // else compliant: the stress input through the base's dashpots
    bool quiet_top = false;   // else free: waves reaching the top reflect (as from a free surface)
  };

  FreeFieldCondition(std::vector<FaceSelection> sels, std::vector<Node> nodes, std::vector<Element> elements,
                     std::vector<Spring> springs, std::vector<SideEdge> edges, Ends ends, bool hold_static);
  std::string describe(const Model& m) const override;
  void setup(Model& m) override;
  void deactivated() override;
  double forces(Model& m, double t) override;
  void end_step(const Model& m, double dt) override;
  void add_dashpots(const Model& m, std::vector<double>& c) const override;
  void set_motions(const std::vector<StageMotion>& motions) override;
  std::vector<double> saved_state() const override;
  void restore_state(const std::vector<double>& s) override;
  bool renumber(const Renumbering& r) override;

  // For tests: the column as it moves.
  const std::vector<Node>& nodes() const { return nodes_; }

 private:
  void column_forces(double t);
  Vec2 element_strain(const Element& e) const;  // (shear strain, vertical strain)
  std::vector<FaceSelection> sels_;
  std::vector<Node> nodes_;
  std::vector<Element> elements_;
  std::vector<Spring> springs_;
  std::vector<SideEdge> edges_;
  bool rigid_base_, quiet_top_, hold_static_;
  int top_element_ = 0;  // the element below the top node (its impedance for a quiet top)
  static constexpr int kBase = 0;  // the lowest node: nodes are sorted by height
  double time_ = 0.0;     // stage time of the column
  double stable_dt_ = 0.0;
  std::vector<StageMotion> motions_;
  bool held_ = false;
  std::vector<Vec2> hold_;  // per node (its model gridpoint)
};

}  // namespace rockdem
