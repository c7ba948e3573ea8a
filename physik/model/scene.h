// Scenes: a rig, engine parameters, control points, a schedule of target changes, and how long
// to run. Files are read and written by physik/io/scene_io.h; the JSON format is documented in
// models/README.md ("Scenes").
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "physik/model/contact_model.h"
#include "physik/model/kinematics.h"
#include "physik/model/params.h"
#include "physik/model/rig.h"

namespace physik {

// A point fixed on a bone, pulled toward a target by a zero-rest-length spring:
//   linear  F = k (t - a)
//   capped  F = k min(|t - a|, c) (t - a)/|t - a|
// (paper Sec. 3.3; the original hard-codes c = 1). Forces in N, positions in rig units.
// A point's own spring law, k and cap are optional: one it does not give is the params'
// (control_spring, control_k, control_cap) at the time of use, so a tuner or a --set that
// changes the params reaches it, while a value the scene gives per point stays fixed.
struct ControlPoint {
  std::string name;    // optional label
  int bone = -1;       // index into the rig
  double alpha = 1.0;  // position along the bone: 0 = head, 1 = tail
  Vec3 target_world = Vec3::Zero();
  std::optional<SpringLaw> spring;  // unset: params.control_spring
  std::optional<double> k;          // N/m; unset: params.control_k
  std::optional<double> cap;        // rig units; unset: params.control_cap

  SpringLaw spring_in(const EngineParams& p) const { return spring ? *spring : p.control_spring; }
  double k_in(const EngineParams& p) const { return k ? *k : p.control_k; }
  double cap_in(const EngineParams& p) const { return cap ? *cap : p.control_cap; }
};

// A rotational spring's law, k and cap, for the targets that turn a bone (an orientation, an aim).
// Like a control point's, an unset law, k or cap is the params' at the time of use, turned into
// rotation by the bone's length L: k = control_k L^2 (a turn of 1 rad at the tail's end is a
// stretch of L, at control_k), c = control_cap / L.
struct TurnSpring {
  std::optional<SpringLaw> spring;  // unset: params.control_spring
  std::optional<double> k;          // N m/rad; unset: params.control_k L^2
  std::optional<double> cap;        // rad; unset: params.control_cap / L

  SpringLaw spring_in(const EngineParams& p) const { return spring ? *spring : p.control_spring; }
  double k_in(const EngineParams& p, double length) const {
    return k ? *k : p.control_k * length * length;
  }
  double cap_in(const EngineParams& p, double length) const {
    return cap ? *cap : p.control_cap / length;
  }
};

// A bone turned toward a target orientation by a rotational spring (physik/engine/
// orientation_springs.h), phi = log(q_target q^-1) the turn from the bone's frame to the target,
// world axes:
//   linear  tau = k phi
//   capped  tau = k min(|phi|, c) phi/|phi|
// Torques in N m, k in N m/rad, c in rad (TurnSpring).
struct OrientationTarget : TurnSpring {
  std::string name;                      // optional label
  int bone = -1;                         // index into the rig
  Quat target_world = Quat::Identity();  // world<-bone, as BoneFrames::orient_world (unit)

  double k_in(const EngineParams& p, const Rig& rig) const {
    return TurnSpring::k_in(p, rig.bone_length[bone]);
  }
  double cap_in(const EngineParams& p, const Rig& rig) const {
    return TurnSpring::cap_in(p, rig.bone_length[bone]);
  }
};

// A bone's axis turned toward a point seen from its head (physik/engine/aim_springs.h): with
// theta the angle from the axis u to the direction d to the point and n = u x d / |u x d|,
//   linear  tau = k theta n
//   capped  tau = k min(theta, c) n
// (TurnSpring), and a force at the head that goes with it. The bone's roll about d is free.
struct AimTarget : TurnSpring {
  std::string name;                 // optional label
  int bone = -1;                    // index into the rig
  Vec3 axis_bone = Vec3::UnitY();   // unit, the bone's frame (default: along it, head to tail)
  Vec3 point_world = Vec3::Zero();  // rig units

  double k_in(const EngineParams& p, const Rig& rig) const {
    return TurnSpring::k_in(p, rig.bone_length[bone]);
  }
  double cap_in(const EngineParams& p, const Rig& rig) const {
    return TurnSpring::cap_in(p, rig.bone_length[bone]);
  }
};

// A point a = head + alpha (tail - head) of a bone held at a world point p by a stiff linear
// spring, F = k (p - a) (physik/engine/pins.h: a spring in every scheme, and why). F in N, k in
// N/m, positions in rig units. An unset k is kPinStiffnessPerControlK times the params'
// control_k at the time of use: the pin then gives way by at most 1/100 of what the control
// springs pulling on it are stretched.
inline constexpr double kPinStiffnessPerControlK = 100.0;
struct Pin {
  std::string name;                 // optional label
  int bone = -1;                    // index into the rig
  double alpha = 0.0;               // position along the bone: 0 = head (the default), 1 = tail
  Vec3 point_world = Vec3::Zero();  // rig units (a scene file that gives none: where the point
                                    // is in the initial pose)
  std::optional<double> k;          // N/m; unset: kPinStiffnessPerControlK params.control_k

  double k_in(const EngineParams& p) const {
    return k ? *k : kPinStiffnessPerControlK * p.control_k;
  }
};

// At `step`, control point `control_point` gets a new target (interpolated per the params).
struct TargetChange {
  int step = 0;
  int control_point = 0;
  Vec3 target_world = Vec3::Zero();
};

struct ConvergenceParams {
  double residual_tol = 0.0;  // rig units; 0 = 1e-3 of Rig::reference_length (the height, or
                              // the mean bone length when that is longer). Reported, and a run
                              // whose final residuals exceed it is "converged" only if at rest
  double speed_tol = 0.0;     // rig units/s; 0 = 1e-3 of the rig's mean bone length per second
                              // (Rig::length_scale). At rest when sqrt(2 KE / total mass) is below
  int settle_steps = 10;      // consecutive steps at rest to call the run converged
  bool stop_when_converged = false;
  bool stop_at_residual_tol = false;  // IK use: converged = every control point within
                                      // residual_tol; stop there, or at rest short of it
  double divergence_energy = 0.0;     // J; > 0: diverged when KE passes it (a fixed bound);
                                      // 0 = the energy rule (physik/engine/run_monitor.h)
};

struct Scene {
  std::string file;      // where it came from ("" if built in code)
  std::string rig_file;  // resolved rig path
  std::string rig_ref;   // the rig path as the scene file gives it ("" for an inline rig)
  Rig rig;
  EngineParams params;
  std::vector<std::string> params_given;  // the params keys the scene file or an override gave
                                          // (the rest are the preset's)
  std::vector<ControlPoint> control_points;
  std::vector<OrientationTarget> orientation_targets;
  std::vector<AimTarget> aim_targets;
  std::vector<Pin> pins;
  std::vector<TargetChange> schedule;  // sorted by step
  int steps = 200;
  ConvergenceParams convergence;
  Pose initial_pose;
  // the frame of a clip of the rig's source skeleton that the initial pose came from
  // (initial_pose {"bvh", "frame"}): its channel values, one per channel of the source skeleton
  // (physik/io/bvh.h SourceFrames), so that a pose written back on the source skeleton keeps
  // what the rig cannot hold (a joint with no bone, a stretch); empty for none
  std::vector<double> initial_source_row;
  Vec3 initial_velocity_world = Vec3::Zero();  // rig units/s, a rigid translation of every bone
  Vec3 gravity_world = Vec3::Zero();  // rig units/s^2, on every bone's mass; zero as in the paper
  ContactModel collision;             // what the bones touch (contact_model.h; none by default)

  double residual_tol() const;
  double speed_tol() const;
  // the fixed bound before the energy rule (1e6 M h^2 unless given), still quoted by
  // experiments/hand_explodes.cpp's note; the run monitor uses it only when given
  double divergence_energy() const;
  // the first of "ground", "self_collision", "obstacles", "gravity", "orientation_targets",
  // "aim_targets", "pins" that the scene sets, or nullptr: what a solver that knows only the rig
  // and the control points (the classic IK solvers, the exact equilibrium) cannot read
  const char* world_field() const;
};

// A scene's start fits its rig's joints (rig.h): an anchored root starts at its rest head and
// does not move (initial_pose.root_head, initial_velocity), a fixed root unturned
// (initial_pose.rotation_deg); implicit_linearisation full needs a free root and no welds (its
// joints balls, hinges, universal joints or welds by locks: rig.h "Locked axes").
// InputError naming the scene's file and field.
void check_scene_joints(const Scene& scene);

// What the parameter table's conflict rules see of a scene (params.h ParamScene).
inline ParamScene param_scene(const Scene& scene) {
  ParamScene out;
  out.contacts = scene.collision.any();
  return out;
}

}  // namespace physik
