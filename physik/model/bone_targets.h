// The checks of a bone target's values, wherever it is given: the scene file's
// "orientation_targets", "aim_targets" and "pins" (physik/io/scene_io.cpp reads their JSON and
// calls these), PosingSession and the command line's --orientation-target, --aim and --pin. Each
// failure is an InputError naming `source` (a file, a method or an option), `element`, the field
// and the reason.
//
// Frames and units: quaternions are world<-bone, [w, x, y, z], normalised here when within
// kQuaternionNormTol of unit (a value a person types, [0.7071, 0.7071, 0, 0], has norm 0.99999);
// points world, rig units; an aim's axis in the bone's frame (normalised here); k in N m/rad
// (turning targets) or N/m (pins), cap in rad, as scene.h states.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "physik/model/input_bounds.h"
#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik {

// An aim's point must lie at least this fraction of its bone's length from the bone's head at
// the start. The aim's pull at the head is a point element of stiffness k / d^2 at distance d
// (aim_springs.h), and with the default k = control_k L^2 a point at L / 10 makes it 100
// control_k, a pin's default stiffness; nearer, the direction swings with every small move of
// the head, and a point 1e-5 from it is no direction at all.
constexpr double kAimMinDistancePerLength = 0.1;

// Where an error is reported: "<source>: <element>: field '<field>': <reason>".
struct TargetSource {
  std::string source;   // the file, method or option ("scene.json", "set_pin", "--pin")
  std::string element;  // the element within it ("" or "'hand=1,0,0,0'")
};

// The rig's index of `bone`; unknown bone otherwise (with a "did you mean" when one is close).
int target_bone_index(const Scene& scene, const std::string& bone, const TargetSource& at);

// A unit quaternion from [w, x, y, z]; zero, non-finite or farther than kQuaternionNormTol from
// unit (the message names the norm) otherwise. A norm off 1 within the tolerance is normalised
// and said in `warnings` (one message naming `at`, the field and the norm).
Quat target_quaternion(double w, double x, double y, double z, const TargetSource& at,
                       std::vector<std::string>& warnings);

// A turning target's optional spring law ("linear" or "capped"), k and cap, range-checked as the
// control springs' rows.
void set_turn_spring(const std::optional<std::string>& spring, std::optional<double> k,
                     std::optional<double> cap, const TargetSource& at, TurnSpring& out);

// The axis an aim turns toward its point when it names none: the bone's forward axis in the
// human template (Rig::bone_forward_local: the face, a palm; human_body.h) where the rig gives it
// one, else +Y (along the bone, head to tail). Bone frame, unit.
Vec3 default_aim_axis(const Rig& rig, int bone);

// A look-at (`--look-at BONE=x,y,z`): an aim of the bone's forward axis; a bone without one is an
// InputError naming `at`, the field "bone" and the bones that have one.
Vec3 look_at_axis(const Rig& rig, int bone, const TargetSource& at);

// An aim's point must lie at least kAimMinDistancePerLength of its bone's length from the bone's
// head in `frames` (the message names the distance and that minimum); its axis is finite and
// nonzero, normalised by this call after scaling by its largest component (so [0, 1e155, 0],
// whose squared norm overflows, is +Y, not zero).
void check_aim_target(const Scene& scene, const BoneFrames& frames, AimTarget& aim,
                      const TargetSource& at);

// A pin on a welded bone is refused (pin the bone it is welded to); alpha in [0, 1], k > 0 when
// given, a finite point.
void check_pin(const Scene& scene, const Pin& pin, const TargetSource& at);

// At most one target of a kind per bone: `t` replaces the list's entry for its bone, or is added.
template <class Target>
void set_bone_target(std::vector<Target>& list, const Target& t) {
  for (Target& e : list) {
    if (e.bone == t.bone) {
      e = t;
      return;
    }
  }
  list.push_back(t);
}

// The list's entry for `bone` removed; false when there was none.
template <class Target>
bool clear_bone_target(std::vector<Target>& list, int bone) {
  const auto it =
      std::find_if(list.begin(), list.end(), [&](const Target& e) { return e.bone == bone; });
  if (it == list.end()) return false;
  list.erase(it);
  return true;
}

}  // namespace physik
