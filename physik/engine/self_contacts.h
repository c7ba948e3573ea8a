// Self-contacts: the forces between two bones whose capsules overlap (self_collision), their
// potential, and their implicit elements. Detection is collision.h's, through the state's contact
// data (contact_data.h); pairs that share a joint or a welded body, and the excluded pairs, are
// never found.
//
// Force law: ground_contacts.h's normal spring and damper and its regularised friction, between
// the two bones a and b (n from b toward a, v = v_a(p) - v_b(p)): F_n n + F_t on a at p, its
// opposite on b at the same point (no net torque), and no static friction (no anchor spring: a
// split anchor would drag the pair's common motion as a split damper does, below; explicit, it
// would need a step below 2 sqrt(m_eff / k_t)). Energy: U = sum k d^2 / 2 over the pairs of a pose.
//
// A self-contact's damper and friction are capped for the step h they are taken over: with n_b
// the bone-bone contacts of bone b and w_b(p) = 1/m_b + r_perp^2 / I_axial,b + |r|^2 / I_perp,b
// (r = p - c_b) an upper bound on the free bone's compliance at p (the joints, and the step's
// augmented inertias, only lower it: Rayleigh), both c and mu F_n / max(|v_t|, v_s) are at most
// 1 / (h W_c), W_c = n_a w_a(p) + n_b w_b(p). Then the step's damper and friction impulses f_c h
// cannot add kinetic energy: dKE = -h sum u_c.D_c u_c + h^2/2 |sum J_c^T f_c|^2_{M^-1} (u_c the
// relative velocity at c, f_c = D_c u_c), and by Cauchy-Schwarz over
// each bone's n_b contacts the second term is at most h^2/2 sum |f_c|^2 W_c <= h/2 sum u_c.D_c u_c
// (margin 2: an isolated pair whose bound is tight has its slip stopped in one step, not
// reversed). As h -> 0 the cap goes to infinity and the law is ground_contacts.h's.
//
// Implicit step (implicit_step.h): a self-contact couples two bodies; the exact step would need
// the coupling block between them, which the articulated recursion cannot take in O(n). Its
// spring (K = k n n^T, linearised at the start of the step) is split: each of the two bones gets
// 2 A = 2 h^2 K at the contact point, with the other moving on at its start-of-step velocity (the
// -h K v term takes the relative velocity): block Jacobi, O(n + contacts). For two point masses
// m_a, m_b, the relative acceleration is F g with g = 1/(m_a + 2A) + 1/(m_b + 2A), and exact
// backward Euler has (m_a + m_b) / (m_a m_b + A (m_a + m_b)); the second minus the first is
// A (m_a - m_b)^2 / (...) >= 0: backward Euler on the relative motion with an effective mass at
// least the true one, stable at every h and k (share 1, A on each, is not: for equal masses at
// large h its amplification is -1 - sqrt 2). Its damper and friction are not split: they stay
// explicit, capped as above. Split, they would be stable at fixed coefficients too, but they
// would drag the pair's common motion (the 2 h D each bone carries), storing up to 2 h u.D u per
// contact, u the common velocity, which returns as kinetic energy when the coefficients or the
// contacts change (the friction's secant changes with every step); CHANGELOG.md (2026-12-04) has
// what that did to a dropped coil. The price: at a long step two bones slide on each other, and
// bounce off each other, more freely than the law says (the cap), and the spring's split still
// drags the common motion by 2 h^2 k per bone while two bones touch. At rest (v = 0, a = 0) the
// forces are the exact ones, so resting poses depend on neither.
// Damping auto (linear_modes.h) does not see it: a coupling between two bodies, which the modes'
// O(n) operators carry no more than the step does, and contacts come and go between the target
// changes at which the damping is chosen.
// Units: N, N/m, N s/m, rig units, s, J.
#pragma once

#include <vector>

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// The force stage: the forces of the bone pairs' contacts the stage found (state.contact.found,
// counted per bone: contact_data.h), their implicit elements listed. h: the step the forces are
// taken over (the cap, above), s.
void apply_self_contacts(const Scene& scene, SimState& state, double h);

// U of the bone pairs among `contacts`, J.
double self_contact_potential(const Scene& scene, const std::vector<Contact>& contacts);
// U of the state's contacts at its frames (state.contact.at_frames: potential.h), J.
double self_contacts_potential(const Scene& scene, const SimState& state);

// The implicit step's terms of the elements the stage listed: -h K (v_a - v_b) on a and its
// opposite on b, and the split 2 h^2 K into each bone's articulated inertia.
void self_contacts_rate(const Scene& scene, double h, SimState& state);
void self_contacts_augment(const Scene& scene, double h, SimState& state);

}  // namespace physik
