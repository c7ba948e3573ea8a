// The scaling study's scenario and its MuJoCo timing, shared by the `scaling`
// experiment and bench/bench_articulated.cpp.
//
// Scenario: a straight chain (make_chain_rig) or a balanced binary tree (make_tree_rig, B = 2)
// of N bones from rest, pulled at its last bone's tail by one capped control spring (k 10 N/m,
// target 3 right and 1 forward of the rest tail), the `original` preset.
// mj_step is timed on the ball-joint model of the same rig (scheme exact's equivalent),
// replaying the applied forces (xfrc_applied) a same-forces reference run gave: the same
// trajectory, MuJoCo's own cost without PhysIK's force stages.
// Times are this thread's CPU time (CLOCK_THREAD_CPUTIME_ID), so other processes on a shared
// machine do not count (their cache pressure still does).
#pragma once

#include <string>
#include <vector>

#include "physik/model/scene.h"
#include "reference/mujoco_runner.h"

namespace physik::experiments {

// kind "chain" or "tree2"; `solve` and `joint_eps` set the engine's joint solve
Scene scaling_scene(const std::string& kind, int nbone, Scheme solve = Scheme::kExact,
                    double joint_eps = 1e-3);

double thread_seconds();  // s, CPU time of the calling thread

struct MjStepReplay {
  MjModelPtr model;
  MjDataPtr start, data;
  std::vector<std::vector<mjtNum>> xfrc;  // (steps) x (6 nbody), N and N m, world axes
  double compile_s = 0.0;                 // s, thread time of compiling the MJCF (mj_setConst...)
  BoneFrames final_frames;                // the reference run's pose after the last step
};

// Compile the ball-joint model and run `steps` same-forces steps, keeping their forces.
MjStepReplay record_mj_step_replay(const Scene& scene, int steps);
// us per mj_step over one replay from the recorded start
double time_mj_step_replay(MjStepReplay& replay);

// One solve's joint forces (the scene's joint_solve and eps) on `state`, with the velocity terms
// both solves share: centripetal on, angular-velocity factor 1. Then the Gauss-Seidel fixed
// point is the exact solution. N per bone (joint_force_world), world axes. `state` must be sized
// for the exact solve (init_state of a scheme exact scene).
std::vector<Vec3> joint_forces_at(Scene scene, const SimState& state);

}  // namespace physik::experiments
