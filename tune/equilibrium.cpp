#include "tune/equilibrium.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <ceres/ceres.h>

#include "physik/engine/torsion_springs.h"
#include "physik/model/errors.h"
#include "physik/model/joint_coordinates.h"

namespace physik::tune {

std::vector<Vec3> final_targets(const Scene& scene) {
  std::vector<Vec3> t;
  for (const ControlPoint& cp : scene.control_points) t.push_back(cp.target_world);
  for (const TargetChange& c : scene.schedule)
    t[c.control_point] = c.target_world;  // sorted by step
  return t;
}

namespace {

template <typename T>
using V3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Q = Eigen::Quaternion<T>;

// rotation vector of a unit quaternion, w >= 0 hemisphere (as physik::rotation_vector)
template <typename T>
V3<T> rotation_vector_t(Q<T> q) {
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  const V3<T> v = q.vec();
  const T s2 = v.squaredNorm();
  if (s2 < T(1e-24)) return T(2) * v / q.w();  // first order, differentiable at 0
  const T s = sqrt(s2);
  return v * (T(2) * atan2(s, q.w()) / s);
}

// residual r with r^2 = 2 U for a (signed) spring excess d, law with cap c
template <typename T>
T torsion_residual(SpringLaw law, double k, double c, const T& d) {
  const T ad = d < T(0) ? -d : d;
  if (law == SpringLaw::kLinear || ad <= T(c)) return sqrt(k) * d;
  const T r = sqrt(T(k * c) * (T(2) * ad - T(c)));
  return d < T(0) ? -r : r;
}

// a joint whose block holds its angles (t0, t1, 0, 0) instead of a quaternion: a hinge or a
// universal joint of the scene's scheme (rig.h "Locked axes"; the gauss-seidel scheme's are balls)
inline bool angle_block(const Rig& rig, LockedAxes locked, int i) {
  const JointType t = rig.joint_type(i, locked);
  return t == JointType::kHinge || t == JointType::kUniversal;
}

// q(t) = L exp(t0 e_a) exp(t1 e_b) (joint_coordinates.h), for Ceres' Jets
template <typename T>
Q<T> hinge_rotation_t(const Rig& rig, int i, const T* t) {
  const auto axis_turn = [](int axis, const T& angle) {
    Q<T> q(cos(angle / T(2)), T(0), T(0), T(0));
    q.vec()[axis] = sin(angle / T(2));
    return q;
  };
  const auto& axes = rig.bone_joint_axes[i];
  Q<T> q = rig.bone_joint_lock[i].cast<T>() * axis_turn(axes[0], t[0]);
  if (axes[1] >= 0) q = q * axis_turn(axes[1], t[1]);
  return q;
}

struct PotentialResiduals {
  const Scene* scene;
  std::vector<Vec3> targets;       // (ncontrol) goal targets
  std::vector<int> limited_bones;  // bones with at least one limited axis (a root only pinned)

  int num_residuals() const {
    return 3 * static_cast<int>(scene->control_points.size() + limited_bones.size());
  }

  // params[0] = root head (3), params[1 + i] = bone i's local rotation (x, y, z, w), or a hinge's
  // or universal joint's angles (t0, t1, 0, 0)
  template <typename T>
  bool operator()(T const* const* params, T* r) const {
    const Rig& rig = scene->rig;
    const EngineParams& ep = scene->params;
    const LockedAxes locked = ep.locked_axes();
    std::vector<Q<T>> orient(rig.nbone), local(rig.nbone);
    std::vector<V3<T>> head(rig.nbone), tail(rig.nbone);
    for (int i = 0; i < rig.nbone; ++i) {
      const T* q = params[1 + i];
      local[i] = angle_block(rig, locked, i) ? hinge_rotation_t(rig, i, q)
                                             : Q<T>(q[3], q[0], q[1], q[2]).normalized();
      const Q<T> rest = rig.bone_rest_orient_parent[i].cast<T>();
      const int p = rig.bone_parent[i];
      const int w = rig.bone_weld[i];
      if (p < 0) {
        orient[i] = rest * local[i];
        head[i] = V3<T>(params[0][0], params[0][1], params[0][2]);
      } else {
        // a welded bone keeps its rest frame in its weld's (its block is held constant)
        orient[i] = w >= 0 ? Q<T>(orient[w] * rig.bone_rest_orient_weld[i].cast<T>())
                           : Q<T>(orient[p] * rest * local[i]);
        head[i] = head[p] + orient[p] * rig.bone_head_in_parent[i].cast<T>();
      }
      tail[i] = head[i] + orient[i] * V3<T>(T(0), T(rig.bone_length[i]), T(0));
    }
    int at = 0;
    for (std::size_t c = 0; c < scene->control_points.size(); ++c) {
      const ControlPoint& cp = scene->control_points[c];
      const V3<T> a = head[cp.bone] + T(cp.alpha) * (tail[cp.bone] - head[cp.bone]);
      const V3<T> d = a - targets[c].cast<T>();
      const T d2 = d.squaredNorm();
      T s = T(1);
      const double cap = cp.cap_in(ep);
      if (cp.spring_in(ep) == SpringLaw::kCapped && d2 > T(cap * cap)) {
        const T dn = sqrt(d2);
        s = sqrt(T(cap) * (T(2) * dn - T(cap))) / dn;
      }
      for (int k = 0; k < 3; ++k) r[at++] = sqrt(cp.k_in(ep)) * s * d[k];
    }
    for (int i : limited_bones) {
      V3<T> theta;
      if (angle_block(rig, locked, i)) {  // the angles at their axes, the locks at their values
        const auto& axes = rig.bone_joint_axes[i];
        for (int k = 0; k < 3; ++k) theta[k] = T(rig.bone_limit[i][k].min);
        theta[axes[0]] = params[1 + i][0];
        if (axes[1] >= 0) theta[axes[1]] = params[1 + i][1];
      } else {
        theta = rotation_vector_t(local[i]);
      }
      for (int k = 0; k < 3; ++k) {
        const AxisLimit& l = rig.bone_limit[i][k];
        r[at++] = l.limited ? torsion_residual(ep.torsion_spring, ep.torsion_k, ep.torsion_cap,
                                               torsion_excess(l, ep.torsion_tolerance, theta[k]))
                            : T(0);
      }
    }
    return true;
  }
};

// the engine's excess (physik/engine/potential.h) of one bone of a pose, on the angles its
// torsion springs measure in the scene's scheme (torsion_springs.h torsion_angles)
Vec3 torsion_excess_of(const Scene& scene, const Pose& pose, int bone) {
  const Rig& rig = scene.rig;
  const TorsionKind kind = torsion_kind(rig, scene.params.locked_axes(), bone);
  const Vec3 theta = torsion_angles(rig, kind, bone, pose.bone_local_rotation[bone]);
  Vec3 e = Vec3::Zero();
  if (kind == TorsionKind::kNone) return e;
  for (int k = 0; k < 3; ++k) {
    const AxisLimit& l = rig.bone_limit[bone][k];
    if (l.limited) e[k] = torsion_excess(l, scene.params.torsion_tolerance, theta[k]);
  }
  return e;
}

}  // namespace

double scene_potential(const Scene& scene, const Pose& pose) {
  // the force list's one sum (potential.h), toward the schedule's final targets
  SimState s = state_at_pose(scene, pose, final_targets(scene));
  return potential_energy(scene, s);
}

double max_pose_distance(const BoneFrames& a, const BoneFrames& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.head_world.size() && i < b.head_world.size(); ++i) {
    m = std::max({m, (a.head_world[i] - b.head_world[i]).norm(),
                  (a.tail_world[i] - b.tail_world[i]).norm()});
  }
  return m;
}

namespace {

// Levenberg-Marquardt to machine precision: the minimum is the reference PhysIK is measured
// against, so it stops on tiny tolerances, not on a budget
ceres::Solver::Options solver_options(const EquilibriumOptions& opt) {
  ceres::Solver::Options so;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = opt.max_iterations;
  so.function_tolerance = 1e-16;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.num_threads = 1;
  so.minimizer_progress_to_stdout = opt.verbose;
  return so;
}

}  // namespace

namespace {

// the solved pose's measures: distances and spring potentials
void measure_result(const Scene& scene, const std::vector<int>& limited_bones,
                    EquilibriumResult& out) {
  const Rig& rig = scene.rig;
  out.frames = forward_kinematics(rig, out.pose);
  out.targets_world = final_targets(scene);
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const double d = (point_on_bone(out.frames, cp.bone, cp.alpha) - out.targets_world[c]).norm();
    out.control_distance.push_back(d);
  }
  out.torsion_excess.assign(rig.nbone, Vec3::Zero());
  for (int i : limited_bones) out.torsion_excess[i] = torsion_excess_of(scene, out.pose, i);
  // the potentials are the force list's elements' (potential.h), at the solved pose
  SimState at = state_at_pose(scene, out.pose, out.targets_world);
  out.control_potential = control_springs_potential(scene, at);
  out.torsion_potential = torsion_springs_potential(scene, at);
  out.potential = potential_energy(scene, at);
}

// The pose of the parameter blocks: root head, then one quaternion (x, y, z, w) per bone, or a
// hinge's or universal joint's angles.
Pose pose_from_blocks(const Scene& scene, const std::vector<double>& root,
                      const std::vector<std::array<double, 4>>& quats) {
  const Rig& rig = scene.rig;
  Pose pose;
  pose.root_head_world = Vec3(root[0], root[1], root[2]);
  pose.bone_local_rotation.resize(quats.size());
  for (std::size_t i = 0; i < quats.size(); ++i) {
    const int b = static_cast<int>(i);
    pose.bone_local_rotation[i] =
        angle_block(rig, scene.params.locked_axes(), b)
            ? hinge_rotation(rig, b, Vec2(quats[i][0], quats[i][1]))
            : Quat(quats[i][3], quats[i][0], quats[i][1], quats[i][2]).normalized();
  }
  return pose;
}

// what the equilibrium can solve: control points, and no potential but the springs'
void check_equilibrium_scene(const Scene& scene) {
  if (scene.control_points.empty()) {
    throw_input_error(scene.file, "control_points", "",
                      "an equilibrium needs at least one control point (else every pose is one)");
  }
  if (const char* field = scene.world_field()) {
    throw_input_error(scene.file, field, "",
                      "the exact equilibrium has the control and torsion springs' potential "
                      "only: it would be the equilibrium of another scene");
  }
}

// every rotation on its manifold, a hinge's angles in their own (its unused entries held); the
// blocks with nothing to solve for held: a weld's rotation (its weld's), a fixed root's, a weld
// by locks (at its lock rotation L) in the exact and implicit schemes, an anchored root's head
void hold_joints(const Scene& scene, std::vector<double>& root,
                 std::vector<std::array<double, 4>>& quats, ceres::Problem& problem) {
  const Rig& rig = scene.rig;
  const LockedAxes locked = scene.params.locked_axes();
  for (int i = 0; i < rig.nbone; ++i) {
    if (angle_block(rig, locked, i)) {
      const bool hinge = rig.joint_type(i, locked) == JointType::kHinge;
      problem.SetManifold(
          quats[i].data(),
          new ceres::SubsetManifold(4, hinge ? std::vector<int>{1, 2, 3} : std::vector<int>{2, 3}));
      continue;
    }
    problem.SetManifold(quats[i].data(), new ceres::EigenQuaternionManifold);
    if (rig.joint_type(i, locked) == JointType::kWeld) {
      problem.SetParameterBlockConstant(quats[i].data());
    }
  }
  if (rig.root_anchored()) problem.SetParameterBlockConstant(root.data());
}

// the bones' blocks at the start pose: a quaternion (x, y, z, w) per bone, a hinge's or universal
// joint's angles put on its set (init_state's rule), a weld by locks at its locks
std::vector<std::array<double, 4>> start_blocks(const Scene& scene, const Pose& start) {
  const Rig& rig = scene.rig;
  std::vector<std::array<double, 4>> quats(rig.nbone);
  const LockedAxes locked = scene.params.locked_axes();
  for (int i = 0; i < rig.nbone; ++i) {
    Quat q = start.bone_local_rotation[i].normalized();
    if (angle_block(rig, locked, i)) {
      const Vec2 t = hinge_coordinates(rig, i, q);
      quats[i] = {t[0], t[1], 0.0, 0.0};
      continue;
    }
    if (locked == LockedAxes::kRemoved && rig.joint_type(i, locked) == JointType::kWeld &&
        !rig.welded(i) && !(i == 0 && rig.root_joint == RootJoint::kFixed)) {
      q = rig.bone_joint_lock[i];
    }
    quats[i] = {q.x(), q.y(), q.z(), q.w()};
  }
  return quats;
}

}  // namespace

EquilibriumResult solve_equilibrium(const Scene& scene, const EquilibriumOptions& opt) {
  const Rig& rig = scene.rig;
  check_equilibrium_scene(scene);
  const Pose start = opt.start ? *opt.start : scene.initial_pose;
  if (static_cast<int>(start.bone_local_rotation.size()) != rig.nbone) {
    throw_input_error(scene.file, "initial_pose", "", "start pose does not match the rig");
  }

  auto* functor = new PotentialResiduals{&scene, final_targets(scene), {}};
  if (scene.params.torsion_k > 0.0) {
    for (int i = 0; i < rig.nbone; ++i) {
      const auto& l = rig.bone_limit[i];
      if (l[0].limited || l[1].limited || l[2].limited) functor->limited_bones.push_back(i);
    }
  }
  const std::vector<int> limited_bones = functor->limited_bones;  // the problem owns the functor
  const int nres = functor->num_residuals();

  // parameter blocks: root head, then one quaternion (x, y, z, w) per bone
  std::vector<double> root(start.root_head_world.data(), start.root_head_world.data() + 3);
  std::vector<std::array<double, 4>> quats = start_blocks(scene, start);
  auto* cost = new ceres::DynamicAutoDiffCostFunction<PotentialResiduals, 4>(functor);
  std::vector<double*> blocks;
  cost->AddParameterBlock(3);
  blocks.push_back(root.data());
  for (int i = 0; i < rig.nbone; ++i) {
    cost->AddParameterBlock(4);
    blocks.push_back(quats[i].data());
  }
  cost->SetNumResiduals(nres);

  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, blocks);
  hold_joints(scene, root, quats, problem);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options(opt), &problem, &summary);

  EquilibriumResult out;
  out.pose = pose_from_blocks(scene, root, quats);
  // a welded bone's rotation follows its weld's (kinematics.h)
  welded_local_rotations(rig, forward_kinematics(rig, out.pose), out.pose);
  measure_result(scene, limited_bones, out);
  out.iterations = static_cast<int>(summary.iterations.size());
  if (!summary.iterations.empty())
    out.gradient_max_norm = summary.iterations.back().gradient_max_norm;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.ceres_brief = summary.BriefReport();
  out.ceres_full = summary.FullReport();
  return out;
}

nlohmann::json equilibrium_to_json(const Scene& scene, const EquilibriumResult& e) {
  using nlohmann::json;
  const Rig& rig = scene.rig;
  json cps = json::array();
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    const Vec3& t = e.targets_world[c];
    const Vec3 a = point_on_bone(e.frames, cp.bone, cp.alpha);
    cps.push_back({{"name", cp.name},
                   {"bone", rig.bone_name[cp.bone]},
                   {"target", {t.x(), t.y(), t.z()}},
                   {"attachment", {a.x(), a.y(), a.z()}},
                   {"distance", e.control_distance[c]}});
  }
  json rot = json::object(), excess = json::object();
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3 v = rotation_vector(e.pose.bone_local_rotation[i]) * (180.0 / kPi);
    rot[rig.bone_name[i]] = {v.x(), v.y(), v.z()};
    if (!e.torsion_excess[i].isZero(0.0)) {
      const Vec3 d = e.torsion_excess[i] * (180.0 / kPi);
      excess[rig.bone_name[i]] = {d.x(), d.y(), d.z()};
    }
  }
  const Vec3& r = e.pose.root_head_world;
  return {{"scene", scene.file},
          {"rig", scene.rig_file},
          {"converged", e.converged},
          {"iterations", e.iterations},
          {"potential", e.potential},
          {"control_potential", e.control_potential},
          {"torsion_potential", e.torsion_potential},
          {"gradient_max_norm", e.gradient_max_norm},
          {"max_control_distance",
           e.control_distance.empty()
               ? 0.0
               : *std::max_element(e.control_distance.begin(), e.control_distance.end())},
          {"control_points", cps},
          {"torsion_excess_deg", excess},
          {"pose", {{"root_head", {r.x(), r.y(), r.z()}}, {"rotation_deg", rot}}},
          {"ceres", e.ceres_brief}};
}

}  // namespace physik::tune
