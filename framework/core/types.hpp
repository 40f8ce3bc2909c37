#pragma once
#include <Eigen/Core>
#include <cstdint>

namespace rockdem {

using Vec2 = Eigen::Vector2d;
// In-plane stress or strain in Voigt order (xx, yy, xy); plane strain, zz tracked separately.
using Voigt3 = Eigen::Vector3d;

// Global ids do not depend on how blocks are split among ranks: blocks are numbered in case-file
// order, gridpoints by (block id, local index). Contacts are keyed by these.
using BlockId = std::int32_t;
using LocalIndex = std::int32_t;

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
inline Vec2 perp(const Vec2& a) { return {-a.y(), a.x()}; }  // a rotated +90 degrees

}  // namespace rockdem
