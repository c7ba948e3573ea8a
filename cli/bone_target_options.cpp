// --orientation-target, --aim and --pin: bone targets given on the command line of simulate and
// solve, added to the scene after it is read (physik/model/bone_targets.h checks them as the
// scene file's "orientation_targets", "aim_targets" and "pins"). Each names a bone and its value:
//   --orientation-target BONE=w,x,y,z   the bone's target frame, world<-bone (unit quaternion)
//   --aim BONE=x,y,z                    the point its axis (+Y, head to tail) turns toward
//   --look-at BONE=x,y,z                the point its forward axis (the human template's face,
//                                       palm: Rig::bone_forward_local) turns toward
//   --pin BONE[=x,y,z]                  its head held at the point (default: where it starts)
// world frame, rig units; the spring, k and cap are the params' (--set control_k=... reaches
// them). One target of a kind per bone: an option replaces the scene's target of that bone.
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "physik/model/bone_targets.h"
#include "physik/model/errors.h"
#include "physik/model/scene.h"

namespace physik::cli {

namespace {

struct Given {
  std::string bone;
  std::vector<double> numbers;
  bool has_value = false;
};

// BONE=a,b,c (the last '=' splits, so a bone's name may hold one): the bone and `n` numbers;
// BONE alone when `optional` says the value may be left out
Given parse_given(const std::string& text, std::size_t n, const char* what, bool optional,
                  const TargetSource& at) {
  Given g;
  const std::size_t eq = text.rfind('=');
  if (eq == std::string::npos) {
    if (!optional)
      throw_input_error(at.source, at.element, "", std::string("expected BONE=") + what);
    g.bone = text;
    return g;
  }
  g.bone = text.substr(0, eq);
  g.has_value = true;
  const std::string value = text.substr(eq + 1);
  const std::string field = n == 4 ? "quaternion" : "point";
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = value.find(',', start);
    const std::string item =
        value.substr(start, comma == std::string::npos ? comma : comma - start);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') {
      throw_input_error(
          at.source, at.element, field,
          "expected " + std::to_string(n) + " numbers " + what + ", got '" + value + "'");
    }
    g.numbers.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (g.numbers.size() != n) {
    throw_input_error(at.source, at.element, field,
                      "expected " + std::to_string(n) + " numbers " + what + ", got " +
                          std::to_string(g.numbers.size()));
  }
  if (g.bone.empty()) throw_input_error(at.source, at.element, "bone", "no bone named before '='");
  return g;
}

Vec3 vec3_of(const Given& g) {
  return {g.numbers[0], g.numbers[1], g.numbers[2]};
}

// --aim (the bone's +Y) or --look-at (its forward axis)
void add_aim(const std::string& text, const char* option, bool forward, const BoneFrames& frames,
             Scene& scene) {
  const TargetSource src{option, "'" + text + "'"};
  const Given g = parse_given(text, 3, "x,y,z", false, src);
  AimTarget t;
  t.bone = target_bone_index(scene, g.bone, src);
  t.point_world = vec3_of(g);
  if (forward) t.axis_bone = look_at_axis(scene.rig, t.bone, src);
  check_aim_target(scene, frames, t, src);
  set_bone_target(scene.aim_targets, t);
}

}  // namespace

void add_bone_target_options(CLI::App* cmd, BoneTargetOptions& o) {
  cmd->add_option("--orientation-target", o.orientation,
                  "A bone turned toward a target frame, BONE=w,x,y,z: a unit quaternion, "
                  "world<-bone (repeat for more bones; replaces the scene's target of that bone)")
      ->type_name("BONE=W,X,Y,Z");
  cmd->add_option("--aim", o.aim,
                  "A bone's axis (its +Y, head to tail) turned toward a world point, BONE=x,y,z "
                  "(rig units; repeat for more bones)")
      ->type_name("BONE=X,Y,Z");
  cmd->add_option("--look-at", o.look_at,
                  "A bone's forward axis (the face, a palm: the human body of a rig converted "
                  "from a human skeleton) turned toward a world point, BONE=x,y,z (rig units; "
                  "repeat for more bones; one aim per bone, as --aim)")
      ->type_name("BONE=X,Y,Z");
  cmd->add_option("--pin", o.pin,
                  "A bone's head held at a world point, BONE=x,y,z, or BONE alone: where it is in "
                  "the initial pose (a stiff spring, 100 control_k; repeat for more bones)")
      ->type_name("BONE[=X,Y,Z]");
}

void apply_bone_target_options(const BoneTargetOptions& o, Scene& scene) {
  if (o.orientation.empty() && o.aim.empty() && o.pin.empty() && o.look_at.empty()) return;
  const BoneFrames frames = forward_kinematics(scene.rig, scene.initial_pose);
  const auto at = [](const char* option, const std::string& text) {
    return TargetSource{option, "'" + text + "'"};
  };
  for (const std::string& text : o.orientation) {
    const TargetSource src = at("--orientation-target", text);
    const Given g = parse_given(text, 4, "w,x,y,z", false, src);
    OrientationTarget t;
    t.bone = target_bone_index(scene, g.bone, src);
    std::vector<std::string> warnings;  // a norm within 1e-3 of 1, normalised: said once
    t.target_world =
        target_quaternion(g.numbers[0], g.numbers[1], g.numbers[2], g.numbers[3], src, warnings);
    for (const std::string& w : warnings) std::cerr << "physik: warning: " << w << "\n";
    set_bone_target(scene.orientation_targets, t);
  }
  for (const std::string& text : o.aim) add_aim(text, "--aim", false, frames, scene);
  for (const std::string& text : o.look_at) add_aim(text, "--look-at", true, frames, scene);
  for (const std::string& text : o.pin) {
    const TargetSource src = at("--pin", text);
    const Given g = parse_given(text, 3, "x,y,z", true, src);
    Pin pin;
    pin.bone = target_bone_index(scene, g.bone, src);
    pin.point_world = g.has_value ? vec3_of(g) : frames.head_world[pin.bone];
    check_pin(scene, pin, src);
    set_bone_target(scene.pins, pin);
  }
}

}  // namespace physik::cli
