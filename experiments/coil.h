// The coil: a long chain of bones on a floor with self-collision, shared by the contacts
// experiment's `coil` section (experiments/contacts.cpp) and bench/bench_contacts.cpp.
//
// The chain: N bones of length L = 0.1 rig units, 1 kg per rig unit (0.1 kg a bone, the original's
// mass per length), no joint limits (a free ball at every joint: a rope of capsules), collision
// radius r = L / 4, the inertia's cylinder of the same radius. Its rest pose is the shape below
// (the rig is built in that shape), so the initial pose is the rest pose.
//   flat spiral  an Archimedean spiral rho = rho_0 + s theta / (2 pi) in the plane z = r - e,
//                inner radius rho_0 = 3 L, e = r / 25, turns s = 2 r - e + L^2 / (8 rho_0) apart
//                (a chord of a turn sags inward by L^2 / (8 rho)): every end sphere sinks e into
//                the floor, the inner turns overlap by up to e and the outer ones, whose chords sag
//                less, just clear each other: 2N ground contacts, a few self-contacts on the
//                innermost turns, and every turn a candidate of its neighbours' in the broad phase
//   flat ring    a flat spiral with a fixed number of turns: its inner radius rho_0 grows with N
//                so that N bones fill `turns` turns (the arc length of T turns is about
//                2 pi T rho_0 + pi s T^2, so rho_0 = (N L - pi s T^2) / (2 pi T)), its turns
//                s = 2 r + e + L^2 / (8 rho_0) apart, so that they clear each other by at least
//                e: 2N ground contacts and no self-contact at the start. rho_0 is at least 3 L,
//                as the spiral's: below that (fewer than about 104 bones at 4 turns) the chain
//                ends short of its turns. Every N has a similar share of bones on the inner and
//                outer turns, which have one neighbouring turn where the others have two, so the
//                broad phase's candidate pairs per bone stay within a few percent at every N:
//                the workload of the growth benchmark (bench/bench_contacts.cpp). The flat
//                spiral's turn count grows with N instead, and its pairs per bone with it
//   helix        `turns` turns of radius N L / (2 pi turns) about the vertical, pitch 3 r (the
//                turns do not touch), its lowest bone r above the floor: dropped under gravity,
//                the turns fall onto one another and pile on the floor
// Points are placed along each curve with chords of exactly L (a few secant corrections per
// bone). Scene: gravity 9.81 down, the floor z = 0, self-collision on (`contacts` false: neither,
// gravity kept), the implicit scheme (the explicit ones need dt below the contact's period,
// docs/engine.md) at dt 0.01 s with the end dampers at `damping` N s/m, the default contact law.
// Units: rig units, kg, s.
#pragma once

#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik::experiments {

constexpr double kCoilBoneLength = 0.1;  // rig units
constexpr double kCoilRadius = 0.025;    // rig units, collision and inertia radius
constexpr double kCoilDamping = 0.1;     // N s/m at each bone end

Scene coil_flat_spiral_scene(int nbone, bool contacts, int steps = 100);
// std::invalid_argument when turns < 1.
Scene coil_flat_ring_scene(int nbone, int turns, bool contacts, int steps = 100);
Scene coil_helix_scene(int nbone, int turns, int steps);

// The broad phase's workload at these frames: the bone pairs whose capsule boxes (each bone's
// segment's box grown by its collision radius, collision.h) overlap, bones that share a joint
// excluded, over the bones. A brute-force count, O(N^2).
double candidate_pairs_per_bone(const Scene& scene, const BoneFrames& frames);

}  // namespace physik::experiments
