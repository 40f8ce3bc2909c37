#pragma once
// Name -> factory registries for joint laws, effects and rock materials. Each object registers
// itself in its own source file with a static Registrar, so adding one touches no central list.
// Registries are function-local statics (no global mutable state visible to physics code).
// Besides the factory, an entry carries what a kind of product declares about itself for the
// tools that use it (`Declarations`, e.g. which parameters calibration keeps fixed), so that
// those tools keep no list of names either.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/core/names.hpp"
#include "framework/core/params.hpp"

#define ROCKDEM_CONCAT_INNER(a, b) a##b
#define ROCKDEM_CONCAT(a, b) ROCKDEM_CONCAT_INNER(a, b)

namespace rockdem {

// A product that declares nothing beyond its parameters.
struct NoDeclarations {};

template <class Product, class Declarations = NoDeclarations>
class Registry {
 public:
  struct Entry {
    std::string name;
    std::string summary;
    std::string reference;
    std::vector<ParamInfo> params;
    std::function<std::unique_ptr<Product>(const RawValues&, const std::string& where)> make;
    Declarations declared{};
  };

  static Registry& instance() {
    static Registry r;
    return r;
  }
  void add(Entry e) { entries_[e.name] = std::move(e); }
  const Entry* find(const std::string& name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : &it->second;
  }
  // Throws an InputError listing the valid names (OpenFOAM-style) when the name is unknown.
  const Entry& get(const std::string& name, const std::string& what, const std::string& where) const {
    if (const Entry* e = find(name)) return *e;
    throw InputError(where + ": unknown " + what + " '" + name + "'; valid names: " + names_joined());
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [n, e] : entries_) out.push_back(n);
    return out;
  }
  std::string names_joined() const { return join_keys(entries_); }
  const std::map<std::string, Entry>& entries() const { return entries_; }

 private:
  std::map<std::string, Entry> entries_;
};

}  // namespace rockdem
