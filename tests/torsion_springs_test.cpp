// Torsion springs: torque only outside the engaged band, pushing back into range, equal and
// opposite on the parent, capped when asked.
#include "physik/engine/torsion_springs.h"

#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/potential.h"
#include "physik/ik/ik_solver.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// the elbow: forearm x in [-90, 0] deg, y and z locked
Scene elbow_scene() {
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  return test::scene_for(rig, test::bare_params(), 400);
}

TEST(TorsionSprings, LocalTorqueFollowsTheBand) {
  EngineParams p = preset_params("original");  // k 10, tolerance 0.1
  std::array<AxisLimit, 3> lim{};
  lim[0] = {true, deg2rad(-90), 0.0};
  // engaged band: [-81, -9] deg; inside it, nothing
  EXPECT_EQ(torsion_torque_local(lim, Vec3(deg2rad(-45), 0, 0), p), Vec3::Zero());
  // past the upper engage point (-9 deg): pushed back down, linear in the excess
  const Vec3 t = torsion_torque_local(lim, Vec3(deg2rad(10), 0, 0), p);
  EXPECT_NEAR(t.x(), -10.0 * deg2rad(19), 1e-12);
  // below the lower one: pushed up
  EXPECT_NEAR(torsion_torque_local(lim, Vec3(deg2rad(-100), 0, 0), p).x(), 10.0 * deg2rad(19),
              1e-12);
  // capped: never more than k * cap
  p.torsion_spring = SpringLaw::kCapped;
  p.torsion_cap = 0.1;
  EXPECT_NEAR(torsion_torque_local(lim, Vec3(deg2rad(10), 0, 0), p).x(), -10.0 * 0.1, 1e-12);
  // a locked axis always pulls to its value; a free axis never
  std::array<AxisLimit, 3> locked{};
  locked[1] = {true, 0.0, 0.0};
  p.torsion_spring = SpringLaw::kLinear;
  EXPECT_NEAR(torsion_torque_local(locked, Vec3(0.3, 0.2, 0.1), p).y(), -10.0 * 0.2, 1e-12);
  EXPECT_EQ(torsion_torque_local(locked, Vec3(0.3, 0.2, 0.1), p).x(), 0.0);
}

TEST(TorsionSprings, EqualAndOppositeTorquesThatPushBackIntoRange) {
  Scene scene = elbow_scene();
  // bend the forearm 30 deg past its limit (-120 deg about x), and twist it a little about y
  scene.initial_pose.bone_local_rotation[1] =
      Quat(Eigen::AngleAxisd(deg2rad(-120), Vec3::UnitX())) *
      Quat(Eigen::AngleAxisd(deg2rad(5), Vec3::UnitY()));
  SimState s;
  init_state(scene, s);
  local_rotations_from_world(scene.rig, s.frames, s.pose);
  prepare_bodies(scene.rig, scene.params, s);
  apply_torsion_springs(scene.rig, scene.params, s);
  EXPECT_LT((s.torque_world[0] + s.torque_world[1]).norm(), 1e-14);
  EXPECT_GT(s.torque_world[1].norm(), 1.0);
  // the torque on the forearm, in its limit axes, opposes the violation about x
  const Quat limit_frame = s.frames.orient_world[0] * scene.rig.bone_rest_orient_parent[1];
  const Vec3 tau_local = limit_frame.conjugate() * s.torque_world[1];
  EXPECT_GT(tau_local.x(), 0.0);

  // left alone (no control points) with the original's damping, the joint returns inside its
  // range and comes to rest
  scene.params = preset_params("original");
  scene.steps = 1000;
  const RunSummary r = run_scene(scene);
  EXPECT_TRUE(r.converged);
  const Vec3 theta = rotation_vector(r.final_pose.bone_local_rotation[1]);
  EXPECT_GE(rad2deg(theta.x()), -90.0 - 0.5);
  EXPECT_LE(rad2deg(theta.x()), 0.5);
  EXPECT_NEAR(rad2deg(theta.y()), 0.0, 0.5);
}

// torsion_torque gradient is the potential's own torque: for a small turn e of the joint's
// rotation in the parent-rest frame (q -> exp(e) q), the work tau_pr . e equals -dU, by central
// differences of the potential (physik/engine/potential.h), on random rotations, for linear and
// capped springs. The paper's per-axis torque (axes) agrees near rest and where theta is along the
// excess, and fails on a bent 1-DOF joint (the test checks it can tell them apart).
TEST(TorsionSprings, GradientTorqueIsMinusTheDerivativeOfThePotential) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  EngineParams p = preset_params("original");
  p.torsion_torque = TorsionTorque::kGradient;
  // an elbow: x in [0, 160] deg, y and z locked
  const std::array<AxisLimit, 3> elbow = {AxisLimit{true, 0.0, deg2rad(160)},
                                          AxisLimit{true, 0.0, 0.0}, AxisLimit{true, 0.0, 0.0}};
  const double eps = 1e-6;
  double worst_gradient = 0.0, worst_axes = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    p.torsion_spring = trial % 2 ? SpringLaw::kCapped : SpringLaw::kLinear;
    p.torsion_cap = 0.2;
    // bent up to 2.6 rad about x, the locked axes off by up to 0.3 rad
    const Vec3 theta(2.6 * std::abs(u(rng)), 0.3 * u(rng), 0.3 * u(rng));
    const Quat q = quat_from_rotation_vector(theta);
    const Vec3 tau_axes = torsion_torque_local(elbow, theta, p);
    const Vec3 tau_grad = left_jacobian_inverse_transpose(theta) * tau_axes;
    const auto U = [&](const Quat& r) {
      const Vec3 e = torsion_excess(elbow, p.torsion_tolerance, r);
      double sum = 0.0;
      for (int a = 0; a < 3; ++a)
        sum += torsion_spring_potential(p.torsion_spring, p.torsion_k, p.torsion_cap, e[a]);
      return sum;
    };
    for (int a = 0; a < 3; ++a) {
      const Vec3 d = eps * Vec3::Unit(a);
      const double minus_dU =
          -(U(quat_from_rotation_vector(d) * q) - U(quat_from_rotation_vector(-d) * q)) / (2 * eps);
      worst_gradient = std::max(worst_gradient, std::abs(tau_grad[a] - minus_dU));
      worst_axes = std::max(worst_axes, std::abs(tau_axes[a] - minus_dU));
    }
  }
  std::cout << "torsion torque vs -dU/d(turn): gradient " << worst_gradient << " N m, axes "
            << worst_axes << " N m\n";
  EXPECT_LT(worst_gradient, 1e-5);
  EXPECT_GT(worst_axes, 0.1);  // the paper's torque is not the potential's at large bends
}

// On a joint locked on every axis (theta along the excess) the two torques are the same.
TEST(TorsionSprings, GradientAndAxesAgreeOnALockedJoint) {
  EngineParams p = preset_params("original");
  const std::array<AxisLimit, 3> locked = {AxisLimit{true, 0.0, 0.0}, AxisLimit{true, 0.0, 0.0},
                                           AxisLimit{true, 0.0, 0.0}};
  const Vec3 theta(0.7, -0.4, 1.1);
  const Vec3 tau = torsion_torque_local(locked, theta, p);
  EXPECT_LT((left_jacobian_inverse_transpose(theta) * tau - tau).norm(), 1e-12 * tau.norm());
}

// Explicit Euler on a torsion spring: with w' = f w + (tau/I) dt and theta' = theta + w' dt, a
// spring tau = -k theta on a body of transverse inertia I is stable iff a = k dt^2 / I < 2 (1 + f).
// A middle phalanx of the hand feels two such springs (its two joints) and its neighbours pull
// the other way in the chain's alternating mode, so a ~ 4 k dt^2 / I_min. The hand's shortest
// phalanx (L = 0.25, m = 0.25, r = 0.5) has I = m (3 r^2 + L^2)/12 = 0.0169 kg m^2; with k = 10
// and f = 0.5: dt = 0.05 gives a ~ 5.9 > 3 (unstable: a 1 deg nudge past the engage band must
// blow up), dt = 0.02 gives a ~ 0.95 < 3 (stable: it must settle).
TEST(TorsionSprings, TheTightHandIsExplicitEulersStabilityLimit) {
  const Rig rig = load_rig(test::model_path("rigs/hand.json"));
  const double I_min = [&] {
    double m = 1e300;
    for (int i = 0; i < rig.nbone; ++i) m = std::min(m, rig.bone_inertia_local[i].x());
    return m;
  }();
  EXPECT_NEAR(I_min, 0.25 * (3 * 0.25 + 0.0625) / 12, 1e-6 * I_min);  // file: 6 decimals
  for (double dt : {0.05, 0.02}) {
    EngineParams p = preset_params("original");
    p.dt = dt;
    const double a = 4 * p.torsion_k * dt * dt / I_min;
    const bool predicted_stable = a < 2 * (1 + p.angular_velocity_factor);
    Scene scene = test::scene_for(rig, p, static_cast<int>(std::lround(50.0 / 0.05 * 0.05 / dt)));
    scene.control_points.push_back(test::control(0, 0.0, Vec3(0, 0, 0), 30.0));
    scene.control_points.push_back(test::control(0, 1.0, Vec3(0, 0, 1), 30.0));
    // index knuckle x in [-10, 10] deg engages at 8 deg: nudge it to 9
    scene.initial_pose.bone_local_rotation[rig.find_bone("index.1")] =
        Quat(Eigen::AngleAxisd(deg2rad(9.0), Vec3::UnitX()));
    const RunSummary r = run_scene(scene);
    // the nudge stores k (1 deg)^2 / 2 = 1.5e-3 J; an explosion releases orders of magnitude more
    if (predicted_stable) {
      EXPECT_TRUE(r.converged) << "dt " << dt << " a " << a;
      EXPECT_LT(r.peak_kinetic_energy, 0.01) << "dt " << dt;
    } else {
      // the energy rule (run_monitor.h) stops it once it holds 4x what it was given; by then
      // its kinetic energy alone is well past the stored 1.5e-3 J
      EXPECT_TRUE(r.diverged) << "dt " << dt << " a " << a;
      EXPECT_GT(r.peak_kinetic_energy, 10 * 1.5e-3) << "dt " << dt << " a " << a;
      EXPECT_FALSE(r.converged) << "dt " << dt;
    }
  }
}

}  // namespace
}  // namespace physik
