#pragma once
// Name -> factory registries for joint laws, effects and rock materials. Each object registers
// itself in its own source file with a static Registrar, so adding one touches no central list.
// Registries are function-local statics (no global mutable state visible to physics code).
// Besides the factory, an entry carries what a kind of product declares about itself for the
// tools that use it (`Declarations`, e.g. which parameters calibration keeps fixed), so that
// those tools keep no list of names either.
#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "framework/core/did_you_mean.hpp"
#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/params.hpp"

#define ROCKDEM_CONCAT_INNER(a, b) a##b
#define ROCKDEM_CONCAT(a, b) ROCKDEM_CONCAT_INNER(a, b)

namespace rockdem {

// Named entries filled at static initialisation by registrars beside each definition (joint
// laws, effects, rock materials, boundary-condition kinds, history quantities, subcommands):
// lookup by name, an unknown name answered with the valid ones (OpenFOAM-style), and one listing
// order. Entries are listed by rank, then by name: a table whose entries register from several
// source files (whose initialisation order is not defined) keeps a chosen order through ranks;
// with the default rank the order is alphabetical. Entries are held in a map, so pointers to
// them stay valid while others register.
template <class Entry>
class NamedTable {
 public:
  // Adds `e`, or replaces the entry of the same name.
  void add(Entry e, int rank = 0) {
    const std::string name = e.name;
    entries_.insert_or_assign(name, Ranked{rank, std::move(e)});
    std::vector<const Ranked*> listed;
    for (const auto& [n, r] : entries_) listed.push_back(&r);  // name order
    std::stable_sort(listed.begin(), listed.end(), [](const Ranked* a, const Ranked* b) { return a->rank < b->rank; });
    order_.clear();
    for (const Ranked* r : listed) order_.push_back({r->entry.name, r->entry});
  }
  const Entry* find(const std::string& name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : &it->second.entry;
  }
  // Throws "<where>: unknown <what> '<name>' (did you mean '<nearest>'?); <valid><the names>"
  // when the name is unknown (the did-you-mean only when a valid name is close).
  const Entry& get(const std::string& name, const std::string& what, const std::string& where,
                   const std::string& valid = "valid names: ") const {
    if (const Entry* e = find(name)) return *e;
    throw InputError(where + ": unknown " + what + " '" + name + "'" +
                     did_you_mean(name, order_, [](const Listed& l) -> const std::string& { return l.name; }) +
                     "; " + valid + names_joined());
  }
  // The entries in listing order: `for (const auto& [name, entry] : table.entries())`.
  struct Listed {
    const std::string& name;
    const Entry& entry;
  };
  const std::vector<Listed>& entries() const { return order_; }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const Listed& l : order_) out.push_back(l.name);
    return out;
  }
  std::string names_joined() const { return join_names(order_, [](const Listed& l) -> const std::string& { return l.name; }); }

 private:
  struct Ranked {
    int rank = 0;
    Entry entry;
  };
  std::map<std::string, Ranked> entries_;
  std::vector<Listed> order_;
};

// A product that declares nothing beyond its parameters.
struct NoDeclarations {};

template <class Product, class Declarations = NoDeclarations>
struct RegistryEntry {
  std::string name;
  std::string summary;
  std::string reference;
  std::vector<ParamInfo> params;
  std::function<std::unique_ptr<Product>(const RawValues&, const std::string& where)> make;
  Declarations declared{};
};

// Name -> factory registry of one kind of plug-in.
template <class Product, class Declarations = NoDeclarations>
class Registry : public NamedTable<RegistryEntry<Product, Declarations>> {
 public:
  using Entry = RegistryEntry<Product, Declarations>;
  static Registry& instance() {
    static Registry r;
    return r;
  }
};

}  // namespace rockdem
