#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <ostream>

namespace rockdem {

using Vec2 = Eigen::Vector2d;
// In-plane stress or strain in Voigt order (xx, yy, xy); plane strain, zz tracked separately.
using Voigt3 = Eigen::Vector3d;

// Global ids do not depend on how blocks are split among ranks or removed by an excavation: blocks
// are numbered in case-file order, gridpoints by (block id, local index). Contacts are keyed by
// these. A block id is its own type, not an int: the blocks' array is indexed by position
// (GridPoint::block, Contact::other), and an id cannot be used as one by mistake
// (Model::position_of finds a block's position from its id).
enum class BlockId : std::int32_t {};
constexpr std::int32_t id_value(BlockId id) { return static_cast<std::int32_t>(id); }
inline std::ostream& operator<<(std::ostream& os, BlockId id) { return os << id_value(id); }
using LocalIndex = std::int32_t;

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
inline Vec2 perp(const Vec2& a) { return {-a.y(), a.x()}; }  // a rotated +90 degrees

}  // namespace rockdem
