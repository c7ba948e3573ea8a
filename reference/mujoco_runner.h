// The MuJoCo reference run of a scene (docs/engine.md "MuJoCo as the reference").
//
// Every step, with the state after the previous step (MuJoCo's mj_step1 has computed positions
// and velocities):
//   1. the PhysIK view of MuJoCo's state is built: per bone (its body b, MjcfBodyMap)
//        com = xpos[b] (body frame at the centre of mass), R = xquat[b] (a welded bone at its
//        fixed offset in b's frame),
//        head/tail = com -/+ R (0, L/2, 0),  (w, v_com) = mj_objectVelocity(body b, world axes),
//        pose = local_rotations_from_world(frames)
//   2. PhysIK's own stages run on that state (no formula is copied here):
//        update_targets, prepare_bodies, apply_damping, apply_control_springs, and in
//        same-forces mode apply_torsion_springs
//   3. the angular-velocity factor f becomes a torque per body,
//        tau_f = I_world (f - 1) w / dt,
//      so that MuJoCo's Euler step w <- w + dt I^-1 (tau + tau_f - w x I w) gives
//      w <- f w + dt alpha, PhysIK's update (integrate.h), exactly for a free body. Both use the
//      start-of-step w, and both integrate positions with the new velocity (semi-implicit Euler),
//      so the order of operations matches. In an articulated MuJoCo model tau_f is a generalized
//      force J^T tau_f filtered by the mass matrix: it damps the joint velocities, which is not the
//      same as scaling each bone's world w after the joint solve as PhysIK's articulated scheme
//      does. If params.gyroscopic is off, +w x I w is added too, cancelling MuJoCo's own gyroscopic
//      term.
//   4. xfrc_applied[b] = (force_world, torque_world): the net force at the centre of mass and the
//      torque about it, world axes (a welded group's bones' summed at the body's centre of mass,
//      xipos); then mj_step2 (constraint solve, Euler integration) and mj_step1 for the new state.
// Modes:
//   same-forces:        the scheme's joints (balls everywhere for gauss-seidel; hinges where the
//                       rig locks axes for exact and implicit: mjcf_export.h kHingeJoints), no
//                       limits, torsion springs applied as torques; for gauss-seidel only
//                       PhysIK's joint-force heuristic differs from MuJoCo's exact dynamics, for
//                       exact nothing does.
//   exact-constraints:  the rig's joint types and limits (mjcf_export.h), no torsion springs.
// MuJoCo's limits are soft (solref 0.02 s raised to 2 dt by its refsafe rule, solimp 0.9 0.95
// 0.001): at rest under a load that would accelerate the joint by a0 (rad/s^2) without the limit,
// MuJoCo's soft-constraint law a = (1 - d) a0 + d (-b v - k r), k = d / (dmax^2 tau^2), gives a
// violation r = (1 - d) dmax^2 tau^2 a0 / d^2 = (1 - d) tau^2 a0 once r > 0.001 rad (d = dmax =
// 0.95), with tau = max(0.02, 2 dt): r = 0.05 x 0.01 s^2 x a0 = 5e-4 s^2 x a0 for dt = 0.05 s.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "physik/engine/engine.h"
#include "reference/mjcf_export.h"

namespace physik {

enum class ReferenceMode { kSameForces, kExactConstraints };
const char* to_string(ReferenceMode mode);

// The joint model each mode uses: same forces, the scheme's own (its locked axes removed in the
// exact and implicit schemes, springs in the gauss-seidel scheme: rig.h "Locked axes"); exact
// constraints, the rig's joints and limits.
inline JointModel joint_model(ReferenceMode mode, const EngineParams& params) {
  if (mode == ReferenceMode::kExactConstraints) return JointModel::kRigJoints;
  return params.locked_axes() == LockedAxes::kRemoved ? JointModel::kHingeJoints
                                                      : JointModel::kBallJoints;
}

// Where each bone lives in a model built by rig_to_mjcf: its body's id (the body named after the
// first bone of its rigid body, Rig::bone_body) and its fixed offset there (mjcf_body_offset);
// `single` where the body holds that bone alone.
struct MjcfBodyMap {
  MjcfBodyMap(const Rig& rig, const mjModel* m);
  std::vector<int> body;               // (nbone) MuJoCo body id
  std::vector<MjcfBodyOffset> offset;  // (nbone) the bone in its body's frame
  std::vector<char> single;            // (nbone) 1: the body is this bone alone
};

// Set qpos/qvel of a model built by rig_to_mjcf from a PhysIK state (positions, velocities and
// local rotations in state.pose). Ball joints take the local rotation exactly; a body's hinges
// take the angles of L^-1 q in their order (joint_coordinates.h: a hinge's twist, two hinges'
// first two intrinsic Euler angles, three hinges' three: exact on the joints' set, a projection
// off it), their rates the relative angular velocity w_i - w_parent on their world axes
// (solved: three hinges' axes are not orthogonal); welded bones keep their locked angles.
void set_mujoco_state(const Rig& rig, const SimState& state, const mjModel* m, mjData* d);
void set_mujoco_state(const Rig& rig, const SimState& state, const mjModel* m, mjData* d,
                      const MjcfBodyMap& bodies);

// The PhysIK view (frames, com, velocities, pose) of MuJoCo's state; needs mj_step1 or
// mj_forward to have run. Other fields of `state` are left as they are.
void read_mujoco_state(const Rig& rig, const mjModel* m, const mjData* d, SimState& state);
void read_mujoco_state(const Rig& rig, const mjModel* m, const mjData* d, SimState& state,
                       const MjcfBodyMap& bodies);

// One scene run in MuJoCo, step by step.
class MujocoReference {
 public:
  MujocoReference(const Scene& scene, ReferenceMode mode);

  void reset();  // the scene's initial pose, targets and velocities
  // continue from another state (positions, velocities, pose; targets are taken from it too)
  void set_state(const SimState& state);
  StepStats step();  // one step (see above); passes = MuJoCo's constraint-solver iterations

  const SimState& state() const { return s_; }
  SimState& state() { return s_; }  // the run monitor's potential detects into its contact data
  const mjModel* model() const { return m_.get(); }
  mjData* data() { return d_.get(); }
  ReferenceMode mode() const { return mode_; }
  bool bad_acceleration() const;  // MuJoCo flagged a non-finite qacc (it then resets itself)

 private:
  const Scene& scene_;
  ReferenceMode mode_;
  MjModelPtr m_;
  MjDataPtr d_;
  std::unique_ptr<MjcfBodyMap> bodies_;
  SimState s_;
  std::vector<double> residuals_;  // (ncontrol) step()'s scratch, rig units
};

// The MuJoCo warning raised in `d` that makes a run not comparable, named as MuJoCo names it with
// what it means, or "" when none was: mjWARN_CONTACTFULL (the contact list, nconmax, was full:
// contacts were dropped), mjWARN_CNSTRFULL (the constraint rows, njmax, were full: contacts or
// limits dropped), mjWARN_BADQACC, mjWARN_BADQVEL, mjWARN_BADQPOS (a non-finite acceleration,
// velocity or position: MuJoCo reset its state). The export sizes the buffers for the scene
// (mjcf_export.h mjcf_size); this is what says when that was not enough.
std::string mujoco_warning(const mjModel* m, const mjData* d);

// True when a MuJoCo run's divergence_reason is a full buffer (mjWARN_CONTACTFULL or
// mjWARN_CNSTRFULL), which a smaller dt does not mend.
bool mujoco_buffer_full(const std::string& reason);

// What to try after MuJoCo's run of `scene` ended for `reason` while PhysIK's did not, in one
// line: a full buffer is the model's size (MuJoCo 2.2's dense constraint arrays), anything else
// MuJoCo's Euler step, unstable at the scene's dt on its springs: a tenth of dt, ten times the
// steps.
std::string mujoco_hint(const Scene& scene, const std::string& reason);

// The whole run, with the same convergence and divergence rules as physik::run_scene
// (physik/run_monitor.h); a MuJoCo warning (mujoco_warning) ends it as diverged, not comparable,
// its reason naming the warning and the step. With observe_initial the observer sees the initial
// state first (step 0), as run_scene's.
RunSummary run_mujoco(const Scene& scene, ReferenceMode mode,
                      const StepObserver& observer = nullptr, bool observe_initial = false);

}  // namespace physik
