// Measures of a state, each written once: the step's stats, the run monitor, the posing session,
// the recorder and the experiments call these (as MuJoCo keeps mj_energyPos / mj_energyVel apart
// from mj_step).
//
//   kinetic energy      KE = sum_b 1/2 m_b |v_b|^2 + 1/2 w_b^T I_b w_b        (J; v at the centre
//                       of mass, I_b the world inertia about it)
//   control residual    r_c = |a_c - g_c|: control point c's attachment a_c (a point on its bone,
//                       world) to its goal target g_c (not the interpolated one), rig units
//   goal residual       the largest of the control residuals and the turning targets' arcs: an
//                       orientation target's |phi| and an aim's theta times the bone's length L
//                       (how far the turn leaves the bone's tail from where the target would lay
//                       it), rig units; pins hold a point rather than reach for one (a loaded pin
//                       gives way by |F| / k by design) and have none
//   goals by their own measure (a solve's stop rule and its shortfall): goal g is a control
//                       point (its r_c, rig units), then an orientation target (its turn |phi|,
//                       rad), then an aim (its theta, rad), in the scene's order; each is met
//                       below its own tolerance, rig units or rad (GoalTolerance). A goal's
//                       excess is its residual over its tolerance (met below 1), which puts goals
//                       of both units on one scale for the stall rule (GoalProgress)
//   joint separation    max over joints of |head_child - (head_parent + R_parent h_child)|: how far
//                       a child's head is from its joint on the parent, and an anchored root's
//                       head from its rest position, rig units (0 unless the scheme integrates
//                       free rods)
//   centre of mass      a bone's is its midpoint (a uniform rod), world, rig units
//   state hash          FNV-1a over the bit patterns of every head, tail and orientation
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "physik/engine/run_summary.h"
#include "physik/engine/state.h"
#include "physik/model/scene.h"

namespace physik {

double kinetic_energy(const Rig& rig, const SimState& state);
double max_joint_separation(const Rig& rig, const BoneFrames& frames);

// r_c of one control point, against the state's goal target.
double control_residual(const Scene& scene, const SimState& state, int c);
// r_c of every control point (out sized to the scene's; no allocation once it is).
void control_residuals(const Scene& scene, const SimState& state, std::vector<double>& out);
// max_c r_c; 0 without control points; NaN when any residual is NaN.
double max_control_residual(const Scene& scene, const SimState& state);
// The goal residual: max_control_residual and every orientation target's and aim's arc (the
// step's max_residual, which the IK stop rule reads); NaN when any is NaN.
double max_goal_residual(const Scene& scene, const SimState& state);
// The orientation targets' and aims' largest arc at `frames`, rig units (0 without them).
double max_turning_arc(const Scene& scene, const BoneFrames& frames);

// The bone targets' residuals at `frames`: an orientation target's turn |phi| and an aim's theta
// (rad), a pin's point from its world point (rig units).
double orientation_residual(const BoneFrames& frames, const OrientationTarget& target);
double aim_residual(const BoneFrames& frames, const AimTarget& target);
double pin_residual(const BoneFrames& frames, const Pin& pin);

// --- goals by their own measure -----------------------------------------------------------------

enum class GoalKind { kControlPoint, kOrientation, kAim };

// The tolerances goals are met below: position goals in rig units, turning goals in rad.
struct GoalTolerance {
  double position = 0.0;  // rig units
  double angle = 0.0;     // rad
  double of(GoalKind kind) const { return kind == GoalKind::kControlPoint ? position : angle; }
};

// A goal of the scene: its kind and its index among the scene's goals of that kind.
struct GoalRef {
  GoalKind kind = GoalKind::kControlPoint;
  int index = 0;
};

// How many goals the scene has: control points, orientation targets and aims.
int goal_count(const Scene& scene);
// Goal g (0 <= g < goal_count): control points first, then orientation targets, then aims.
GoalRef goal_ref(const Scene& scene, int g);
// Its residual by its own measure at the state: rig units (a control point, against its goal
// target) or rad.
double goal_residual(const Scene& scene, const SimState& state, int g);
// The same at `frames`, the control points against `targets_world` (one per control point).
double goal_residual(const Scene& scene, const BoneFrames& frames,
                     const std::vector<Vec3>& targets_world, int g);
// "control point 0 on 'hand.L'", "orientation target on 'head'", "aim of 'head'" (the goal's
// name when the scene gives one), for the messages that name a goal.
std::string goal_label(const Scene& scene, int g);
// "rig units" or "rad".
const char* goal_unit(GoalKind kind);
// Every goal below its tolerance (true without goals); false when any residual is NaN.
bool goals_met(const Scene& scene, const SimState& state, const GoalTolerance& tolerance);

// The stall rule, per goal: a solve has stalled when no goal still short of its tolerance has
// improved its excess (residual over tolerance) by `fraction` of its best over the last
// `window` observations, so a slow aim does not hide behind a met reach, nor a moving one behind
// a stuck one. A goal's best counts from the last observation that found it short after one
// that found it met (a held point that a pull stretches starts its record there). restart sizes its
// buffer (allocates only when the scene has more goals than before); observe allocates nothing.
class GoalProgress {
 public:
  void restart(const Scene& scene, int now, int window, double fraction);
  // Observe the state at count `now` (steps or iterations); true when stalled.
  bool observe(const Scene& scene, const SimState& state, const GoalTolerance& tolerance, int now);

 private:
  std::vector<double> best_;   // (ngoal) each goal's best excess since its last improvement
  std::vector<int> improved_;  // (ngoal) the count at its last improvement
  int window_ = 1;
  double fraction_ = 0.0;
};

// A bone's centre of mass: its midpoint.
inline Vec3 bone_centre_world(const BoneFrames& frames, int bone) {
  return 0.5 * (frames.head_world[bone] + frames.tail_world[bone]);
}

// The stats of a state no step has produced yet (the initial one): its kinetic energy, residuals
// and joint separation; no passes, no mismatch.
StepStats initial_stats(const Scene& scene, const SimState& state);

// Equal hashes mean bit-identical frames (determinism made visible, as Jolt prints a state hash).
std::uint64_t state_hash(const BoneFrames& frames);

}  // namespace physik
