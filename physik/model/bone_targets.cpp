// The bone targets' checks: see bone_targets.h.
#include "physik/model/bone_targets.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "physik/model/errors.h"
#include "physik/model/message_number.h"
#include "physik/model/names.h"
#include "physik/model/params.h"

namespace physik {

namespace {

[[noreturn]] void fail(const TargetSource& at, const std::string& field,
                       const std::string& reason) {
  throw_input_error(at.source, at.element, field, reason);
}

// a value checked against a parameter row's range (the control springs' k and cap)
double in_row_range(const char* row, double v, const char* field, const TargetSource& at) {
  if (!std::isfinite(v)) fail(at, field, "not finite");
  const std::string why = range_violation(param_row(row), v);
  if (!why.empty()) fail(at, field, why);
  return v;
}

// a target's point: finite, and within the coordinates a rig may have
void check_point(const Vec3& p, const TargetSource& at) {
  if (!p.allFinite()) fail(at, "point", "not finite");
  static_assert(kMaxCoordinate == 1e9, "the message below quotes it");
  if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
    fail(at, "point", "a coordinate beyond +-1e9 (rig.h kMaxCoordinate)");
}

// a quaternion's norm with the digits that show how far it is from 1 (0.99999, 1.0011)
std::string norm_text(double n) {
  std::ostringstream o;
  o.precision(8);
  o << n;
  return o.str();
}

}  // namespace

int target_bone_index(const Scene& scene, const std::string& bone, const TargetSource& at) {
  const int b = scene.rig.find_bone(bone);
  if (b < 0) {
    fail(at, "bone",
         unknown_bone(bone, scene.rig) + " in rig " +
             (scene.rig_file.empty() ? scene.rig.name : scene.rig_file));
  }
  return b;
}

Quat target_quaternion(double w, double x, double y, double z, const TargetSource& at,
                       std::vector<std::string>& warnings) {
  const Eigen::Vector4d q(w, x, y, z);
  if (!q.allFinite()) fail(at, "quaternion", "not finite");
  // scaled by its largest component first: a norm near 1 is what matters, and no square overflows
  const double norm = q.stableNorm();
  if (norm == 0.0) fail(at, "quaternion", "zero quaternion: give a unit [w, x, y, z]");
  static_assert(kQuaternionNormTol == 1e-3, "the messages below quote it");
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTol)) {
    fail(at, "quaternion",
         "not a unit quaternion (norm " + norm_text(norm) +
             ", more than 1e-3 from 1); give [w, x, y, z] with w^2 + x^2 + y^2 + z^2 = 1");
  }
  if (norm != 1.0) {
    warnings.push_back(
        input_error_message(at.source, at.element, "quaternion",
                            "norm " + norm_text(norm) + " (within 1e-3 of 1): normalised to unit"));
  }
  return Quat(w / norm, x / norm, y / norm, z / norm).normalized();
}

void set_turn_spring(const std::optional<std::string>& spring, std::optional<double> k,
                     std::optional<double> cap, const TargetSource& at, TurnSpring& out) {
  out.spring.reset();
  if (spring) {
    const std::vector<std::string>& names = choice_names(SpringLaw{});
    const auto it = std::find(names.begin(), names.end(), *spring);
    if (it == names.end())
      fail(at, "spring", "unknown spring law '" + *spring + "' (linear|capped)");
    out.spring = static_cast<SpringLaw>(it - names.begin());
  }
  out.k = k ? std::optional<double>(in_row_range("control_k", *k, "k", at)) : std::nullopt;
  out.cap =
      cap ? std::optional<double>(in_row_range("control_cap", *cap, "cap", at)) : std::nullopt;
}

Vec3 default_aim_axis(const Rig& rig, int bone) {
  const Vec3& forward = rig.bone_forward_local[bone];
  return forward.isZero() ? Vec3::UnitY() : forward;
}

Vec3 look_at_axis(const Rig& rig, int bone, const TargetSource& at) {
  const Vec3& forward = rig.bone_forward_local[bone];
  if (!forward.isZero()) return forward;
  std::string with;
  int count = 0;
  for (int b = 0; b < rig.nbone; ++b) {
    if (rig.bone_forward_local[b].isZero()) continue;
    if (++count <= 6) with += (with.empty() ? "" : ", ") + rig.bone_name[b];
  }
  fail(at, "bone",
       "'" + rig.bone_name[bone] + "' has no forward axis (a face, a palm): " +
           (count == 0 ? std::string("this rig has none (a rig converted from a human skeleton, "
                                     "`rig from-bvh --body human`, gives every bone one); use "
                                     "--aim to turn the bone itself")
                       : "the rig's bones with one: " + with + (count > 6 ? ", ..." : "")));
}

void check_aim_target(const Scene& scene, const BoneFrames& frames, AimTarget& aim,
                      const TargetSource& at) {
  check_point(aim.point_world, at);
  if (!aim.axis_bone.allFinite()) fail(at, "axis", "not finite");
  if (aim.axis_bone.isZero(0.0))
    fail(at, "axis", "must not be zero (a direction in the bone's frame)");
  // scaled first: [0, 1e155, 0]'s squared norm overflows, and normalize() would make it zero
  aim.axis_bone.stableNormalize();
  const double length = scene.rig.bone_length[aim.bone];
  const double least = kAimMinDistancePerLength * length;
  const double d = (aim.point_world - frames.head_world[aim.bone]).norm();
  const double tol = 1e-9 * std::max(1.0, scene.rig.reference_length());
  static_assert(kAimMinDistancePerLength == 0.1, "the message below quotes it");
  if (!(d >= least) || d <= tol) {
    fail(at, "point",
         "lies " + message_number(d) + " rig units from the head of bone '" +
             scene.rig.bone_name[aim.bone] +
             "': an aim's point must be at least 0.1 of its "
             "bone's length (" +
             message_number(least) +
             ") from the head, or its direction swings with every move of the head");
  }
}

void check_pin(const Scene& scene, const Pin& pin, const TargetSource& at) {
  const int weld = scene.rig.bone_weld[pin.bone];
  if (weld >= 0) {
    fail(at, "bone",
         "'" + scene.rig.bone_name[pin.bone] + "' is welded to '" + scene.rig.bone_name[weld] +
             "': pin the bone it is welded to");
  }
  if (!(pin.alpha >= 0.0 && pin.alpha <= 1.0))
    fail(at, "alpha", "must lie in [0, 1] (0 = head, 1 = tail)");
  check_point(pin.point_world, at);
  if (pin.k) {
    in_row_range("control_k", *pin.k, "k", at);
    if (*pin.k == 0.0) fail(at, "k", "must be above 0 (a pin of no stiffness holds nothing)");
  }
}

}  // namespace physik
