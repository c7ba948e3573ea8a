// Contacts and gravity: the forces of a floor and of a rig touching itself, in every scheme
// (forces.h), and their potential energy for the run monitor's energy rule and the implicit
// step's energy guard (potential.h). Detection is collision.h's.
//
// Contact force law, per contact found at the state (bodies a, b; point p; unit normal n from b
// toward a; depth d > 0): with v = v_a(p) - v_b(p) the relative velocity of the two bodies'
// material points at p (v_b = 0 for the ground and obstacles), v_n = v . n and v_t = v - v_n n,
//   normal    F_n = max(0, k d - c v_n)      a penalty spring with a damper (compliant, like
//                                            MuJoCo's soft contacts), never pulling
//   friction  F_t = -mu F_n v_t / max(|v_t|, v_s)
//                                            regularised Coulomb: viscous below the slip speed
//                                            v_s, |F_t| = mu F_n above it
//   on a: F_n n + F_t at p; on b (a bone): the opposite, at the same point (no net torque)
// with k = contact_k (N/m), c = contact_damping (N s/m), mu = friction, v_s = friction_speed
// (rig units/s) (params.h). At rest under a load W along n the spring sinks by d = W / k.
//
// Energy: U_contact = sum k d^2 / 2 over the contacts of a pose (k d n is minus its gradient:
// the depth's gradient is the normal, for the plane and for two capsules at their closest
// points); the damper and friction only remove energy (F_n clamped at 0 releases less than the
// spring stored). Gravity: m_i g at every bone's centre of mass c_i, U_gravity = -sum m_i g .
// (c_i - x_0), x_0 the ground's point nearest the origin (U >= 0 above a ground that gravity
// points into) or, without a ground, the initial pose's root head. Both are conservative: with
// them in U, the run monitor's E_k <= E_0 + W_k still holds along the exact motion
// (run_monitor.h) and the implicit step's guard holds E (implicit_advance.h).
//
// Implicit step (implicit_step.h): each contact is a point element, linearised at the start of
// the step (Gauss-Newton: the turn of n with the motion is dropped; it is multiplied by the force)
//   stiffness K = k n n^T,  damping D = c n n^T + (mu F_n / max(|v_t|, v_s)) (1 - n n^T)
// (beyond the slip speed the friction's secant, a majoriser as the capped springs'). A ground or
// obstacle contact is then exactly an augmented inertia h^2 K + h D on its bone, like a control
// spring, O(n). A self-contact couples two bodies; the exact step would need the coupling block -A
// between them (A = h^2 K + h D), which the articulated recursion cannot take in O(n). Instead each
// of the two bones gets 2 A at the contact point, with the other moving on at its start-of-step
// velocity (the -h K v term takes the relative velocity): block Jacobi, O(n + contacts), no dense
// matrix. Along the contact, for two point masses m_a, m_b, the relative acceleration is then
// F g with g = 1/(m_a + 2A) + 1/(m_b + 2A), and exact backward Euler has (m_a + m_b) /
// (m_a m_b + A (m_a + m_b)); the second minus the first is A (m_a - m_b)^2 / (...) >= 0. So the
// split is backward Euler on the pair's relative motion with an effective mass at least the true
// one (equal to it for equal masses): stable at every h, k, c, like the one-body element (the
// plain Jacobi split, A on each, is not: for equal masses at large h its amplification is
// -1 - sqrt 2). The price: while they touch, the pair's common motion carries 2 A of extra inertia
// per bone, a drag that vanishes at rest. Rotations and the articulated coupling make this an
// argument for the point-mass reduction only; the energy guard (implicit_advance.h) halves any
// step that adds energy all the same. At rest (v = 0, a = 0) the forces are the exact ones, so
// resting poses do not depend on the split.
// Units: N, N m, rig units, s, J.
#pragma once

#include <vector>

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// m_i g at every centre of mass (nothing when gravity is zero).
void apply_gravity(const Scene& scene, SimState& state);

// Detect the contacts at the state's frames (state.contacts), apply their forces, and list their
// elements for the implicit step (state.contact_elements). Nothing when the scene has no ground,
// no obstacles and no self-collision.
void apply_contacts(const Scene& scene, SimState& state);

// x_0 of U_gravity (above).
Vec3 gravity_reference(const Scene& scene);
// U_gravity of a pose's frames (0 when gravity is zero), J.
double gravity_potential(const Scene& scene, const BoneFrames& frames);
// U_contact of a set of contacts, J.
double contact_potential(const Scene& scene, const std::vector<Contact>& contacts);
// U_contact of the state's frames (detects at them, in the state's own collision world), J.
double contact_potential(const Scene& scene, const SimState& state);

// The deepest overlap of a set of contacts, in rig units and as a fraction of the radius of the
// thinner capsule of its contact (a bone's own radius is what a penetration is measured against).
struct Penetration {
  int contacts = 0;
  double max_depth = 0.0;           // rig units
  double max_depth_fraction = 0.0;  // 1, of the thinner touching bone's collision radius
};
Penetration penetration(const Scene& scene, const std::vector<Contact>& contacts);
Penetration penetration(const Scene& scene, const BoneFrames& frames);

}  // namespace physik
