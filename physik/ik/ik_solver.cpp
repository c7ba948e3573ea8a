// The shared part of the classic IK solvers: goal bookkeeping, limits, the colinearity bump, the
// rotation recovery of position-based solvers, and the iteration loop. See ik_solver.h.
#include "physik/ik/ik_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "physik/model/errors.h"

namespace physik {

const char* to_string(IkMethod m) {
  switch (m) {
    case IkMethod::kFabrik:
      return "fabrik";
    case IkMethod::kCcd:
      return "ccd";
    case IkMethod::kJacobianTranspose:
      return "jt";
    case IkMethod::kDampedLeastSquares:
      return "dls";
    case IkMethod::kMassSpring:
      return "mass-spring";
    case IkMethod::kRotation:
      return "rotation";
  }
  return "?";
}

bool ik_method_from_string(const std::string& name, IkMethod& out) {
  for (IkMethod m : {IkMethod::kFabrik, IkMethod::kCcd, IkMethod::kJacobianTranspose,
                     IkMethod::kDampedLeastSquares, IkMethod::kMassSpring, IkMethod::kRotation}) {
    if (name == to_string(m)) {
      out = m;
      return true;
    }
  }
  return false;
}

double chain_reach(const Rig& rig, const std::vector<IkGoal>& goals) {
  double best = 0.0;
  for (const IkGoal& g : goals) best = std::max(best, rig.chain_length(g.bone, g.alpha));
  return best;
}

std::vector<int> dfs_goal_order(const std::vector<IkGoal>& goals) {
  std::vector<int> order(goals.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return goals[a].bone < goals[b].bone; });
  return order;
}

void goal_residuals(const BoneFrames& frames, const std::vector<IkGoal>& goals,
                    std::vector<double>& out) {
  out.resize(goals.size());
  for (std::size_t k = 0; k < goals.size(); ++k) {
    out[k] =
        goals[k].has_position
            ? (point_on_bone(frames, goals[k].bone, goals[k].alpha) - goals[k].target_world).norm()
            : 0.0;
  }
}

Vec3 goal_orientation_error(const BoneFrames& frames, const IkGoal& goal) {
  // rotation_vector takes the short way round (|phi| <= pi)
  return rotation_vector(goal.orientation_world * frames.orient_world[goal.bone].conjugate());
}

void goal_orientation_residuals(const BoneFrames& frames, const std::vector<IkGoal>& goals,
                                std::vector<double>& out) {
  out.resize(goals.size());
  for (std::size_t k = 0; k < goals.size(); ++k) {
    out[k] = goals[k].has_orientation ? goal_orientation_error(frames, goals[k]).norm() : 0.0;
  }
}

std::vector<char> active_bones(const Rig& rig, const std::vector<IkGoal>& goals) {
  std::vector<char> active(rig.nbone, 0);
  for (const IkGoal& g : goals) {
    for (int b = g.bone; b >= 0 && !active[b]; b = rig.bone_parent[b]) active[b] = 1;
  }
  // a fixed root and the bones welded into its body never move (rig.h: the root's joint)
  for (int i = 0; i < rig.nbone; ++i) {
    if (held_by_world(rig, i)) active[i] = 0;
  }
  return active;
}

bool held_by_world(const Rig& rig, int bone) {
  // a weld (or a fixed root's joint, a weld to the world) down to the world from this bone
  for (int b = bone; b >= 0; b = rig.bone_joint_parent[b]) {
    if (rig.bone_joint_type[b] != JointType::kWeld) return false;
  }
  return rig.root_joint == RootJoint::kFixed;
}

Quat quat_from_rotation_vector(const Vec3& v) {
  const double angle = v.norm();
  if (angle < 1e-12) return Quat(1.0, 0.5 * v.x(), 0.5 * v.y(), 0.5 * v.z()).normalized();
  return Quat(Eigen::AngleAxisd(angle, v / angle));
}

Quat clamp_to_limits(const Rig& rig, int bone, const Quat& q) {
  // the root's too: a pinned root's limits hold against its rest frame in the world (a free or
  // fixed root has none)
  const auto& lim = rig.bone_limit[bone];
  if (!lim[0].limited && !lim[1].limited && !lim[2].limited) return q;
  Vec3 v = rotation_vector(q);
  bool changed = false;
  for (int k = 0; k < 3; ++k) {
    if (!lim[k].limited) continue;
    const double c = std::clamp(v[k], lim[k].min, lim[k].max);
    changed |= c != v[k];
    v[k] = c;
  }
  return changed ? quat_from_rotation_vector(v) : q;
}

Quat rest_frame_world(const Rig& rig, const BoneFrames& frames, int bone) {
  const int p = rig.bone_parent[bone];
  if (p < 0) return rig.bone_rest_orient_parent[bone];
  return frames.orient_world[p] * rig.bone_rest_orient_parent[bone];
}

Quat rotate_local(const Rig& rig, const BoneFrames& frames, int bone, const Quat& q_local,
                  const Quat& delta_world) {
  const Quat P = rest_frame_world(rig, frames, bone);
  return (P.conjugate() * delta_world * P * q_local).normalized();
}

int bump_colinear_joints(const Rig& rig, const std::vector<char>& active, double bump, Pose& pose) {
  if (bump <= 0.0) return 0;
  int count = 0;
  BoneFrames frames = forward_kinematics(rig, pose);
  for (int i = 1; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    if (!active[i] || p < 0) continue;
    const Vec3 d_child = frames.orient_world[i] * Vec3::UnitY();
    const Vec3 d_parent = frames.orient_world[p] * Vec3::UnitY();
    if (d_child.cross(d_parent).norm() > 1e-6 || d_child.dot(d_parent) < 0.0) continue;
    // first free axis other than the bone's own y; bend in the direction the limits allow
    for (int k : {0, 2}) {
      const AxisLimit& l = rig.bone_limit[i][k];
      if (l.locked()) continue;
      Vec3 v = rotation_vector(pose.bone_local_rotation[i]);
      double step = bump;
      if (l.limited && v[k] + step > l.max) step = -bump;
      if (l.limited && v[k] + step < l.min) continue;
      v[k] += step;
      pose.bone_local_rotation[i] = quat_from_rotation_vector(v);
      ++count;
      forward_kinematics(rig, pose, frames);
      break;
    }
  }
  return count;
}

void aim_bones_at(const Rig& rig, const std::vector<char>& active,
                  const std::vector<Vec3>& tail_world, bool respect_limits, Pose& pose,
                  BoneFrames& frames) {
  frames.resize(rig.nbone);
  for (int i = 0; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    const Vec3 head =
        p < 0 ? pose.root_head_world
              : Vec3(frames.head_world[p] + frames.orient_world[p] * rig.bone_head_in_parent[i]);
    if (active[i]) {
      const Vec3 want = tail_world[i] - head;
      if (want.norm() > 1e-12) {
        // desired direction in the bone's rest frame; the bone's current direction there is
        // q_i e_y; the smallest rotation between them, applied in the rest frame, keeps twist
        const Quat P = p < 0 ? rig.bone_rest_orient_parent[i]
                             : Quat(frames.orient_world[p] * rig.bone_rest_orient_parent[i]);
        const Vec3 want_rest = P.conjugate() * want;
        const Vec3 now_rest = pose.bone_local_rotation[i] * Vec3::UnitY();
        Quat q =
            (Quat::FromTwoVectors(now_rest, want_rest) * pose.bone_local_rotation[i]).normalized();
        if (respect_limits) q = clamp_to_limits(rig, i, q);
        pose.bone_local_rotation[i] = q;
      }
    }
    const Quat parent = p < 0 ? Quat::Identity() : frames.orient_world[p];
    frames.orient_world[i] =
        (parent * rig.bone_rest_orient_parent[i] * pose.bone_local_rotation[i]).normalized();
    frames.head_world[i] = head;
    frames.tail_world[i] = head + frames.orient_world[i] * Vec3(0, rig.bone_length[i], 0);
  }
}

void ik_dofs(const Rig& rig, const std::vector<char>& active, bool respect_limits,
             std::vector<int>& dof_bone, std::vector<int>& dof_axis) {
  dof_bone.clear();
  dof_axis.clear();
  for (int i = 0; i < rig.nbone; ++i) {
    // a welded bone turns with the bone it is welded to (rig.h "Welds"): no axis of its own
    if (!active[i] || rig.bone_weld[i] >= 0) continue;
    for (int k = 0; k < 3; ++k) {
      if (respect_limits && rig.bone_limit[i][k].locked()) continue;  // the root's too
      dof_bone.push_back(i);
      dof_axis.push_back(k);
    }
  }
}

namespace {

bool pose_finite(const Pose& pose) {
  for (const Quat& q : pose.bone_local_rotation) {
    if (!q.coeffs().allFinite()) return false;
  }
  return pose.root_head_world.allFinite();
}

double max_of(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::isfinite(x) ? x : 1e300);
  return m;
}

// the report's residuals at the final pose; converged = position and orientation within theirs
void finish_report(const IkProblem& pb, const Pose& pose, IkReport& rep) {
  const BoneFrames frames = forward_kinematics(*pb.rig, pose);
  goal_residuals(frames, pb.goals, rep.residuals);  // DFS order here; solve_ik maps back
  goal_orientation_residuals(frames, pb.goals, rep.orientation_residuals);
  rep.residual = max_of(rep.residuals);
  rep.orientation_residual = max_of(rep.orientation_residuals);
  rep.orientation_tolerance = pb.orientation_tolerance;
  rep.orientation_length = pb.orientation_length;
  rep.converged = rep.residual <= pb.tolerance &&
                  (!pb.any_orientation || rep.orientation_residual <= pb.orientation_tolerance);
}

// the goals, pose and options solve_ik takes (InputError naming the goal and field otherwise)
void check_ik_input(IkMethod method, const Rig& rig, const std::vector<IkGoal>& goals,
                    const Pose& pose, const IkOptions& options) {
  if (goals.empty()) throw_input_error("ik", "goals", "", "no goals to solve for");
  for (std::size_t k = 0; k < goals.size(); ++k) {
    const std::string el = "goals[" + std::to_string(k) + "]";
    if (goals[k].bone < 0 || goals[k].bone >= rig.nbone) {
      throw_input_error("ik", el, "bone", "index out of range");
    }
    if (!(goals[k].alpha >= 0.0 && goals[k].alpha <= 1.0)) {
      throw_input_error("ik", el, "alpha", "must lie in [0, 1]");
    }
    if (goals[k].has_position && !goals[k].target_world.allFinite()) {
      throw_input_error("ik", el, "target", "not a finite position");
    }
    if (!goals[k].has_position && !goals[k].has_orientation) {
      throw_input_error("ik", el, "", "neither a position nor an orientation to reach");
    }
    if (goals[k].has_orientation) {
      const Quat& q = goals[k].orientation_world;
      if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-6) {
        throw_input_error("ik", el, "orientation", "not a unit quaternion");
      }
      if (method != IkMethod::kDampedLeastSquares && method != IkMethod::kJacobianTranspose) {
        throw_input_error("ik", el, "orientation",
                          std::string("the ") + to_string(method) +
                              " solver does not support orientation targets (dls and jt do)");
      }
    }
  }
  if (static_cast<int>(pose.bone_local_rotation.size()) != rig.nbone) {
    throw_input_error("ik", "pose", "bone_local_rotation", "size differs from the rig's bones");
  }
  if (options.max_iterations < 0) {
    throw_input_error("ik", "options", "max_iterations", "must not be negative");
  }
}

}  // namespace

IkReport run_ik_loop(const char* name, const IkProblem& pb, Pose& pose, const IkIterate& iterate) {
  const auto t0 = std::chrono::steady_clock::now();
  const Rig& rig = *pb.rig;
  const IkOptions& opt = pb.options;
  IkReport rep;
  rep.solver = name;
  rep.tolerance = pb.tolerance;
  rep.reach = pb.reach;

  bump_colinear_joints(rig, pb.active, opt.colinear_bump, pose);
  BoneFrames frames = forward_kinematics(rig, pose);
  std::vector<double> res, ores;
  // the loop's residual: the position residual, or with orientations the larger of it and the
  // orientation residual scaled onto the position tolerance (below the tolerance = both are)
  const double oscale =
      pb.orientation_tolerance > 0.0 ? pb.tolerance / pb.orientation_tolerance : 0.0;
  auto residual = [&]() {
    goal_residuals(frames, pb.goals, res);
    if (!pb.any_orientation) return max_of(res);
    goal_orientation_residuals(frames, pb.goals, ores);
    return std::max(max_of(res), oscale * max_of(ores));
  };
  double r = residual();
  Pose best = pose;
  double best_r = r;
  std::vector<double> history{r};
  int it = 0;
  while (r > pb.tolerance && it < opt.max_iterations) {
    iterate(pose, frames);
    ++it;
    if (!pose_finite(pose)) {  // never hand back NaN: restore the best pose and stop
      pose = best;
      break;
    }
    forward_kinematics(rig, pose, frames);
    r = residual();
    if (r < best_r) {  // kept only to replace a non-finite iterate
      best_r = r;
      best = pose;
    }
    history.push_back(r);
    const int w = opt.stall_window;
    if (w > 0 && static_cast<int>(history.size()) > w &&
        history[history.size() - 1 - w] - r < opt.stall_fraction * pb.reach && r > pb.tolerance) {
      rep.stalled = true;
      break;
    }
  }
  rep.iterations = it;
  finish_report(pb, pose, rep);
  rep.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

IkReport solve_ik(IkMethod method, const Rig& rig, const std::vector<IkGoal>& goals, Pose& pose,
                  const IkOptions& options) {
  check_ik_input(method, rig, goals, pose, options);
  IkProblem pb;
  pb.rig = &rig;
  pb.options = options;
  const std::vector<int> order = dfs_goal_order(goals);
  for (int k : order) pb.goals.push_back(goals[k]);
  pb.active = active_bones(rig, goals);
  pb.reach = chain_reach(rig, goals);
  pb.tolerance =
      options.tolerance > 0.0 ? options.tolerance : options.tolerance_fraction * pb.reach;
  pb.orientation_length = options.orientation_length > 0.0 ? options.orientation_length : pb.reach;
  pb.orientation_tolerance = options.orientation_tolerance > 0.0
                                 ? options.orientation_tolerance
                                 : pb.tolerance / pb.orientation_length;
  for (const IkGoal& g : goals) pb.any_orientation |= g.has_orientation;
  IkReport rep;
  switch (method) {
    case IkMethod::kFabrik:
      rep = solve_fabrik(pb, pose);
      break;
    case IkMethod::kCcd:
      rep = solve_ccd(pb, pose);
      break;
    case IkMethod::kJacobianTranspose:
      rep = solve_jacobian(pb, false, pose);
      break;
    case IkMethod::kDampedLeastSquares:
      rep = solve_jacobian(pb, true, pose);
      break;
    case IkMethod::kMassSpring:
      rep = solve_mass_spring(pb, pose);
      break;
    case IkMethod::kRotation:
      rep = solve_rotation_method(pb, pose);
      break;
  }
  // residuals back in the caller's goal order
  std::vector<double> res(goals.size()), ores(goals.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    res[order[k]] = rep.residuals[k];
    ores[order[k]] = rep.orientation_residuals[k];
  }
  rep.residuals = res;
  rep.orientation_residuals = ores;
  return rep;
}

}  // namespace physik
