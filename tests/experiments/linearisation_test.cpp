// The linearisation study's instruments (experiments/linearisation.h):
//  - its rule and guard around the shipped step are PosingSession::solve's: the same steps and
//    the same final pose;
//  - its finite-difference A_v at rest is the closed form -M^-1 (c D1 + Dr) (the end dampers and
//    the angular-velocity factor's damper; the velocity products' derivatives vanish at rest),
//    with M, D1 and Dr assembled independently (tests/dense_dynamics.h);
//  - on a moving state, its velocity products' derivative M^-1 dC/dv is an independent dense
//    Newton-Euler recursion's (tests/dense_dynamics.h);
//  - shipped_dcdv's unit-force responses are M^-1 and (M + h D)^-1 (dampers only), and from
//    rest its step is the shipped step;
//  - the applied wrench's generalised force is the dense Jacobians' J^T F, and the shipped step
//    rebuilt densely from the pieces (shipped_dense) is the shipped step;
//  - the dense Newton step solves a target as the shipped one does (to the tolerance);
//  - the shipped step and shipped_dcdv have no dense derivatives: asking is an error.
#include "experiments/linearisation.h"

#include <random>

#include <gtest/gtest.h>

#include "experiments/common.h"
#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/interpolation.h"
#include "physik/ik/ik_solver.h"
#include "physik/model/params.h"
#include "physik/model/rig_generators.h"
#include "physik/posing/posing_session.h"
#include "tests/dense_dynamics.h"

namespace physik::experiments::linearisation {
namespace {

// ik_comparison's chain scene (experiments/common.h): the tip pulled to `target`, the root's
// head pinned, the solve mode's engine, the target jumping
Scene chain_scene(int n, const Vec3& target) {
  Scene sc = effector_scene("linearisation_test", make_chain_rig(n), n - 1, true);
  sc.params.interpolation = Interpolation::kNone;
  sc.control_points[0].target_world = target;
  return sc;
}

// a state at rest in a random pose (every ball and the root's orientation turned)
SimState random_pose_at_rest(const Scene& sc, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  SimState s;
  init_state(sc, s);
  for (int i = 1; i < sc.rig.nbone; ++i) s.pose.bone_local_rotation[i] = quat_from_rotation_vector(Vec3(u(rng), u(rng), u(rng)));
  s.root_orient_world = quat_from_rotation_vector(Vec3(u(rng), u(rng), u(rng)));
  world_from_joint_space(sc.rig, s);
  return s;
}

// the dampers' D = c D1 + Dr (the end dampers and the angular-velocity factor's (1 - f) / dt I),
// assembled from tests/dense_dynamics.h's Jacobians
Eigen::MatrixXd dampers(const Scene& sc, const SimState& s) {
  const Rig& rig = sc.rig;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(dense::nv(rig), dense::nv(rig)), Jw, Jv;
  for (int b = 0; b < rig.nbone; ++b) {
    for (const Vec3& p : {s.frames.head_world[b], s.frames.tail_world[b]}) {
      const Eigen::MatrixXd Jp = dense::point_jacobian(rig, s, b, p);
      D += sc.params.damping * Jp.transpose() * Jp;
    }
    dense::jacobians(rig, s, b, Jw, Jv);
    D += (1.0 - sc.params.angular_velocity_factor) / sc.params.dt * Jw.transpose() * dense::inertia(rig, s, b) * Jw;
  }
  return D;
}

TEST(Linearisation, TheStudysRuleAroundTheShippedStepIsPosingSessionSolve) {
  for (const Vec3& target : {Vec3(2.0, 1.0, 4.0), Vec3(-3.0, 2.5, 1.0)}) {
    SCOPED_TRACE(target.transpose());
    const Scene sc = chain_scene(10, target);
    const double tol = 1e-4 * chain_reach(sc.rig, {{9, 1.0, Vec3::Zero()}});
    SimState s;
    init_state(sc, s);
    const SolveCount study = solve(sc, s, tol, 2000, Variant::kShipped);

    PosingSession session(sc);
    SolveRule rule = solve_mode_rule();
    rule.tolerance = tol;
    rule.max_steps = 2000;
    const SolveResult r = session.solve(rule);
    ASSERT_TRUE(r.converged);
    ASSERT_TRUE(study.converged);
    EXPECT_GT(study.steps, 5);  // a real solve, not a first-step hit
    EXPECT_EQ(study.steps, r.steps);
    EXPECT_GE(study.substeps, study.steps);
    for (int i = 0; i < sc.rig.nbone; ++i) {
      EXPECT_LT((s.frames.tail_world[i] - session.frames().tail_world[i]).norm(), 1e-12) << i;
    }
  }
}

TEST(Linearisation, AtRestTheRateDerivativeIsTheDampersClosedForm) {
  Scene sc = chain_scene(4, Vec3(1.0, 1.0, 2.0));
  sc.params.damping = 2.5;
  sc.params.angular_velocity_factor = 0.6;
  const SimState s = random_pose_at_rest(sc, 7);
  Eigen::MatrixXd A_q, A_v;
  derivatives(sc, s, Variant::kNewtonAtRest, A_q, A_v);
  const Eigen::MatrixXd expected = -dense::mass_matrix(sc.rig, s).ldlt().solve(dampers(sc, s));
  EXPECT_LT((A_v - expected).norm(), 1e-6 * expected.norm()) << (A_v - expected).norm() << " of " << expected.norm();
}

// on a moving state the velocity products' derivative, A_v(pose, 0) - A_v(pose, v) = M^-1 dC/dv,
// is an independent Newton-Euler recursion's (tests/dense_dynamics.h generalised_force: tau - C)
TEST(Linearisation, TheVelocityProductsDerivativeIsTheDenseRecursions) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Scene sc = chain_scene(4, Vec3(1.0, 1.0, 2.0));
  const Rig& rig = sc.rig;
  SimState s = random_pose_at_rest(sc, 11);  // then moving
  s.root_vel_world = 2.0 * Vec3(u(rng), u(rng), u(rng));
  for (Vec3& w : s.joint_vel_local) w = 2.0 * Vec3(u(rng), u(rng), u(rng));
  world_from_joint_space(rig, s);

  Eigen::MatrixXd A_q, A_v_rest, A_v;
  derivatives(sc, s, Variant::kNewtonAtRest, A_q, A_v_rest);
  derivatives(sc, s, Variant::kNewton, A_q, A_v);
  ASSERT_GT((A_v_rest - A_v).norm(), 1e-3);  // moving: the velocity products' share is there

  // dense -C(v): no applied wrench, no damper, the gyroscopic torque on (the scene's default)
  SimState d = s;
  for (Vec3& f : d.force_world) f.setZero();
  for (Vec3& t : d.torque_world) t.setZero();
  d.articulated.torque_per_omega = 0.0;
  d.articulated.cancel_gyroscopic = false;
  const Eigen::VectorXd v = joint_velocity(d);
  const auto minus_c = [&](const Eigen::VectorXd& q) {
    SimState t = d;
    t.root_vel_world = q.head<3>();
    for (int i = 0; i < rig.nbone; ++i) t.joint_vel_local[i] = q.segment<3>(3 + 3 * i);
    world_from_joint_space(rig, t);
    return dense::generalised_force(rig, t);
  };
  Eigen::MatrixXd Cv(v.size(), v.size());
  for (int k = 0; k < v.size(); ++k) {  // C is quadratic in v: central differences are exact
    Eigen::VectorXd e = Eigen::VectorXd::Zero(v.size());
    e[k] = 1e-3;
    Cv.col(k) = -(minus_c(v + e) - minus_c(v - e)) / 2e-3;
  }
  const Eigen::MatrixXd expected = dense::mass_matrix(rig, s).ldlt().solve(Cv);
  EXPECT_LT((A_v_rest - A_v - expected).norm(), 1e-6 * expected.norm())
      << (A_v_rest - A_v - expected).norm() << " of " << expected.norm();
}

// shipped_dcdv's pieces: the unit-force responses are M^-1 (the explicit solve) and, with only
// the dampers as elements (no spring, torsion k 0), (M + h D)^-1 (the implicit solve), with M and
// D assembled independently; from rest (dC/dv = 0) its step is the shipped step
TEST(Linearisation, TheUnitForceResponsesAreTheInverseOperators) {
  Scene sc = chain_scene(4, Vec3(1.0, 1.0, 2.0));
  sc.params.control_k = 0.0;
  sc.params.torsion_k = 0.0;
  sc.params.damping = 2.5;
  sc.params.angular_velocity_factor = 0.6;
  const SimState s = random_pose_at_rest(sc, 5);
  const Eigen::MatrixXd M = dense::mass_matrix(sc.rig, s), D = dampers(sc, s);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(M.rows(), M.cols());
  EXPECT_LT((unit_force_response(sc, s, false, 0.05) * M - I).norm(), 1e-9);
  for (double h : {0.05, 1.0, 10.0}) {
    SCOPED_TRACE(h);
    // the factor's damper is set by dt: h D_r = (h / dt) (1 - f) I over a step h
    EXPECT_LT((unit_force_response(sc, s, true, h) * (M + h * D) - I).norm(), 1e-9);
  }

  const Scene pulled = chain_scene(5, Vec3(1.5, -1.0, 3.0));
  SimState a, b;
  init_state(pulled, a);
  init_state(pulled, b);
  bare_step(pulled, a, 1.0, Variant::kShipped);
  bare_step(pulled, b, 1.0, Variant::kShippedDcdv);
  ASSERT_GT(joint_velocity(a).norm(), 1e-3);  // the step moved the chain
  EXPECT_LT((joint_velocity(a) - joint_velocity(b)).norm(), 1e-9 * joint_velocity(a).norm());
}

// the pose split's pieces: the applied wrench's generalised force is the dense Jacobians' J^T F,
// and the shipped step rebuilt densely from them (shipped_dense) is the shipped step
TEST(Linearisation, TheShippedStepRebuiltDenselyIsTheShippedStep) {
  const Scene sc = chain_scene(5, Vec3(1.5, -1.0, 3.0));
  const SimState rest = random_pose_at_rest(sc, 3);
  SimState forced = rest;
  apply_forces(sc, forced);
  EXPECT_LT((applied_generalised_force(sc, rest) - dense::generalised_force(sc.rig, forced)).norm(),
            1e-10 * dense::generalised_force(sc.rig, forced).norm());

  SimState moving = rest;  // a few shipped steps on: moving, pulled
  for (int k = 0; k < 3; ++k) bare_step(sc, moving, 0.05, Variant::kShipped);
  for (double h : {0.05, 1.0}) {
    SCOPED_TRACE(h);
    SimState a = moving, b = moving;
    bare_step(sc, a, h, Variant::kShipped);
    bare_step(sc, b, h, Variant::kShippedDense);
    const Eigen::VectorXd dv = joint_velocity(a) - joint_velocity(moving);
    ASSERT_GT(dv.norm(), 1e-3);
    EXPECT_LT((joint_velocity(a) - joint_velocity(b)).norm(), 1e-5 * dv.norm());
  }
}

TEST(Linearisation, TheDenseNewtonStepSolvesATargetAsTheShippedStepDoes) {
  const Scene sc = chain_scene(5, Vec3(1.5, -1.0, 3.0));
  const double tol = 1e-4 * chain_reach(sc.rig, {{4, 1.0, Vec3::Zero()}});
  SimState shipped, newton;
  init_state(sc, shipped);
  init_state(sc, newton);
  const SolveCount a = solve(sc, shipped, tol, 2000, Variant::kShipped);
  const SolveCount b = solve(sc, newton, tol, 2000, Variant::kNewton);
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged);
  EXPECT_FALSE(b.diverged);
  EXPECT_LT(b.residual, tol);
  // both meet the tip's target: the tips agree to twice the tolerance
  EXPECT_LT((shipped.frames.tail_world[4] - newton.frames.tail_world[4]).norm(), 2.0 * tol);
}

TEST(Linearisation, TheShippedStepsHaveNoDenseDerivatives) {
  const Scene sc = chain_scene(3, Vec3(1.0, 0.0, 2.0));
  SimState s;
  init_state(sc, s);
  Eigen::MatrixXd A_q, A_v;
  EXPECT_THROW(derivatives(sc, s, Variant::kShipped, A_q, A_v), std::invalid_argument);
  EXPECT_THROW(derivatives(sc, s, Variant::kShippedDcdv, A_q, A_v), std::invalid_argument);
}

}  // namespace
}  // namespace physik::experiments::linearisation
