// Ground and obstacle contacts: the forces of a floor and of static boxes on the bones, their
// potential, and their implicit elements. Detection is collision.h's, through the state's contact
// data (contact_data.h); a bone pair's contact is self_contacts.h's.
//
// Contact force law, per contact found at the state (bodies a, b: a bone and the ground or a box;
// point p; unit normal n from b toward a; depth d > 0): with v = v_a(p) - v_b(p) the relative
// velocity of the two bodies' material points at p (v_b = 0: b is static), v_n = v . n and
// v_t = v - v_n n,
//   normal    F_n = max(0, k d - c v_n)      a penalty spring with a damper (compliant, like
//                                            MuJoCo's soft contacts), never pulling
//   friction  F_t = -k_t s - (mu F_n - k_t |s|) v_t / max(|v_t|, v_s)
//                                            static friction: an anchor spring of stretch s
//                                            (below), and regularised Coulomb's viscous share
//                                            of what it leaves of mu F_n; |F_t| <= mu F_n
//   on a: F_n n + F_t at p
// with k = contact_k (N/m), c = contact_damping (N s/m), mu = friction, v_s = friction_speed
// (rig units/s), k_t = friction_stiffness (N/m) (params.h). At rest under a load W along n the
// spring sinks by d = W / k.
//

// Static friction (k_t = 0: none, the regularised law alone). The regularised law alone has no
// static part: under a steady tangential load T < mu F_n a contact creeps at v_t = v_s T / (mu
// F_n), for ever (a rod on a slope, a pile of bones). So each contact carries an anchor spring, the
// elastic-plastic (bristle) model of friction (P. Dahl, "A solid friction model", 1968; the
// stick-slip spring of penalty contact, e.g. K. Yamane and Y. Nakamura, "Stable penalty-based model
// of frictional contacts", ICRA 2006): its stretch s, tangent to n, grows with the contact's slip
// and is held at |s| <= mu F_n / k_t (the contact slips there):
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
// Energy: U = sum k d^2 / 2 over the contacts of a pose (k d n is minus its gradient: the
// depth's gradient is the normal), plus the anchor springs' sum k_t |s|^2 / 2; the damper and
// the viscous friction only remove energy (F_n clamped at 0 releases less than the spring
// stored). With it in U the run monitor's E_k <= E_0 + W_k holds along the exact motion
// (run_monitor.h) and the implicit step's guard holds E (implicit_advance.h).
//
// Implicit step (implicit_step.h): each contact is a point element on its bone, linearised at the
// start of the step (Gauss-Newton: the turn of n with the motion is dropped; it is multiplied by
// the force)
//   stiffness K = k n n^T + k_t (1 - n n^T - [slipping] e e^T),  e = s / |s|
//   damping   D = c n n^T + ((mu F_n - k_t |s|) / max(|v_t|, v_s)) (1 - n n^T)
// (beyond the slip speed the friction's secant, a majoriser as the capped springs'; a slipping
// anchor pulls a constant mu F_n along the slip, so it adds no stiffness along it): exactly an
// augmented inertia h^2 K + h D on its bone, like a control spring, O(n); the right-hand side
// gets -h K v at its point.
// Damping auto (linear_modes.h) does not see it: the damping is chosen when the targets change,
// and the contacts come and go between; a contact's own damper c damps its normal motion.
// Units: N, N/m, N s/m, rig units, s, J.
#pragma once

#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

// The force stage: the forces of the contacts the stage found (state.contact.found) with the
// ground and the obstacles, their friction anchors carried over, their implicit elements listed
// (state.contact.elements). h: the step the forces are taken over, s.
void apply_ground_contacts(const Scene& scene, SimState& state, double h);

// U of the ground and obstacle contacts among `contacts` (the springs), J.
double ground_contact_potential(const Scene& scene, const std::vector<Contact>& contacts);
// The static friction's anchor springs, sum k_t |stretch now|^2 / 2 over state.contact.anchors
// (their stretch now, above), J.
double friction_potential(const Scene& scene, const SimState& state);
// U of the state: its contacts at its frames (state.contact.at_frames, detected by the potential
// stage: potential.h) and its anchors, J.
double ground_contacts_potential(const Scene& scene, const SimState& state);

// The implicit step's terms of the elements the stage listed: -h K v at each contact point, and
// h^2 K + h D into its bone's articulated inertia (implicit_step.h).
void ground_contacts_rate(const Scene& scene, double h, SimState& state);
void ground_contacts_augment(const Scene& scene, double h, SimState& state);

}  // namespace physik
