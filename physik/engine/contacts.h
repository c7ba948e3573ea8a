// Contacts and gravity: the forces of a floor and of a rig touching itself, in every scheme
// (forces.h), and their potential energy for the run monitor's energy rule and the implicit
// step's energy guard (potential.h). Detection is collision.h's.
//
// Contact force law, per contact found at the state (bodies a, b; point p; unit normal n from b
// toward a; depth d > 0): with v = v_a(p) - v_b(p) the relative velocity of the two bodies'
// material points at p (v_b = 0 for the ground and obstacles), v_n = v . n and v_t = v - v_n n,
//   normal    F_n = max(0, k d - c v_n)      a penalty spring with a damper (compliant, like
//                                            MuJoCo's soft contacts), never pulling
//   friction  F_t = -k_t s - (mu F_n - k_t |s|) v_t / max(|v_t|, v_s)
//                                            static friction: an anchor spring of stretch s
//                                            (below), and regularised Coulomb's viscous share
//                                            of what it leaves of mu F_n; |F_t| <= mu F_n
//   on a: F_n n + F_t at p; on b (a bone): the opposite, at the same point (no net torque)
// with k = contact_k (N/m), c = contact_damping (N s/m), mu = friction, v_s = friction_speed
// (rig units/s), k_t = friction_stiffness (N/m) (params.h). At rest under a load W along n the
// spring sinks by d = W / k.
//
// Static friction (ground and obstacle contacts; k_t = 0: none, the regularised law alone, as
// before it). The regularised law alone has no static part: under a steady tangential load T < mu
// F_n a contact creeps at v_t = v_s T / (mu F_n), for ever (a rod on a slope, a pile of bones).
// So each contact carries an anchor spring, the elastic-plastic (bristle) model of friction
// (P. Dahl, "A solid friction model", 1968; the stick-slip spring of penalty contact, e.g. K.
// Yamane and Y. Nakamura, "Stable penalty-based model of frictional contacts", ICRA 2006): its
// stretch s, tangent to n, grows with the contact's slip and is held at |s| <= mu F_n / k_t (the
// contact slips there):
//   s+ = clamp(P_n+ (s + h v_t+), mu F_n+ / k_t)                  (P_n: onto the tangent plane)
// with v_t+ the slip velocity at the end of the step (backward Euler, as the implicit step takes
// the spring's force at the end of the step). A contact the last force stage had (the same bodies
// and feature, collision.h Contact::feature) carries its stretch on (state.friction_anchors); a
// new one starts at 0, and one that stops pushing lets go. A tangential load T < mu F_n then
// holds the contact T / k_t from where it stuck, at rest; above, the spring pulls mu F_n against
// the slip and the viscous share is gone: kinetic Coulomb friction. Rolling has no slip at p and
// stretches nothing. The stretch takes the contact point's material velocity, so a capsule that
// turns about its contact point while pressed stretches it as it should. Its energy k_t |s|^2 / 2
// is in U_contact (friction_potential); the clamp, and a contact letting go, only lower it.
//
// Energy: U_contact = sum k d^2 / 2 over the contacts of a pose (k d n is minus its gradient:
// the depth's gradient is the normal, for the plane and for two capsules at their closest
// points), plus the anchor springs' sum k_t |s|^2 / 2; the damper and the viscous friction only
// remove energy (F_n clamped at 0 releases less than the spring stored). Gravity: m_i g at every
// bone's centre of mass c_i, U_gravity = -sum m_i g . (c_i - x_0), x_0 the ground's point nearest
// the origin (U >= 0 above a ground that gravity points into) or, without a ground, the initial
// pose's root head. Both are conservative: with them in U, the run monitor's E_k <= E_0 + W_k still
// holds along the exact motion (run_monitor.h) and the implicit step's guard holds E
// (implicit_advance.h).
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
// reversed). As h -> 0 the cap goes to infinity and the law is the one above.
//
// Implicit step (implicit_step.h): each contact is a point element, linearised at the start of
// the step (Gauss-Newton: the turn of n with the motion is dropped; it is multiplied by the force)
//   stiffness K = k n n^T + k_t (1 - n n^T - [slipping] e e^T),  e = s / |s|
//   damping   D = c n n^T + ((mu F_n - k_t |s|) / max(|v_t|, v_s)) (1 - n n^T)
// (beyond the slip speed the friction's secant, a majoriser as the capped springs'; a slipping
// anchor pulls a constant mu F_n along the slip, so it adds no stiffness along it). A ground or
// obstacle contact is then exactly an augmented inertia h^2 K + h D on its bone, like a control
// spring, O(n). A self-contact couples two bodies; the exact step would need the coupling block
// between them, which the articulated recursion cannot take in O(n). Its spring is split: each
// of the two bones gets 2 A = 2 h^2 K at the contact point, with the other moving on at its
// start-of-step velocity (the -h K v term takes the relative velocity): block Jacobi,
// O(n + contacts). For two point masses m_a, m_b, the relative acceleration is F g
// with g = 1/(m_a + 2A) + 1/(m_b + 2A), and exact backward Euler has (m_a + m_b) / (m_a m_b + A
// (m_a + m_b)); the second minus the first is A (m_a - m_b)^2 / (...) >= 0: backward Euler on
// the relative motion with an effective mass at least the true one, stable at every h and k
// (share 1, A on each, is not: for equal masses at large h its amplification is -1 - sqrt 2).
// Its damper and friction are not split: they stay explicit, capped as above, with no anchor
// spring (no static part: a split anchor would drag the pair's common motion as the split damper
// does, below; explicit, it would need a step below 2 sqrt(m_eff / k_t)). Split, they are
// stable at fixed coefficients too, but they drag the pair's common motion (the 2 h D each bone
// carries): that stores up to 2 h u.D u per contact, u the common velocity, which returns as
// kinetic energy when the coefficients or the contacts change, and the friction's secant
// mu F_n / max(|v_t|, v_s) (~1e3 N s/m on 0.1 kg bones in a pile) changes with every step. A helix
// dropped on the floor (experiments/coil.h) piles its turns so: with the split damper and
// friction every helix tried, 200 to 1,000 bones, diverged within 22 steps of dt 0.01, the energy
// guard splitting down to dt / 256 and still finding energy added; with the split damper and the
// capped friction the 1,000-bone one still diverged (step 28); with both capped it comes to rest
// (tests/experiments/coil_test.cpp, the contacts experiment). The price: at a long step two
// bones slide on each other, and bounce off each other, more freely than the law says (the cap),
// and the spring's split still drags the common motion by 2 h^2 k per bone while two bones touch.
// At rest (v = 0, a = 0) the forces are the exact ones, so resting poses depend on neither.
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
// h: the step the forces are taken over, s (the self-contacts' cap, above).
void apply_contacts(const Scene& scene, SimState& state, double h);

// x_0 of U_gravity (above).
Vec3 gravity_reference(const Scene& scene);
// U_gravity of a pose's frames (0 when gravity is zero), J.
double gravity_potential(const Scene& scene, const BoneFrames& frames);
// U_contact of a set of contacts, J.
double contact_potential(const Scene& scene, const std::vector<Contact>& contacts);
// The static friction's anchor springs, sum k_t |stretch now|^2 / 2 over state.friction_anchors
// (their stretch now: current_stretch, above), J.
double friction_potential(const Scene& scene, const SimState& state);
// U_contact of the state's frames (detects at them, in the state's own collision world), plus
// friction_potential, J.
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
