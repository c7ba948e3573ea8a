// How far a welded group came apart: the largest turn of a welded bone against its rest frame in
// the frame of the bone it is welded to (rig.h "Welds"),
//   turn_i = angle( R_w(i) q_i^rest , R_i ),   q_i^rest = Rig::bone_rest_orient_weld[i]
// (rad, world frames from the state's forward kinematics). 0 while every welded group moves as one
// rigid body. The outside_rigs experiment's weld checks, and the tests of welds. Uses the model
// alone, so the core's tests include it too.
#pragma once

#include <algorithm>
#include <cmath>

#include "physik/model/kinematics.h"
#include "physik/model/rig.h"

namespace physik::experiments {

// rad, over every welded bone, or (`body` >= 0) over that rigid body's bones alone
// (Rig::bone_body); a non-finite turn (a state gone non-finite) is returned as it is, never taken
// for 0
inline double max_weld_turn(const Rig& rig, const BoneFrames& frames, int body = -1) {
  double worst = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const int w = rig.bone_weld[i];
    if (w < 0 || (body >= 0 && rig.bone_body[i] != body)) continue;
    const Quat expected = frames.orient_world[w] * rig.bone_rest_orient_weld[i];
    const double turn = expected.angularDistance(frames.orient_world[i]);
    if (!std::isfinite(turn)) return turn;
    worst = std::max(worst, turn);
  }
  return worst;
}

}  // namespace physik::experiments
