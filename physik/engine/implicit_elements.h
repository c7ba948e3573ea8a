// What a point element adds to the implicit step's recursion (implicit_step.h): a force element
// that acts at a point of a body (a control spring, a damper at a bone's end, a contact) enters
// the augmented inertias as Phi^T A Phi, Phi the point's velocity map from the body's spatial
// velocity about its point o, and its velocity-product share as a bias force. Every force's file
// that has implicit terms (forces.h) uses these; they hold no state.
//   Phi = [-[r]x  1],  Phi^T A Phi = [[r]x A [r]x^T   [r]x A;  A [r]x^T   A]  (angular first)
// Featherstone, Rigid Body Dynamics Algorithms (2008) 2.8 (a point's velocity) and 7.3 (the
// articulated inertia's blocks). Units: A in N s/m (a damper) or N s^2/m (h^2 K), r in rig units.
#pragma once

#include "physik/engine/articulated_body.h"
#include "physik/model/types.h"

namespace physik {

// Phi^T A Phi for a point element A at offset r from the body's point: adds to `inertia`
void add_point_inertia(const Mat3& A, const Vec3& r, SpatialInertia& inertia);
// A point element's whole share of the step : Phi^T A Phi into the
// body's inertia, and -Phi^T A Phi a0 (its velocity-product share, a0 = state.implicit.accel_bias
// of the body) into its bias force.
void add_point_element(const Mat3& A, const Vec3& r, const Vec6& a0, SpatialInertia& inertia,
                       Vec6& bias);
// A couple element (a torque on the body's own turn, an orientation spring's): A in N m s/rad (a
// rotational damper) or N m s^2/rad (h^2 K), its map [1 0], so A joins the inertia's angular
// block alone, and -A w0 (w0 the angular part of a0) its bias force, whatever the body's point.
void add_couple_element(const Mat3& A, const Vec6& a0, SpatialInertia& inertia, Vec6& bias);
// The coupling of a couple element and a point element at offset r on the same body (an aim's,
// whose potential couples the bone's turn and its head): A the block of the couple's rows and the
// point's columns, A^T its mirror, so c^T A Phi + Phi^T A^T c (c = [1 0] the couple's map), a
// symmetric 6x6, joins the inertia, and minus it times a0 the bias force.
void add_couple_point_element(const Mat3& A, const Vec3& r, const Vec6& a0, SpatialInertia& inertia,
                              Vec6& bias);

}  // namespace physik
