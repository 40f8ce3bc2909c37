#pragma once
// Blocks and zone mechanics: building rigid and deformable blocks into a Model, and the
// constant-strain-triangle (CST) force and stiffness computation for deformable blocks.
//
// Zones follow the explicit finite-difference form of UDEC/FLAC (Itasca UDEC theory, "deformable
// blocks"; Cundall & Hart 1985): strain rates from gridpoint velocities, stress from the zone's
// rock material, gridpoint forces from the zone stresses. Plane strain, tension positive.
#include <string>

#include "framework/geometry/mesh.hpp"
#include "framework/model/model.hpp"

namespace rockdem {

// Append a rigid block. The polygon may be given in either orientation; it is stored counter-
// clockwise with its first vertex kept first. Fills mass = density*area, inertia = density*polar
// second moment about the centroid, the centroid (xc0 = xc), rest_offsets (vertex - centroid at
// theta = 0) and one gridpoint per vertex (boundary loop = all of them, in order). Rigid-block
// gridpoints carry no mass or stiffness of their own: the block's mass and inertia are in Block.
// Throws InputError for a non-simple polygon or non-positive density. Returns the block id
// (= index in Model::blocks; ids follow the order of addition).
int add_rigid_block(Model& m, const Polygon& polygon, double density, const std::string& name, int group);

// Append a deformable block meshed as `mesh` (its nodes become the block's gridpoints in mesh
// order, so boundary[i] = first_gp + mesh.boundary[i]). Lumped gridpoint masses density*area/3 per
// zone node; block mass, centroid and inertia are filled for diagnostics. Zone material states are
// initialised by the material. Returns the block id.
int add_deformable_block(Model& m, const TriMesh& mesh, int material, const std::string& name, int group);

// Zone update for one step of the explicit scheme; call it once per step after the gridpoint
// positions have been advanced, with GridPoint::v the velocities that produced that advance
// (v at t - dt/2 in central differences, x at t). For each zone:
//  1. strain rate and spin from the velocities and the CST shape-function gradients (B matrix) of
//     the mid-step configuration x - v dt/2, not the initial one. The increment then measures the
//     stretch the position update really made: a rigid rotation of any size per step, moved as
//     x += (R - I) x, gives exactly zero strain (the mid-point rule of Hughes & Winget 1980),
//     whereas an initial-configuration B reads a block turned by theta as a strain of order
//     (1 - cos theta) and stresses it spuriously.
//  2. the stress (and the accumulated strain) is turned with the zone's rotation over the step
//     (sigma <- R sigma R^T, the angle recovered exactly from the mid-step spin), so that a
//     pre-stressed block that rotates carries its stress with it: the objective (Jaumann-type)
//     correction of FLAC's large-strain mode. Strains are small otherwise (no finite-strain measure).
//  3. the strain increment rate*dt goes through the rock material (Zone::stress, Zone::szz,
//     material_state).
//  4. stiffness-proportional Rayleigh damping stress beta*D*rate (D the plane-strain elastic
//     matrix) is added to the forces of this step only, not to Zone::stress.
//  5. gridpoint forces f -= A * B^T * sigma with the current area and B (forces at time t),
//     added to GridPoint::f.
// Throws InstabilityError naming the zone, its block and the step if a zone turns inside out.
// With threads > 1 the zones are updated on that many threads (core/threads.hpp); the forces are
// added to the gridpoints in zone order all the same, so the results are those of one thread.
void zone_forces(Model& m, double dt, double beta_stiffness, int threads = 1);

// Adds to GridPoint::stiffness, for gridpoints of deformable blocks, the absolute row sum of
// each zone's stiffness matrix A*B^T*D*B over the gridpoint's two rows (the larger of the x and y
// rows), D built from K + 4G/3 and K - 2G/3 (plane strain). By Gershgorin's theorem, max_i
// k_i/m_i bounds the largest eigenvalue of M^-1 K, so central differences with lumped masses
// are stable (undamped) for dt <= 2 min_i sqrt(m_i/k_i) (Belytschko, Liu & Moran, Nonlinear Finite
// Elements for Continua and Structures, ch. 6). Uses the current positions. Threads as zone_forces.
void zone_stiffness(Model& m, int threads = 1);

// Plane-strain isotropic elastic matrix acting on (exx, eyy, gxy) [Pa].
Eigen::Matrix3d plane_strain_elasticity(double bulk, double shear);

}  // namespace rockdem
