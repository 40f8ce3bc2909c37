#pragma once
// Case-file text and placement helpers for the contact-geometry checks that build blocks of any
// outline (test_corner_readings.cpp, test_deep_contacts.cpp, test_held_contacts.cpp). Blocks may
// not overlap in a case file, so a check that needs a point pressed into a face moves the block
// after parsing.
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "framework/io/case.hpp"

namespace rockdem::polygon_case {

// A rigid block of density 2650 kg/m3 with the given outline (counter-clockwise, metres), as [[blocks]].
inline std::string rigid_block(const std::string& name, const std::vector<Vec2>& pts) {
  std::ostringstream os;
  os.precision(17);
  os << "[[blocks]]\nname = \"" << name << "\"\ntype = \"rigid\"\ndensity = \"2650 kg/m3\"\npolygon = [";
  for (std::size_t i = 0; i < pts.size(); ++i)
    os << (i ? ", " : "") << "[\"" << pts[i].x() << " m\", \"" << pts[i].y() << " m\"]";
  os << "]\n";
  return os.str();
}

// Every case needs a stage; these checks call detection directly.
inline const std::string kOneStep = "[[stages]]\nname = \"s\"\nuntil = \"steps\"\nsteps = 1\n";

inline const Block& block(const Case& c, const std::string& name) {
  return c.model.blocks[static_cast<std::size_t>(c.block_index(name, "test"))];
}

// Moves every gridpoint of block `name` by `by`.
inline void translate(Case& c, const std::string& name, const Vec2& by) {
  const Block& b = block(c, name);
  for (int i = b.first_gp; i < b.first_gp + b.n_gp; ++i) c.model.gp[static_cast<std::size_t>(i)].x += by;
}

// Moves block `name` so that its boundary point `local` is at `to`.
inline void place(Case& c, const std::string& name, int local, const Vec2& to) {
  const Block& b = block(c, name);
  translate(c, name, to - c.model.gp[static_cast<std::size_t>(b.boundary[static_cast<std::size_t>(local)])].x);
}

// The contacts of block a's boundary point `local` on block b.
inline std::vector<Contact*> contacts_of(Case& c, const std::string& a, int local, const std::string& b) {
  const BlockId ia = block(c, a).id, ib = block(c, b).id;
  std::vector<Contact*> out;
  for (Contact& k : c.model.contacts.items)
    if (k.key.point_block == ia && k.key.point_local == local && k.key.other_block == ib) out.push_back(&k);
  return out;
}

}  // namespace rockdem::polygon_case
