#include "physik/model/scene.h"

#include <algorithm>

#include "physik/model/errors.h"

namespace physik {

double Scene::residual_tol() const {
  if (convergence.residual_tol > 0.0) return convergence.residual_tol;
  return 1e-3 * rig.reference_length();
}

double Scene::speed_tol() const {
  return convergence.speed_tol > 0.0 ? convergence.speed_tol : 1e-3 * rig.length_scale();
}

double Scene::divergence_energy() const {
  const double h = rig.height();
  return convergence.divergence_energy > 0.0 ? convergence.divergence_energy
                                             : 1e6 * rig.total_mass() * h * h;
}

const char* Scene::world_field() const {
  if (collision.ground) return "ground";
  if (collision.self_collision) return "self_collision";
  if (!collision.obstacles.empty()) return "obstacles";
  if (!gravity_world.isZero()) return "gravity";
  if (!orientation_targets.empty()) return "orientation_targets";
  if (!aim_targets.empty()) return "aim_targets";
  if (!pins.empty()) return "pins";
  return nullptr;
}

void check_scene_joints(const Scene& s) {
  const Rig& rig = s.rig;
  if (s.params.scheme == Scheme::kImplicit &&
      s.params.implicit_linearisation == ImplicitLinearisation::kFull &&
      (rig.has_welds() || rig.root_anchored())) {
    throw_input_error(s.file, "params", "implicit_linearisation",
                      "full needs a rig with a free root and no welds (rig '" +
                          (rig.name.empty() ? s.rig_file : rig.name) +
                          "'); gauss-newton takes any rig");
  }
  if (!rig.root_anchored() || rig.nbone == 0) return;
  const std::string root = std::string("the rig's root is ") + to_string(rig.root_joint);
  const double tol = 1e-9 * std::max(1.0, rig.reference_length());
  if ((s.initial_pose.root_head_world - rig.bone_rest_head_world[0]).norm() > tol) {
    throw_input_error(s.file, "initial_pose", "root_head",
                      root + ": its head stays at its rest position");
  }
  if (!s.initial_velocity_world.isZero(0.0)) {
    throw_input_error(s.file, "", "initial_velocity", root + ": the rig cannot translate");
  }
  if (rig.root_joint == RootJoint::kFixed &&
      s.initial_pose.bone_local_rotation[0].angularDistance(Quat::Identity()) > 1e-12) {
    throw_input_error(s.file, "initial_pose", "rotation_deg." + rig.bone_name[0],
                      root + ": it does not turn");
  }
}

}  // namespace physik
