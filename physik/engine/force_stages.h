// What the stages of the force list (forces.h) are given and give back: the force stage's
// purpose, the implicit step's h, and the stiffness damping auto's modes see. Every force's file
// includes this; forces.h lists the forces.
#pragma once

#include <vector>

#include "physik/model/types.h"

namespace physik {

// Who applies a force when the MuJoCo reference runs the scene (reference/mujoco_runner.h).
enum class MujocoSide {
  kApplied,         // PhysIK's force, applied to MuJoCo's bodies (xfrc_applied)
  kSameForcesOnly,  // applied in same-forces mode; MuJoCo's own joint limits in
                    // exact-constraints mode
  kMujocosOwn,      // MuJoCo's own (its gravity, its contacts against the same capsules)
};

// What the force stage is for.
struct ForceStage {
  double step = 0.0;  // s, the step the forces are taken over (0: params.dt); it caps a
                      // self-contact's damper and friction (self_contacts.h)
  enum class For { kEngine, kMujocoSameForces, kMujocoExactConstraints } for_ = For::kEngine;
};

// Which of the pose terms the implicit step with implicit_linearisation full keeps
// (implicit_pose_terms.h (1)-(5); all of them unless a study drops some: the linearisation
// experiment passes its selection to solve_implicit, implicit_step.h)
struct PoseTermSelection {
  bool forces = true;                 // (2), the gradient torque's curvature in (5), and the
                                      // world-held forces' share of (1)
  bool torque_frame = true;           // (5): the torsion torque's frame turning, -[tau]x
  bool inertia_wrench = true;         // the d'Alembert wrenches' share of (1)
  bool inertia_turn = true;           // (3)
  bool turning_accelerations = true;  // (4)
  bool torsion_in_wrench = false;     // the torsion torques in (1)'s wrench (the shared DESIGN.md
                                      // sketch, with torque_frame off)
  bool gauss_newton_retake = true;    // a step whose recursion meets a pivot whose symmetric
                                      // part is not positive definite is taken again as
                                      // Gauss-Newton (off: the bare recursion, for the dense
                                      // comparisons)
  bool needs_rest() const { return inertia_wrench || inertia_turn || turning_accelerations; }
};

// The implicit step's terms (implicit_step.h) over a step h.
struct ImplicitStage {
  double h = 0.0;           // s
  bool full = false;        // implicit_linearisation full: the pose terms' share too
  PoseTermSelection terms;  // with full: which of them (all, unless a study says otherwise)
};

// The forces an element applies at the state's pose with the rig at rest, as the pose-terms step
// reads them (implicit_linearisation full; implicit_pose_terms.h): each held in the world while
// the pose moves (how a force follows the pose is its element's own step stiffness, its augment)
// except a joint's torque, held in the joint's parent frame. A reader overrides what it reads.
class PoseForces {
 public:
  // a force at a point moving with the bone (N at a point in rig units, world)
  virtual void point(int /*bone*/, const Vec3& /*at_world*/, const Vec3& /*force_world*/) {}
  // a couple on the bone (N m, world axes)
  virtual void couple(int /*bone*/, const Vec3& /*torque_world*/) {}
  // a torque on the child bone and its opposite on the parent, turning with the parent (a torsion
  // spring's; implicit_pose_terms.h (5))
  virtual void joint(int /*child*/, const Vec3& /*torque_world*/) {}

 protected:
  ~PoseForces() = default;
};

// The stiffness damping auto's modes see at a pose (linear_modes.h): point elements K at points
// of bodies, couples K on bodies' own turns, and 3x3 blocks on balls' relative turns.
struct ModeStiffness {
  struct Point {
    int bone = 0;
    Vec3 point_world = Vec3::Zero();  // rig units
    Mat3 stiffness = Mat3::Zero();    // N/m, world
  };
  struct Block {
    int bone = 0;                   // the ball's bone (a pinned root's: against the world)
    Mat3 stiffness = Mat3::Zero();  // N m/rad, world axes, on w_bone - w_parent
  };
  struct Couple {
    int bone = 0;
    Mat3 stiffness = Mat3::Zero();  // N m/rad, world axes, on w_bone (a couple: no point)
  };
  std::vector<Point> points;
  std::vector<Couple> couples;
  std::vector<Block> blocks;
};

}  // namespace physik
