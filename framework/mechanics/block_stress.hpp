#pragma once
// The mean stress of each block. For a body in equilibrium the mean of the stress over its area A
// follows from the forces on its boundary alone (the divergence theorem applied to x_i sigma_kj):
//   mean sigma_ij = (1/A) sum_k (x_k - x_c)_i f_k,j ,
// symmetrised, with f_k the forces at boundary points x_k and x_c the centroid (Love 1927; in DEM
// the particle stress of Christoffersen, Mehrabadi and Nemat-Nasser 1981). Measured from the
// centroid, a uniform body force (gravity) adds nothing.
// Rigid blocks have no strain and hence no constitutive stress: this is the stress they carry, and
// the VTK fields show it in their place. Their gridpoints' forces of the last step are exactly the
// contact and boundary forces (gravity and damping act on the block as a whole, and a contact's
// force at a point of an edge, split to the edge's ends in proportion, keeps its first moment), so
// the sum runs over them. Out of equilibrium the sum also holds the inertial part.
// A rigid block held in place or driven (Block::fixed, Block::prescribed) takes reactions that are
// no forces of the model, so its mean stress is not known: NaN.
// Deformable blocks: the area-weighted mean of their zones' stresses.
#include <vector>

#include "framework/core/types.hpp"

namespace rockdem {

struct Model;
struct Block;

// Per block (Model::blocks order): mean in-plane stress (sxx, syy, sxy) [Pa], tension positive;
// NaN for a held rigid block.
std::vector<Voigt3> block_mean_stress(const Model& m);

// Whether block_mean_stress knows the block's stress: deformable, or rigid and free to move.
bool block_stress_known(const Block& b);

}  // namespace rockdem
