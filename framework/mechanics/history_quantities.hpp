#pragma once
// The quantities a case can record as histories (`[[histories]] quantity = "..."`), each defined
// once, in history_quantities.cpp: its name, the parameters it needs, its unit and description,
// how it is measured on a model and engine, and how values from several processes combine. The
// case reader validates names here, the case builder checks parameters against it, and the
// recorder measures through it.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "framework/core/registry.hpp"
#include "framework/model/communication.hpp"
#include "framework/model/model.hpp"

namespace rockdem {

class Engine;

// What one history measures on: the members the quantity's parameters name are set.
struct HistoryTarget {
  int block = -1;
  int component = 0;        // index into HistoryQuantity::components
  std::vector<int> points;  // gridpoints of a block face
  // Quantities by location (needs_point): the point `at` [m], or with `segment` the joint
  // segment from `at` to `to`.
  Vec2 at = Vec2::Zero(), to = Vec2::Zero();
  bool segment = false;
};

// Where the value of a quantity comes from in a domain-decomposed run (partition.hpp); the
// recorder (framework/simulation/recorder.cpp) gets it accordingly.
enum class Reduction {
  global,  // the engine has combined the processes' parts already: the same on every process
  owner,   // held by the engine of the process owning the target block (its contact forces)
  state,   // read from the model's state, made current on the recording process first
};

struct HistoryQuantity {
  std::string name;
  std::string unit;  // SI; the default label of the series
  std::string description;
  bool needs_block = false;             // `block` names the block measured
  bool rigid_only = false;              // the block must be rigid
  bool needs_face = false;              // `face` names a face of the block (its gridpoints are measured)
  std::vector<std::string> components;  // accepted `component`s, the first is the default; empty: none
  Reduction reduction = Reduction::state;
  std::function<double(const Model&, const Engine&, const HistoryTarget&)> measure;
  bool needs_point = false;    // `at` (and optionally `to`) locate what is measured
  bool takes_segment = false;  // `to` may be given: averaged over the joint segment at..to
  // With Reduction::state: the parts of the state it reads besides the blocks' motion and the
  // gridpoints (communication.hpp's StateParts: zone stresses, contacts).
  unsigned state_parts = 0;
};

// Quantities by name; listed (in messages) in name order.
class HistoryQuantities : public NamedTable<HistoryQuantity> {
 public:
  static HistoryQuantities& instance();
  // Throws an InputError at `where` listing the valid names when `name` is unknown.
  const HistoryQuantity& get(const std::string& name, const std::string& where) const {
    return NamedTable::get(name, "quantity", where, "valid: ");
  }
};

// Registers a quantity at static initialisation: `const HistoryQuantityRegistrar r{HistoryQuantity{...}};`
struct HistoryQuantityRegistrar {
  explicit HistoryQuantityRegistrar(HistoryQuantity q) { HistoryQuantities::instance().add(std::move(q)); }
};

}  // namespace rockdem
