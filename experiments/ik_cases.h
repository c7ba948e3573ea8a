// The rigs and targets of the ik_comparison experiment, defined once for the experiment and the
// solve mode's cost benchmark (bench/solve_cost.cpp): chains of 3, 10 and 50 bones along +z and
// pinhead's left hand, each target drawn from one fixed seed.
//
// Targets: reachable ones uniform in the ball of 0.95 of the reach around the root for the free
// chains, pinhead's hand tip in random legal poses; unreachable ones at 1.1..2 times the reach in
// a uniform direction; the continuity moves, 1% of the reach in a uniform direction. World frame,
// rig units.
#pragma once

#include <string>
#include <vector>

#include "physik/model/rig.h"

namespace physik::experiments {

// Every solver's pose is measured against the limits by one ruler: the rig's joints as the exact
// and implicit schemes (and MuJoCo) have them, hinges and universal joints by their own angles
// (physik/model/joint_angles.h), whichever solver made the pose.
constexpr LockedAxes kMeasuredJoints = LockedAxes::kRemoved;

struct RigCase {
  std::string name;
  Rig rig;
  int bone = 0;        // the effector's bone (its tail is the effector)
  double reach = 0.0;  // rig units
  bool chain = false;
};

// chain3, chain10, chain50 (unless without_chain50) and pinhead (from models_dir/rigs)
std::vector<RigCase> make_ik_rigs(const std::string& models_dir, bool without_chain50);

// A standing human figure of 75 bones with fingers, for the solve-cost comparison on a rig of a
// motion-capture file's size (MakeHuman's walk has 75 joints): hips (the root), seven spine
// bones, three neck bones, the head, a jaw and two eyes; per side a clavicle, an upper arm, a
// forearm in two (a twist bone), a hand and five fingers of a metacarpal and three phalanges; per
// side a pelvis bone, a thigh, a shin, a foot and a toe. Z up, facing -Y, .L on +X, 1.85 rig units
// tall, masses by length (1 per unit, as the original), the limits of a person in round numbers:
// hinges (elbows, knees, finger joints, toes, jaw: two axes locked), wrists and ankles with the
// twist locked, shoulders and hips free within a wide range, a small range per spine and neck bone.
Rig make_figure_rig();

// A rig's targets, drawn from one fixed seed: reachable, unreachable, and the continuity moves.
struct Targets {
  std::vector<Vec3> reach, unreach, moves;  // rig units, world frame
};

// n_reach reachable targets, then n_unreach unreachable ones and n_cont moves, drawn in that
// order from the one seed (the reachable ones of a shorter list are the first of a longer one)
Targets make_ik_targets(const RigCase& rc, int n_reach, int n_unreach, int n_cont);

}  // namespace physik::experiments
