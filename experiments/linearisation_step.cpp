// The dense reference step and the solve rule of the linearisation study (linearisation.h).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "experiments/linearisation.h"
#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/run_monitor.h"
#include "physik/model/joint_coordinates.h"
#include "physik/posing/posing_session.h"

namespace physik::experiments::linearisation {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

const char* variant_name(Variant v) {
  switch (v) {
    case Variant::kShipped:
      return "shipped";
    case Variant::kNewton:
      return "newton";
    case Variant::kNewtonAtRest:
      return "newton_at_rest";
    case Variant::kNewtonNoGyro:
      return "newton_no_gyro";
    case Variant::kShippedDcdv:
      return "shipped_dcdv";
    case Variant::kPoseForces:
      return "pose_forces";
    case Variant::kPoseInertia:
      return "pose_inertia";
    case Variant::kShippedDense:
      return "shipped_dense";
    case Variant::kFull:
      return "full";
    case Variant::kFullForces:
      return "full_forces";
    case Variant::kFullInertia:
      return "full_inertia";
    case Variant::kFullNoZ:
      return "full_no_z";
    case Variant::kFullSketch:
      return "full_sketch";
  }
  return "?";
}

bool is_recursive(Variant v) {
  return v == Variant::kShipped || v == Variant::kFull || v == Variant::kFullForces ||
         v == Variant::kFullInertia || v == Variant::kFullNoZ || v == Variant::kFullSketch;
}

namespace {

// central differences: rig units, rad, rig units/s, rad/s. Near the round-off optimum eps^(1/3)
// (6e-6) for quantities of order 1: at 1e-6 the dense step's error was round-off (PoseTerms'
// system error fell 10x from 1e-6 to 1e-5 and grew 3x at 3e-7), up to 2.6e-8 of S on hinged trees
constexpr double kEps = 1e-5;

// The study's coordinates: MuJoCo's qvel layout of the rig's joint model (rig.h "Locked axes";
// the study's rigs have a free root): the root's centre velocity (world) and w (local), then per
// bone from Rig::bone_dofadr its joint's coordinates: a ball's u (local), a hinge's or
// universal's angle rates (joint_coordinates.h); a weld none. A joint's entries are the first
// rotational_coordinates of its joint_vel_local and joint_accel_local.
int nv(const Rig& rig) {
  return rig.nv;
}
int first_dof(const Rig& rig, int bone) {
  return rig.bone_dofadr[bone] + (bone == 0 ? 3 : 0);  // the free root's rotation after its centre
}
int coordinates(const Rig& rig, int bone) {
  return rotational_coordinates(rig.bone_joint_type[bone]);
}

// the bone whose joint owns coordinate k >= 3, and its index there
std::pair<int, int> dof_of(const Rig& rig, int k) {
  for (int i = rig.nbone - 1; i >= 0; --i) {
    const int first = first_dof(rig, i);
    if (k >= first && k < first + coordinates(rig, i)) return {i, k - first};
  }
  throw std::invalid_argument("linearisation: no coordinate " + std::to_string(k));
}

// the world axis a unit rate of bone i's coordinate c turns the bone about: its local axis c (a
// ball, the root), a hinge's or universal's s_c
Vec3 dof_axis_world(const Rig& rig, const SimState& s, int i, int c) {
  const JointType type = rig.bone_joint_type[i];
  if (type == JointType::kBall || type == JointType::kFree) {
    return s.frames.orient_world[i] * Vec3::Unit(c);
  }
  const int p = rig.bone_parent[i];
  Vec3 s0, s1;
  hinge_axes_world(rig, i, p < 0 ? Quat::Identity() : s.frames.orient_world[p],
                   s.frames.orient_world[i], s0, s1);
  return c == 0 ? s0 : s1;
}

// the joints' coordinates of per-bone vectors (joint_vel_local, joint_accel_local) into v after
// its first three entries, or back
void gather(const Rig& rig, const std::vector<Vec3>& per_bone, VecX& v) {
  for (int i = 0; i < rig.nbone; ++i) {
    for (int c = 0; c < coordinates(rig, i); ++c) v[first_dof(rig, i) + c] = per_bone[i][c];
  }
}
void scatter(const Rig& rig, const VecX& v, std::vector<Vec3>& per_bone) {
  for (int i = 0; i < rig.nbone; ++i) {
    for (int c = 0; c < coordinates(rig, i); ++c) per_bone[i][c] = v[first_dof(rig, i) + c];
  }
}

void set_joint_velocity(const Rig& rig, SimState& s, const VecX& v) {
  s.joint_space.root_vel_world = v.head<3>();
  scatter(rig, v, s.joint_space.joint_vel_local);
}

// q (+) e along dof k: the root's centre, a quaternion turned about its local axis, or a hinge's
// angle
void perturb_position(const Rig& rig, SimState& s, int k, double e) {
  if (k < 3) {
    s.joint_space.root_com_world[k] += e;
    return;
  }
  const auto [bone, c] = dof_of(rig, k);
  const JointType type = rig.bone_joint_type[bone];
  if (type == JointType::kHinge || type == JointType::kUniversal) {
    s.joint_space.hinge_angle[bone][c] += e;
    s.pose.bone_local_rotation[bone] = hinge_rotation(rig, bone, s.joint_space.hinge_angle[bone]);
    return;
  }
  Quat& q = bone == 0 ? s.joint_space.root_orient_world : s.pose.bone_local_rotation[bone];
  quat_integrate(q, e * Vec3::Unit(c), 1.0);
}

// the accelerations of the state's last solve, in the study's coordinates
VecX joint_accelerations(const Rig& rig, const SimState& s) {
  VecX a(nv(rig));
  a.head<3>() = s.joint_space.articulated.root_accel_world;
  gather(rig, s.joint_space.articulated.joint_accel_local, a);
  return a;
}

// a scratch copy of a state: assigning into one that has the same sizes reuses its buffers (the
// study copies a state per force evaluation)
SimState& scratch(const SimState& from) {
  thread_local SimState work;
  work = from;
  return work;
}

// the exact accelerations at the joint state (the world view rebuilt from it)
VecX exact_accelerations(const Scene& scene, const SimState& state) {
  SimState& s = scratch(state);
  world_from_joint_space(scene.rig, s);
  apply_forces(scene, s);
  solve_articulated(scene.rig, scene.params, s);
  return joint_accelerations(scene.rig, s);
}

// a generalised force of size f on dof k (qvel layout) added to the state's wrench: a force at
// the root's centre, a torque about the root's local axis, or a torque pair about a joint's axis
// (+ on the bone, - on its parent: its virtual power is the joint's rate)
void add_unit_force(const Rig& rig, SimState& s, int k, double f) {
  if (k < 3) {
    s.force_world[0][k] += f;
    return;
  }
  const auto [bone, c] = dof_of(rig, k);
  const Vec3 t = f * dof_axis_world(rig, s, bone, c);
  s.torque_world[bone] += t;
  if (bone > 0) s.torque_world[rig.bone_parent[bone]] -= t;
}

// the accelerations of the shipped implicit solve (implicit = true) or the exact explicit one,
// with a generalised force of size f on dof k added (k < 0: none)
VecX solve_with_force(const Scene& scene, const SimState& state, int k, bool implicit, double h,
                      const PoseTermSelection& terms = {}, double f = 1.0) {
  SimState& s = scratch(state);
  world_from_joint_space(scene.rig, s);
  apply_forces(scene, s);
  if (k >= 0) add_unit_force(scene.rig, s, k, f);
  if (implicit) {
    solve_implicit(scene, s, h, terms);
  } else {
    solve_articulated(scene.rig, scene.params, s);
  }
  return joint_accelerations(scene.rig, s);
}

// A_v = da/dv at the state, by central differences
MatX rate_derivative(const Scene& scene, const SimState& base) {
  const int n = nv(scene.rig);
  const VecX v0 = joint_velocity(scene.rig, base);
  MatX A_v(n, n);
  SimState plus = base, minus = base;
  for (int k = 0; k < n; ++k) {
    VecX vp = v0, vm = v0;
    vp[k] += kEps;
    vm[k] -= kEps;
    set_joint_velocity(scene.rig, plus, vp);
    set_joint_velocity(scene.rig, minus, vm);
    A_v.col(k) =
        (exact_accelerations(scene, plus) - exact_accelerations(scene, minus)) / (2.0 * kEps);
  }
  return A_v;
}

// shipped_dcdv's accelerations (linearisation.h)
VecX shipped_with_dcdv(const Scene& given, const SimState& s, double h) {
  Scene scene = given;  // the shipped (Gauss-Newton) step, whatever the scene's linearisation
  scene.params.implicit_linearisation = ImplicitLinearisation::kGaussNewton;
  const int n = nv(scene.rig);
  SimState at_rest = s;
  set_joint_velocity(scene.rig, at_rest, VecX::Zero(n));
  const MatX Minv_Cv = rate_derivative(scene, at_rest) - rate_derivative(scene, s);
  const MatX M = unit_force_response(scene, s, false, h).inverse();
  const MatX S = MatX::Identity(n, n) + h * unit_force_response(scene, s, true, h) * M * Minv_Cv;
  return S.partialPivLu().solve(solve_with_force(scene, s, -1, true, h));
}

}  // namespace

MatX unit_force_response(const Scene& scene, const SimState& s, bool implicit, double h,
                         const PoseTermSelection& terms) {
  const int n = nv(scene.rig);
  const VecX base = solve_with_force(scene, s, -1, implicit, h, terms);
  MatX out(n, n);
  for (int k = 0; k < n; ++k) {
    // the solve is linear in the force, so a column is (a(f e_k) - a(0)) / f for any f; with f = 1
    // its round-off is eps |a(0)| / |column|, which a moving state's accelerations make large
    // (columns of 0.24 to 11 against |a(0)| = 58: PoseTerms' system error 2e-8, an aim 1.2 rad
    // off). Retaken with f = |a(0)| / |column| where that exceeds 1, the round-off is eps's own
    out.col(k) = solve_with_force(scene, s, k, implicit, h, terms) - base;
    const double f = base.norm() / out.col(k).norm();
    if (f > 1.0 && std::isfinite(f)) {
      out.col(k) = (solve_with_force(scene, s, k, implicit, h, terms, f) - base) / f;
    }
  }
  return out;
}

VecX joint_velocity(const Rig& rig, const SimState& s) {
  VecX v(nv(rig));
  v.head<3>() = s.joint_space.root_vel_world;
  gather(rig, s.joint_space.joint_vel_local, v);
  return v;
}

VecX accelerations(const Scene& scene, const SimState& state) {
  return exact_accelerations(scene, state);
}

VecX applied_generalised_force(const Scene& scene, const SimState& state) {
  SimState& s = scratch(state);
  world_from_joint_space(scene.rig, s);
  apply_forces(scene, s);
  const Rig& rig = scene.rig;
  const int n = rig.nbone;
  // each bone's subtree wrench about its point o_i (head; the root's centre), leaves to root
  // (parents come first); a ball's (or the root's) rate u_k turns that subtree about o_i, about
  // the world axis R_i e_k (a hinge's about s_k), so its generalised force is that axis . moment_i
  std::vector<Vec3> force(n), moment(n);
  const auto point = [&](int i) { return i == 0 ? s.com_world[0] : s.frames.head_world[i]; };
  for (int i = 0; i < n; ++i) {
    force[i] = s.force_world[i];
    moment[i] = s.torque_world[i] + (s.com_world[i] - point(i)).cross(s.force_world[i]);
  }
  for (int i = n - 1; i > 0; --i) {
    const int p = rig.bone_parent[i];
    force[p] += force[i];
    moment[p] += moment[i] + (point(i) - point(p)).cross(force[i]);
  }
  VecX Q(nv(rig));
  Q.head<3>() = force[0];
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < coordinates(rig, i); ++c)
      Q[first_dof(rig, i) + c] = dof_axis_world(rig, s, i, c).dot(moment[i]);
  }
  return Q;
}

namespace {

// d/dq of `f` at the state, by central differences on the joint manifold
template <typename F>
MatX pose_derivative(const Rig& rig, const SimState& base, F f) {
  const int n = nv(rig);
  MatX out(n, n);
  SimState plus = base, minus = base;
  for (int k = 0; k < n; ++k) {
    plus = base;
    minus = base;
    perturb_position(rig, plus, k, kEps);
    perturb_position(rig, minus, k, -kEps);
    out.col(k) = (f(plus) - f(minus)) / (2.0 * kEps);
  }
  return out;
}

}  // namespace

void derivatives(const Scene& scene, const SimState& state, Variant variant, MatX& A_q, MatX& A_v,
                 double h) {
  if (is_recursive(variant) || variant == Variant::kShippedDcdv) {
    throw std::invalid_argument("derivatives: only the dense variants have dense derivatives");
  }
  const int n = nv(scene.rig);
  SimState at_rest = state;
  set_joint_velocity(scene.rig, at_rest, VecX::Zero(n));
  const auto accel = [&](const SimState& x) { return exact_accelerations(scene, x); };
  if (variant == Variant::kNewton || variant == Variant::kNewtonNoGyro) {
    A_q = pose_derivative(scene.rig, state, accel);
    if (variant == Variant::kNewton) {
      A_v = rate_derivative(scene, state);
    } else {
      Scene no_gyro = scene;
      no_gyro.params.gyroscopic = false;
      A_v = rate_derivative(no_gyro, state);
    }
    return;
  }
  A_v = rate_derivative(scene, at_rest);
  if (variant == Variant::kNewtonAtRest) {
    A_q = pose_derivative(scene.rig, at_rest, accel);
    return;
  }
  const MatX M_inv = unit_force_response(scene, at_rest, false, h);
  const auto force = [&](const SimState& x) { return applied_generalised_force(scene, x); };
  const MatX pose_forces = M_inv * pose_derivative(scene.rig, at_rest, force);  // M^-1 dtau/dq
  if (variant == Variant::kPoseForces) {
    A_q = pose_forces;
    return;
  }
  // -M^-1 K of the shipped step: M^-1 P = 1 + h M^-1 D + h^2 M^-1 K, M^-1 D = -A_v(pose, 0)
  // (its Gauss-Newton K, whatever the scene's implicit_linearisation)
  Scene gauss_newton = scene;
  gauss_newton.params.implicit_linearisation = ImplicitLinearisation::kGaussNewton;
  const MatX P = unit_force_response(gauss_newton, at_rest, true, h).inverse();
  A_q = -(M_inv * P - MatX::Identity(n, n) + h * A_v) / (h * h);
  if (variant == Variant::kPoseInertia)
    A_q += pose_derivative(scene.rig, at_rest, accel) - pose_forces;
}

namespace {

// the term selection of an O(n) full variant (linearisation.h)
PoseTermSelection selection_of(Variant v) {
  PoseTermSelection out;
  out.gauss_newton_retake = false;  // the dense variants' twins: the bare recursion
  const bool forces = v != Variant::kFullInertia, inertia = v != Variant::kFullForces;
  out.forces = out.torque_frame = forces;
  out.inertia_wrench = out.inertia_turn = out.turning_accelerations = inertia;
  if (v == Variant::kFullNoZ) out.turning_accelerations = false;
  if (v == Variant::kFullSketch) {
    out.torsion_in_wrench = true;
    out.torque_frame = out.inertia_turn = out.turning_accelerations = false;
  }
  return out;
}

// the scene an O(n) variant steps: shipped the Gauss-Newton step, the full ones the full step,
// whatever the scene's implicit_linearisation (the dense variants: the scene as given)
Scene linearised_scene(const Scene& scene, Variant v) {
  Scene out = scene;
  if (is_recursive(v)) {
    out.params.implicit_linearisation =
        v == Variant::kShipped ? ImplicitLinearisation::kGaussNewton : ImplicitLinearisation::kFull;
  }
  return out;
}

// what the engine's energy guard passes through to the bare step: the variant, its scene
// (linearised_scene), and a count of every bare step taken, rejected ones included
struct BareContext {
  Variant variant;
  const Scene* linearised;
  int* taken;
};

// one bare step of the variant, in the shape of the engine's (implicit_advance.h BareStep), so
// that the shipped guard holds it
void variant_step(const Scene& scene, SimState& s, double h, const void* context) {
  const BareContext& c = *static_cast<const BareContext*>(context);
  ++*c.taken;
  if (is_recursive(c.variant)) {
    // the engine's bare step (implicit_advance.h take_implicit_step) with the variant's terms
    ForceStage stage;
    stage.step = h;
    apply_forces(*c.linearised, s, stage);
    solve_implicit(*c.linearised, s, h,
                   c.variant == Variant::kShipped ? PoseTermSelection{} : selection_of(c.variant));
    integrate_joint_space(c.linearised->rig, h, s);
    return;
  }
  VecX next;
  if (c.variant == Variant::kShippedDcdv) {
    next = shipped_with_dcdv(scene, s, h);
  } else {
    MatX A_q, A_v;
    derivatives(scene, s, c.variant, A_q, A_v, h);
    const int n = nv(scene.rig);
    const VecX a = exact_accelerations(scene, s), v = joint_velocity(scene.rig, s);
    const MatX S = MatX::Identity(n, n) - h * A_v - h * h * A_q;
    next = S.partialPivLu().solve(a + h * (A_q * v));  // (L)
  }
  s.joint_space.articulated.root_accel_world = next.head<3>();
  scatter(scene.rig, next, s.joint_space.articulated.joint_accel_local);
  integrate_joint_space(scene.rig, h, s);
}

}  // namespace

void bare_step(const Scene& scene, SimState& s, double h, Variant v) {
  int taken = 0;
  const Scene linearised = linearised_scene(scene, v);
  const BareContext context{v, &linearised, &taken};
  variant_step(scene, s, h, &context);
  s.step += 1;
  s.time += h;
}

SolveCount solve(const Scene& scene, SimState& s, double tolerance, int max_steps,
                 Variant variant) {
  if (!scene.schedule.empty() || scene.params.interpolation != Interpolation::kNone ||
      scene.params.damping_auto) {
    throw std::invalid_argument(scene.file +
                                ": the linearisation study needs targets that hold still "
                                "(no schedule, interpolation none, no damping auto)");
  }
  // the solve mode's step-length rule, around the engine's energy guard (posing_session.h)
  const StepLength length{scene.params.dt, kSolveMaxDt, kSolveDtGrowth};
  double h = scene.params.dt, previous_ke = kinetic_energy(scene.rig, s);
  SolveCount out;
  const Scene linearised = linearised_scene(scene, variant);
  const BareContext context{variant, &linearised, &out.substeps};
  while (out.steps < max_steps) {
    const int substeps = advance_implicit(scene, s, h, variant_step, &context);
    s.step += 1;
    s.time += h;
    ++out.steps;
    out.residual = max_control_residual(scene, s);
    if (!state_finite(s)) {
      out.diverged = true;
      break;
    }
    if (out.residual < tolerance) {
      out.converged = true;
      break;
    }
    const double ke = kinetic_energy(scene.rig, s);
    h = length.next(h, substeps > 1, ke, previous_ke);
    previous_ke = ke;
  }
  return out;
}

}  // namespace physik::experiments::linearisation
