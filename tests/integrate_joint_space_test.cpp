// The exact step (scheme exact, physik/engine/integrate_joint_space.h): one free rod follows
// the paper's own update; internal torques change neither total momentum in the dynamics (the
// discrete Euler run drifts at first order in dt); on a
// 1000-bone chain pulled at its tail the force reaches bone 0 (Gauss-Seidel with eps 1e-3 stops
// before it does); MuJoCo's quaternion step turns by the local angular velocity.
#include "physik/engine/integrate_joint_space.h"

#include <random>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/integrate.h"
#include "physik/io/scene_io.h"
#include "physik/model/rig_generators.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

TEST(JointSpace, QuatIntegrateTurnsByTheLocalAngularVelocity) {
  const Quat q(Eigen::AngleAxisd(0.7, Vec3(1, 2, -1).normalized()));
  const Vec3 w_local(0.3, -1.1, 2.0);
  Quat a = q;
  quat_integrate(a, w_local, 0.05);
  // R exp(h u) = exp(h R u) R: the same turn as the world angular velocity R u (integrate.h)
  const Quat b = rotate_by(q, q * w_local, 0.05);
  EXPECT_LT(test::angle_between(a, b), 1e-15);
  EXPECT_NEAR(a.norm(), 1.0, 1e-15);
  Quat c = q;
  quat_integrate(c, Vec3::Zero(), 0.05);  // no turn
  EXPECT_LT(test::angle_between(c, q), 1e-16);
}

TEST(JointSpace, OneFreeRodFollowsThePapersUpdate) {
  // a single body has no joint: w <- f w + dt alpha (integrate.h) is exactly MuJoCo's Euler step
  // with the factor torque, so both solves give one trajectory
  Scene s = test::scene_for(test::one_rod(1.5, 1.2, 0.4), preset_params("original"), 200);
  s.control_points.push_back(test::control(0, 0.8, Vec3(1.3, 0.7, 1.9), 10.0));
  SimState gs, ex;
  init_state(s, gs);
  Scene se = s;
  se.params.scheme = Scheme::kExact;
  init_state(se, ex);
  double worst = 0.0;
  for (int k = 0; k < s.steps; ++k) {
    step(s, gs);
    step(se, ex);
    worst = std::max({worst, (gs.frames.head_world[0] - ex.frames.head_world[0]).norm(),
                      (gs.frames.tail_world[0] - ex.frames.tail_world[0]).norm(),
                      (gs.omega_world[0] - ex.omega_world[0]).norm()});
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT((ex.frames.tail_world[0] - Vec3(0, 0, 1.5)).norm(), 0.5);  // it moved
}

// a 7-bone binary tree whose every joint is limited to +-0.2 rad per axis and starts up to 1 rad
// outside: the torsion springs (internal torque pairs) throw it about; no control points, no
// damping, f = 1, a drift velocity
Scene internal_torque_scene(double dt) {
  Rig rig = make_tree_rig(7, 2, 1.0, 0.3);
  for (int i = 1; i < rig.nbone; ++i) {
    for (int a = 0; a < 3; ++a) rig.bone_limit[i][a] = AxisLimit{true, -0.2, 0.2};
  }
  Scene scene = test::scene_for(rig, test::bare_params(dt), 100);
  scene.params.scheme = Scheme::kExact;
  scene.params.torsion_k = 10.0;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 1; i < rig.nbone; ++i) {
    scene.initial_pose.bone_local_rotation[i] =
        Quat(Eigen::AngleAxisd(u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
  }
  scene.initial_velocity_world = Vec3(0.3, -0.2, 0.1);
  return scene;
}

// total linear momentum, and angular momentum about the world origin
void momentum(const Rig& rig, const SimState& s, Vec3& P, Vec3& L) {
  P.setZero();
  L.setZero();
  for (int i = 0; i < rig.nbone; ++i) {
    const Mat3 R = s.frames.orient_world[i].toRotationMatrix();
    const Mat3 I = R * rig.bone_inertia_local[i].asDiagonal() * R.transpose();
    P += rig.bone_mass[i] * s.vel_world[i];
    L += I * s.omega_world[i] + s.com_world[i].cross(rig.bone_mass[i] * s.vel_world[i]);
  }
}

TEST(JointSpace, InternalTorquesLeaveTheMomentumRatesZero) {
  // the accelerations of every step of a long run: dP/dt = sum m a = 0 and
  // dL/dt = sum I alpha + w x I w + c x m a = 0, to round-off (the implied joint forces are
  // internal), while the torsion springs drive a large motion
  const Scene scene = internal_torque_scene(0.01);
  SimState s;
  init_state(scene, s);
  double worst_dP = 0.0, worst_dL = 0.0, scale = 0.0, arm = 0.0, max_omega = 0.0;
  std::vector<Vec3> com_before(scene.rig.nbone);
  for (int k = 0; k < 600; ++k) {
    com_before = s.com_world;  // the step's accelerations belong to the positions it starts at
    step(scene, s);
    Vec3 dP = Vec3::Zero(), dL = Vec3::Zero();
    for (int i = 0; i < scene.rig.nbone; ++i) {
      // joint_force = m a - F_ext and joint_torque = I alpha + w x I w - tau_ext (about the
      // centre), the external ones being internal pairs (torsion springs) that sum to zero
      const Vec3 m_a = s.joint_force_world[i] + s.force_world[i];
      dP += m_a;
      dL += s.joint_torque_world[i] + s.torque_world[i] + com_before[i].cross(m_a);
      scale = std::max(scale, s.joint_force_world[i].norm());
      arm = std::max(arm, com_before[i].norm());
      max_omega = std::max(max_omega, s.omega_world[i].norm());
    }
    worst_dP = std::max(worst_dP, dP.norm());
    worst_dL = std::max(worst_dL, dL.norm());
  }
  std::cout << "[momentum rates] worst |dP/dt| " << worst_dP << ", |dL/dt| " << worst_dL
            << " (joint forces up to " << scale << " N)\n";
  EXPECT_GT(scale, 1.0);      // the joints carry real forces
  EXPECT_GT(max_omega, 1.0);  // and the rig really moves
  EXPECT_LT(worst_dP, 1e-12 * scale);
  EXPECT_LT(worst_dL, 1e-12 * scale * (1.0 + arm));
}

TEST(JointSpace, MomentumDriftOfTheDiscreteRunIsFirstOrderInDt) {
  // the dynamics keep the momentum exactly (above), but MuJoCo's Euler step in joint space does
  // not: P = J_P(q) qdot changes by about -h Jdot_P qdot per step, so over 3 s the total momentum
  // drifts by O(dt). Measured at dt and dt/2: the drift halves (the integrator's, not the
  // solve's; the MuJoCo same-forces run drifts the same, exact_vs_mujoco_test.cpp)
  double drift_P[2] = {0.0, 0.0}, drift_L[2] = {0.0, 0.0};
  for (int r = 0; r < 2; ++r) {
    const Scene scene = internal_torque_scene(r == 0 ? 0.01 : 0.005);
    SimState s;
    init_state(scene, s);
    Vec3 P0, L0, P, L;
    momentum(scene.rig, s, P0, L0);
    const int steps = r == 0 ? 300 : 600;  // the same 3 s
    for (int k = 0; k < steps; ++k) {
      step(scene, s);
      momentum(scene.rig, s, P, L);
      drift_P[r] = std::max(drift_P[r], (P - P0).norm() / P0.norm());
      drift_L[r] = std::max(drift_L[r], (L - L0).norm() / L0.norm());
    }
  }
  std::cout << "[momentum drift over 3 s, relative] P: dt 0.01 " << drift_P[0] << ", dt 0.005 "
            << drift_P[1] << "; L: dt 0.01 " << drift_L[0] << ", dt 0.005 " << drift_L[1] << "\n";
  for (const double* d : {drift_P, drift_L}) {
    EXPECT_GT(d[0], 1e-6);  // a real drift, not round-off
    EXPECT_GT(d[0] / d[1], 1.6);
    EXPECT_LT(d[0] / d[1], 2.5);
  }
}

TEST(JointSpace, LongChainPulledAtItsTailMovesBoneZero) {
  // 1000 bones along +Z, the tail pulled sideways by a capped spring: the exact solve carries the
  // pull through the whole chain in the first step; Gauss-Seidel with the paper's eps 1e-3 stops
  // before the forces have travelled and leaves bone 0 where it was
  const int n = 1000;
  Scene s = test::scene_for(make_chain_rig(n), preset_params("original"), 5);
  s.control_points.push_back(
      test::control(n - 1, 1.0, Vec3(10.0, 0.0, n), 10.0, SpringLaw::kCapped));
  s.params.interpolation = Interpolation::kNone;
  double moved[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    Scene sk = s;
    sk.params.scheme = k == 0 ? Scheme::kExact : Scheme::kGaussSeidel;
    SimState st;
    init_state(sk, st);
    for (int j = 0; j < sk.steps; ++j) step(sk, st);
    moved[k] = (st.frames.head_world[0] - Vec3::Zero()).norm();
  }
  std::cout << "[1000-bone chain, 5 steps] bone 0 moved: exact " << moved[0] << ", Gauss-Seidel "
            << moved[1] << "\n";
  // the whole chain (1000 kg) under ~10 N for 0.25 s moves by ~3e-4; the tail end swings more
  EXPECT_GT(moved[0], 1e-5);
  EXPECT_LT(moved[1], 1e-3 * moved[0]);
}

}  // namespace
}  // namespace physik
