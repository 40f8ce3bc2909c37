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

// How the values of the processes of a parallel run combine into the history's value. Declared
// so that each quantity states it now; a parallel recorder will apply it.
enum class Reduction {
  sum,    // every process holds a part (e.g. contact forces of its contacts)
  max,    // every process holds a bound, the largest one applies
  min,    // e.g. the time step: the smallest one applies
  owner,  // only the process owning the block holds it
};

struct HistoryQuantity {
  std::string name;
  std::string unit;  // SI; the default label of the series
  std::string description;
  bool needs_block = false;             // `block` names the block measured
  bool rigid_only = false;              // the block must be rigid
  bool needs_face = false;              // `face` names a face of the block (its gridpoints are measured)
  std::vector<std::string> components;  // accepted `component`s, the first is the default; empty: none
  Reduction reduction = Reduction::sum;
  std::function<double(const Model&, const Engine&, const HistoryTarget&)> measure;
  bool needs_point = false;    // `at` (and optionally `to`) locate what is measured
  bool takes_segment = false;  // `to` may be given: averaged over the joint segment at..to
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
