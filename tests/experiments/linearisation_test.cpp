// The linearisation study's instruments (experiments/linearisation.h):
//  - its rule and guard around the shipped step are PosingSession::solve's: the same steps and
//    the same final pose;
//  - its finite-difference A_v at rest is the closed form -M^-1 (c D1 + Dr) (the end dampers and
//    the angular-velocity factor's damper; the velocity products' derivatives vanish at rest),
//    with M, D1 and Dr assembled independently (tests/dense_dynamics.h);
//  - on a moving state, its velocity products' derivative M^-1 dC/dv is an independent dense
//    Newton-Euler recursion's (tests/dense_dynamics.h);
//  - shipped_dcdv's unit-force responses are M^-1 and (M + h D)^-1 (dampers only);
//  - the applied wrench's generalised force is the dense Jacobians' J^T F on branching trees, and
//    the shipped step rebuilt densely from the pieces (shipped_dense) is the shipped step;
//  - A_q follows the Euler update's position map; shipped_dcdv solves (P + h C_v) a = r; the pose
//    split adds up with the dense mass matrix's own pose derivative;
//  - a scene whose targets move is an error;
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
  for (int i = 1; i < sc.rig.nbone; ++i)
    s.pose.bone_local_rotation[i] = quat_from_rotation_vector(Vec3(u(rng), u(rng), u(rng)));
  s.joint_space.root_orient_world = quat_from_rotation_vector(Vec3(u(rng), u(rng), u(rng)));
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
    D += (1.0 - sc.params.angular_velocity_factor) / sc.params.dt * Jw.transpose() *
         dense::inertia(rig, s, b) * Jw;
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
    SolveRule rule = steps_mode_rule();
    rule.tolerance = tol;
    rule.max_steps = 2000;
    const SolveResult r = session.solve(rule);
    ASSERT_TRUE(r.converged);
    ASSERT_TRUE(study.converged);
    EXPECT_GT(study.steps, 5);  // a real solve, not a first-step hit
    EXPECT_EQ(study.steps, r.steps);
    EXPECT_GT(study.substeps, study.steps);  // the guard split steps on these targets: compared too
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
  EXPECT_LT((A_v - expected).norm(), 1e-6 * expected.norm())
      << (A_v - expected).norm() << " of " << expected.norm();
}

// on a moving state the velocity products' derivative, A_v(pose, 0) - A_v(pose, v) = M^-1 dC/dv,
// is an independent Newton-Euler recursion's (tests/dense_dynamics.h generalised_force: tau - C)
TEST(Linearisation, TheVelocityProductsDerivativeIsTheDenseRecursions) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Scene sc = chain_scene(4, Vec3(1.0, 1.0, 2.0));
  const Rig& rig = sc.rig;
  SimState s = random_pose_at_rest(sc, 11);  // then moving
  s.joint_space.root_vel_world = 2.0 * Vec3(u(rng), u(rng), u(rng));
  for (Vec3& w : s.joint_space.joint_vel_local) w = 2.0 * Vec3(u(rng), u(rng), u(rng));
  world_from_joint_space(rig, s);

  Eigen::MatrixXd A_q, A_v_rest, A_v;
  derivatives(sc, s, Variant::kNewtonAtRest, A_q, A_v_rest);
  derivatives(sc, s, Variant::kNewton, A_q, A_v);
  ASSERT_GT((A_v_rest - A_v).norm(), 1e-3);  // moving: the velocity products' share is there

  // dense -C(v): no applied wrench, no damper, the gyroscopic torque on (the scene's default)
  SimState d = s;
  for (Vec3& f : d.force_world) f.setZero();
  for (Vec3& t : d.torque_world) t.setZero();
  d.joint_space.articulated.torque_per_omega = 0.0;
  d.joint_space.articulated.cancel_gyroscopic = false;
  const Eigen::VectorXd v = joint_velocity(rig, d);
  const auto minus_c = [&](const Eigen::VectorXd& q) {
    SimState t = d;
    t.joint_space.root_vel_world = q.head<3>();
    for (int i = 0; i < rig.nbone; ++i) t.joint_space.joint_vel_local[i] = q.segment<3>(3 + 3 * i);
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
// D assembled independently
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
}

// the applied wrench's generalised force is the dense Jacobians' J^T (F; T), on random branching
// trees pulled at a leaf's tail
TEST(Linearisation, TheAppliedGeneralisedForceIsTheDenseJacobiansTransposeTimesTheWrench) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 3; ++trial) {
    SCOPED_TRACE(trial);
    Scene sc;
    sc.file = "random tree";
    sc.rig = dense::random_rig(rng, 7);
    sc.params = preset_params(kDefaultPreset);
    use_solve_mode(sc.params);  // the joint-space state (init_state sizes it for the exact solves)
    sc.params.interpolation = Interpolation::kNone;
    ControlPoint cp;
    cp.bone = 6;
    cp.alpha = 1.0;
    cp.target_world = Vec3(3.0, -2.0, 1.0);
    sc.control_points = {cp};
    sc.initial_pose = rest_pose(sc.rig);
    const SimState rest = random_pose_at_rest(sc, 100 + trial);
    SimState forced = rest;
    apply_forces(sc, forced);
    const Eigen::VectorXd expected = dense::generalised_force(sc.rig, forced);
    ASSERT_GT(expected.norm(), 1.0);
    EXPECT_LT((applied_generalised_force(sc, rest) - expected).norm(), 1e-10 * expected.norm());
  }
}

// the shipped step rebuilt densely from the unit-force responses (shipped_dense) is the shipped
// step, on a moving, pulled chain
TEST(Linearisation, TheShippedStepRebuiltDenselyIsTheShippedStep) {
  const Scene sc = chain_scene(5, Vec3(1.5, -1.0, 3.0));
  SimState moving = random_pose_at_rest(sc, 3);  // a few shipped steps on: moving, pulled
  for (int k = 0; k < 3; ++k) bare_step(sc, moving, 0.05, Variant::kShipped);
  for (double h : {0.05, 1.0}) {
    SCOPED_TRACE(h);
    SimState a = moving, b = moving;
    bare_step(sc, a, h, Variant::kShipped);
    bare_step(sc, b, h, Variant::kShippedDense);
    const Eigen::VectorXd dv = joint_velocity(sc.rig, a) - joint_velocity(sc.rig, moving);
    ASSERT_GT(dv.norm(), 1e-3);
    EXPECT_LT((joint_velocity(sc.rig, a) - joint_velocity(sc.rig, b)).norm(), 1e-7 * dv.norm());
  }
}

// a moving, pulled chain: three shipped steps from a random pose
SimState moving_chain(const Scene& sc, unsigned seed) {
  SimState s = random_pose_at_rest(sc, seed);
  for (int k = 0; k < 3; ++k) bare_step(sc, s, 0.05, Variant::kShipped);
  return s;
}

// A_q follows the Euler update's position map: moving the joint state by h v (integrate_joint_space
// with no acceleration) changes the accelerations by h A_q v + O(h^2)
TEST(Linearisation, ThePoseDerivativeFollowsTheEulerUpdate) {
  const Scene sc = chain_scene(5, Vec3(1.5, -1.0, 3.0));
  const SimState s = moving_chain(sc, 9);
  Eigen::MatrixXd A_q, A_v;
  derivatives(sc, s, Variant::kNewton, A_q, A_v);
  const Eigen::VectorXd expected = A_q * joint_velocity(sc.rig, s);
  ASSERT_GT(expected.norm(), 1e-2);
  const double h = 1e-5;
  SimState t = s;
  t.joint_space.articulated.root_accel_world.setZero();
  for (Vec3& a : t.joint_space.articulated.joint_accel_local) a.setZero();
  integrate_joint_space(sc.rig, h, t);
  const Eigen::VectorXd moved = (accelerations(sc, t) - accelerations(sc, s)) / h;
  EXPECT_LT((moved - expected).norm(), 1e-3 * expected.norm())
      << (moved - expected).norm() << " of " << expected.norm();
}

// shipped_dcdv solves (P + h C_v) a = r: (L) with A_q = -M^-1 K (shipped_dense's) and the full
// A_v at the state (newton's), on a moving chain
TEST(Linearisation, TheShippedStepWithDcdvIsThatDenseSystem) {
  const Scene sc = chain_scene(5, Vec3(1.5, -1.0, 3.0));
  const SimState s = moving_chain(sc, 13);
  for (double h : {0.05, 1.0}) {
    SCOPED_TRACE(h);
    Eigen::MatrixXd A_q, A_v_rest, A_q_full, A_v;
    derivatives(sc, s, Variant::kShippedDense, A_q, A_v_rest, h);
    derivatives(sc, s, Variant::kNewton, A_q_full, A_v, h);
    ASSERT_GT((A_v - A_v_rest).norm(), 1e-3);  // moving: dC/dv is there
    const int n = static_cast<int>(A_q.rows());
    const Eigen::VectorXd v = joint_velocity(sc.rig, s);
    const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(n, n) - h * A_v - h * h * A_q;
    const Eigen::VectorXd expected =
        v + h * S.partialPivLu().solve(accelerations(sc, s) + h * (A_q * v));
    SimState t = s;
    bare_step(sc, t, h, Variant::kShippedDcdv);
    EXPECT_LT((joint_velocity(sc.rig, t) - expected).norm(), 1e-6 * (expected - v).norm());
  }
}

// the pose split: with the inertia's term -M^-1 (dM/dq) a from the dense mass matrix
// (tests/dense_dynamics.h) at poses moved along each dof, pose_forces + it = newton_at_rest's A_q,
// and pose_inertia - shipped_dense = it
TEST(Linearisation, ThePoseSplitAddsUpWithTheDenseInertiaTerm) {
  const Scene sc = chain_scene(4, Vec3(1.0, 1.0, 2.0));
  const SimState rest = random_pose_at_rest(sc, 17);
  const Rig& rig = sc.rig;
  const Eigen::VectorXd a = accelerations(sc, rest);
  const Eigen::MatrixXd M = dense::mass_matrix(rig, rest);
  const int n = static_cast<int>(M.rows());
  Eigen::MatrixXd inertia_term(n, n);
  const double eps = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::MatrixXd Mk[2];
    for (int side = 0; side < 2; ++side) {
      SimState t = rest;
      const double e = side == 0 ? eps : -eps;
      if (k < 3) {
        t.joint_space.root_com_world[k] += e;
      } else {
        const int bone = (k - 3) / 3;
        quat_integrate(
            bone == 0 ? t.joint_space.root_orient_world : t.pose.bone_local_rotation[bone],
            e * Vec3::Unit((k - 3) % 3), 1.0);
      }
      world_from_joint_space(rig, t);
      Mk[side] = dense::mass_matrix(rig, t);
    }
    inertia_term.col(k) = -M.ldlt().solve((Mk[0] - Mk[1]) / (2.0 * eps) * a);
  }
  ASSERT_GT(inertia_term.norm(), 1e-2);
  Eigen::MatrixXd rest_q, forces_q, inertia_q, shipped_q, A_v;
  derivatives(sc, rest, Variant::kNewtonAtRest, rest_q, A_v);
  derivatives(sc, rest, Variant::kPoseForces, forces_q, A_v);
  derivatives(sc, rest, Variant::kPoseInertia, inertia_q, A_v);
  derivatives(sc, rest, Variant::kShippedDense, shipped_q, A_v);
  EXPECT_LT((forces_q + inertia_term - rest_q).norm(), 1e-4 * rest_q.norm());
  EXPECT_LT((inertia_q - shipped_q - inertia_term).norm(), 1e-4 * inertia_term.norm());
}

TEST(Linearisation, TheStudyNeedsTargetsThatHoldStill) {
  Scene sc = chain_scene(3, Vec3(1.0, 0.0, 2.0));
  sc.params.interpolation = Interpolation::kLinear;
  SimState s;
  init_state(sc, s);
  EXPECT_THROW(solve(sc, s, 1e-4, 10, Variant::kShipped), std::invalid_argument);
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
