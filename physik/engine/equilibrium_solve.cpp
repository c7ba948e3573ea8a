// The equilibrium solve: see equilibrium_solve.h (its equations and sources).
#include "physik/engine/equilibrium_solve.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "physik/engine/damping.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/potential.h"
#include "physik/engine/subnormals.h"

namespace physik {

double rig_inertia_scale(const Rig& rig) {
  const BoneFrames rest = forward_kinematics(rig, rest_pose(rig));
  double inertia = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    inertia += rig.bone_mass[i] * (bone_centre_world(rest, i) - rest.head_world[0]).squaredNorm();
  }
  return inertia;
}

void size_equilibrium(const Scene& scene, std::size_t anchor_capacity, EquilibriumWorkspace& ws) {
  size_joint_snapshot(scene.rig.nbone, anchor_capacity, ws.before);
  ws.progress.restart(scene, 0, 1, 0.0);
  ws.inertia_scale = rig_inertia_scale(scene.rig);
}

void pull_at_goals(const Scene& scene, SimState& s) {
  for (const TargetChange& t : scene.schedule) {
    if (t.step >= s.step) s.target_goal_world[t.control_point] = t.target_world;
  }
  for (std::size_t c = 0; c < s.target_goal_world.size(); ++c) {
    s.target_effective_world[c] = s.target_goal_world[c];
    s.interp_steps_left[c] = 0;
  }
}

StepModel step_model(const Scene& scene, const SimState& s, double h, double armature) {
  const Rig& rig = scene.rig;
  const ArticulatedBodyData& d = s.joint_space.articulated;
  const double c = step_damping(scene.params, s);
  const double rot = (1.0 - scene.params.angular_velocity_factor) / scene.params.dt;
  double work = 0.0, inertia = 0.0, damper = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    const Vec3 alpha = d.accel_spatial[i].head<3>(), lin = d.accel_spatial[i].tail<3>();
    const Vec3& o = d.point_world[i];
    const Vec3 a_com = lin + alpha.cross(s.com_world[i] - o);
    const Vec3 i_alpha = d.inertia_com_world[i] * alpha;
    work += s.force_world[i].dot(a_com) + s.torque_world[i].dot(alpha);
    inertia += rig.bone_mass[i] * a_com.squaredNorm() + alpha.dot(i_alpha);
    damper += rot * alpha.dot(i_alpha);
    if (c != 0.0) {
      damper += c * ((lin + alpha.cross(s.frames.head_world[i] - o)).squaredNorm() +
                     (lin + alpha.cross(s.frames.tail_world[i] - o)).squaredNorm());
    }
    if (armature != 0.0 && rig.bone_joint_type[i] == JointType::kBall) {
      const int p = rig.bone_joint_parent[i];
      const Vec3 rel = p < 0 ? alpha : Vec3(alpha - d.accel_spatial[p].head<3>());
      inertia += armature * rel.squaredNorm();
    }
  }
  StepModel m;
  m.slope = h * h * work;
  m.metric = h * h * (inertia + h * damper);
  return m;
}

double predicted_decrease(const Scene& scene, const SimState& s, double h, double armature) {
  return step_model(scene, s, h, armature).decrease(1.0);
}

namespace {

// v = 0 everywhere: the joint-space velocities and the world view's
void come_to_rest(SimState& s) {
  JointSpaceState& js = s.joint_space;
  js.root_vel_world.setZero();
  for (auto& u : js.joint_vel_local) u.setZero();
  for (Vec3& v : s.vel_world) v.setZero();
  for (Vec3& w : s.omega_world) w.setZero();
}

// the largest joint turn of the trial just integrated, rad: h |v+| of every joint's rotation
// (the root's w among them)
double largest_turn(const SimState& s, double h) {
  double w = 0.0;
  for (const auto& u : s.joint_space.joint_vel_local) w = std::max(w, u.squaredNorm());
  return h * std::sqrt(w);
}

// the round-off of U, J: below it a predicted decrease is no decrease (as the implicit step's
// E_round, implicit_advance.h: kRoundoffGrowth eps (|U| + M |g| R))
double roundoff(const Scene& scene, const SimState& s, double u) {
  double coordinate = 0.0;
  for (int i = 0; i < scene.rig.nbone; ++i) {
    coordinate = std::max(coordinate, s.frames.tail_world[i].cwiseAbs().maxCoeff());
  }
  const double r = coordinate + scene.rig.reference_length();
  return kRoundoffGrowth * std::numeric_limits<double>::epsilon() *
         (std::abs(u) + scene.rig.total_mass() * scene.gravity_world.norm() * r);
}

// The pose q (+) alpha dq at rest, from the pose in ws.before and the recursion's accelerations
// a (dq = h^2 a): the joint-space update of length h sqrt(alpha) from rest moves by alpha h^2 a.
// Returns the largest joint turn, rad.
double move_along(const Scene& scene, SimState& s, const EquilibriumWorkspace& ws, double h,
                  double alpha, bool from_before) {
  if (from_before) restore_joint_state(scene.rig, ws.before, s);
  const double hs = h * std::sqrt(alpha);
  integrate_joint_space(scene.rig, hs, s);
  const double turn = largest_turn(s, hs);
  come_to_rest(s);
  return turn;
}

struct Trial {
  bool accepted = false;
  double rho = 0.0;    // the accepted step's gain ratio
  double alpha = 1.0;  // the share of the step taken
  double u = 0.0;      // J, U after it
  int backtracks = 0;
  bool stationary = false;
};

// One iteration's recursion of length h from the pose at rest with its forces applied (saved in
// ws.before), then the line search along its step: the whole step, or the share of it that turns
// no joint more than kMaxTurn, halved while U falls by less than kAcceptRatio of the model's
// predicted fall (at most kMaxBacktracks times). Refused: the state restored.
Trial iterate(const Scene& scene, SimState& s, EquilibriumWorkspace& ws, double h, double u) {
  Trial t;
  solve_implicit(scene, s, h, PoseTermSelection{}, ws.armature);
  const StepModel model = step_model(scene, s, h, ws.armature);
  if (!(model.decrease(1.0) > roundoff(scene, s, u))) {
    t.stationary = true;  // no decrease left to take
    return t;
  }
  double turn = move_along(scene, s, ws, h, 1.0, false);
  if (turn > kMaxTurn) t.alpha = kMaxTurn / turn;  // the turn is linear in alpha
  for (;;) {
    if (t.alpha < 1.0) move_along(scene, s, ws, h, t.alpha, true);
    t.u = potential_energy(scene, s);
    t.rho = (u - t.u) / model.decrease(t.alpha);
    if (t.rho >= kAcceptRatio) {
      t.accepted = true;
      return t;
    }
    if (t.backtracks == kMaxBacktracks) break;
    ++t.backtracks;
    t.alpha *= 0.5;
  }
  restore_joint_state(scene.rig, ws.before, s);
  return t;
}

// the trust region's next h after an accepted step of gain ratio rho taken to the share alpha
double next_step(const EquilibriumRule& rule, double h, const Trial& t) {
  if (t.backtracks > 0) return h * std::pow(0.5, 0.5 * t.backtracks);  // dq ~ h^2
  if (t.rho < 0.25) return 0.5 * h;
  if (t.rho > 0.75) return std::min(kGrowth * h, rule.max_step);
  return h;
}

void observe(const Scene& scene, const SimState& s, double u, const StepObserver& observer) {
  if (!observer) return;
  StepStats st;
  st.passes = 1;
  st.substeps = 1;
  st.energy_measured = true;
  st.potential_energy = u;
  st.max_residual = max_goal_residual(scene, s);
  observer(s, st);
}

}  // namespace

EquilibriumResult equilibrium_solve(const Scene& scene, SimState& s, EquilibriumWorkspace& ws,
                                    const EquilibriumRule& rule, const StepObserver& observer) {
  const FlushSubnormals flushed(scene.params.flush_subnormals);  // as every step (subnormals.h)
  EquilibriumResult out;
  ws.armature = rule.armature * ws.inertia_scale;
  pull_at_goals(scene, s);
  come_to_rest(s);
  double u = potential_energy(scene, s), h = rule.initial_step;
  int accepted = 0, u_progress = 0;  // the last accepted iteration that lowered U by the fraction
  double u_mark = u;
  ws.progress.restart(scene, 0, rule.stall_iterations, rule.stall_fraction);
  out.converged = goals_met(scene, s, rule.tolerance);
  ws.progress.observe(scene, s, rule.tolerance, 0);
  while (!out.converged && out.iterations < rule.max_iterations) {
    apply_forces(scene, s);  // the forces and tangents of the pose
    save_joint_state(s, ws.before);
    const Trial t = iterate(scene, s, ws, h, u);
    ++out.iterations;
    out.backtracks += t.backtracks;
    if (t.stationary) {
      out.stationary = true;
      break;
    }
    if (!t.accepted) {  // refused: a shorter step from the same pose
      ++out.refused;
      h *= 0.25;
      if (h < rule.min_step) {
        out.stalled = true;
        break;
      }
      continue;
    }
    u = t.u;
    h = next_step(rule, h, t);
    ++accepted;
    observe(scene, s, u, observer);
    out.converged = goals_met(scene, s, rule.tolerance);
    if (u < (1.0 - rule.stall_fraction) * u_mark) {
      u_mark = u;
      u_progress = accepted;
    }
    const bool goals_stalled = ws.progress.observe(scene, s, rule.tolerance, accepted);
    if (!out.converged && goals_stalled && accepted - u_progress >= rule.stall_iterations) {
      out.stalled = true;
      break;
    }
  }
  out.out_of_iterations = !out.converged && !out.stalled && !out.stationary;
  out.potential = u;
  out.step = h;
  return out;
}

}  // namespace physik
