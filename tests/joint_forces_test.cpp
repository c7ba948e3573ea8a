// Inter-joint forces: after the solve they sum to zero at every joint, the joint-point
// accelerations agree within eps, and (being internal) they change neither total linear nor
// angular momentum.
#include "physik/engine/joint_forces.h"

#include <random>

#include <gtest/gtest.h>

#include "physik/engine/control_springs.h"
#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/integrate.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/torsion_springs.h"
#include "physik/io/scene_io.h"
#include "physik/model/rig_generators.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// pinhead in a random pose with random velocities and random control springs
Scene random_pinhead_scene(std::mt19937& rng, bool centripetal) {
  Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  scene.params.centripetal = centripetal;
  scene.params.max_passes = 100000;  // let the solve reach eps
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < scene.rig.nbone; ++i) {
    scene.initial_pose.bone_local_rotation[i] =
        Quat(Eigen::AngleAxisd(0.6 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
  }
  for (int c = 0; c < 4; ++c) {
    scene.control_points.push_back(test::control((c * 5) % scene.rig.nbone, 0.5 + 0.5 * u(rng),
                                                 Vec3(u(rng), u(rng), u(rng)) * 2.0, 30.0));
  }
  return scene;
}

void randomize_velocities(std::mt19937& rng, SimState& s) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < s.vel_world.size(); ++i) {
    s.vel_world[i] = Vec3(u(rng), u(rng), u(rng));
    s.omega_world[i] = 2.0 * Vec3(u(rng), u(rng), u(rng));
  }
}

// every stage up to the joint solve
JointSolveStats forces_and_solve(const Scene& scene, SimState& s) {
  local_rotations_from_world(scene.rig, s.frames, s.pose);
  apply_forces(scene, s);
  return solve_joint_forces(scene.rig, scene.params, s);
}

TEST(JointForces, SumToZeroAtEveryJointAndEqualiseAccelerations) {
  std::mt19937 rng(42);
  for (bool centripetal : {false, true}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Scene scene = random_pinhead_scene(rng, centripetal);
      SimState s;
      init_state(scene, s);
      randomize_velocities(rng, s);
      const double before = [&] {
        SimState t = s;
        local_rotations_from_world(scene.rig, t.frames, t.pose);
        prepare_bodies(scene.rig, scene.params, t);
        apply_control_springs(scene, t);
        prepare_joint_solve(scene.rig, t);
        return joint_accel_mismatch(scene.rig, scene.params, t);
      }();
      const JointSolveStats st = forces_and_solve(scene, s);
      EXPECT_GT(before, 100 * scene.params.joint_eps);  // the solve had real work to do
      EXPECT_LT(st.mismatch, scene.params.joint_eps) << "passes " << st.passes;
      EXPECT_LT(joint_accel_mismatch(scene.rig, scene.params, s), scene.params.joint_eps);
      // per joint: the forces on its bones sum to zero (Newton's third law)
      for (std::size_t j = 0; j < scene.rig.joints.size(); ++j) {
        Vec3 sum = Vec3::Zero();
        double scale = 0.0;
        const Rig& rig = scene.rig;
        for (int m = rig.joint_first_member[j]; m < rig.joint_first_member[j + 1]; ++m) {
          sum += s.gauss_seidel.member_force_world[m];
          scale = std::max(scale, s.gauss_seidel.member_force_world[m].norm());
        }
        EXPECT_LT(sum.norm(), 1e-12 * std::max(1.0, scale)) << "joint " << j;
      }
    }
  }
}

TEST(JointForces, LeaveTotalMomentumUnchanged) {
  std::mt19937 rng(7);
  const Scene scene = random_pinhead_scene(rng, true);
  SimState s;
  init_state(scene, s);
  randomize_velocities(rng, s);
  forces_and_solve(scene, s);
  // rate of change of momentum due to the joint forces alone:
  //   dP/dt = sum F_joint,   dL/dt (about the world origin) = sum (tau_joint + cm x F_joint)
  Vec3 dP = Vec3::Zero(), dL = Vec3::Zero();
  double scale = 0.0;
  for (int i = 0; i < scene.rig.nbone; ++i) {
    dP += s.joint_force_world[i];
    dL += s.joint_torque_world[i] + s.com_world[i].cross(s.joint_force_world[i]);
    scale = std::max(scale, s.joint_force_world[i].norm());
  }
  ASSERT_GT(scale, 1.0);
  EXPECT_LT(dP.norm(), 1e-11 * scale);
  EXPECT_LT(dL.norm(), 1e-11 * scale);

  // and over a free-rods step with no external forces at all, total linear momentum is kept
  // exactly (semi-implicit Euler adds dt * sum F = 0)
  Scene bare = scene;
  bare.control_points.clear();
  bare.params.damping = 0.0;
  bare.params.angular_velocity_factor = 1.0;
  bare.params.torsion_k = 0.0;
  bare.params.free_rods = true;
  SimState t;
  init_state(bare, t);
  randomize_velocities(rng, t);
  Vec3 p0 = Vec3::Zero(), p1 = Vec3::Zero();
  for (int i = 0; i < bare.rig.nbone; ++i) p0 += bare.rig.bone_mass[i] * t.vel_world[i];
  step(bare, t);
  for (int i = 0; i < bare.rig.nbone; ++i) p1 += bare.rig.bone_mass[i] * t.vel_world[i];
  EXPECT_LT((p1 - p0).norm(), 1e-12 * p0.norm() + 1e-12);
}

TEST(JointForces, PassCapAndToleranceAreReported) {
  std::mt19937 rng(3);
  Scene scene = random_pinhead_scene(rng, false);
  scene.params.max_passes = 2;
  SimState s;
  init_state(scene, s);
  randomize_velocities(rng, s);
  const JointSolveStats st = forces_and_solve(scene, s);
  EXPECT_EQ(st.passes, 2);
  EXPECT_GT(st.mismatch, scene.params.joint_eps);  // two passes are not enough on pinhead
  EXPECT_EQ(scene.params.passes_cap(18), 2);
  scene.params.max_passes = 0;
  EXPECT_EQ(scene.params.passes_cap(18), 5 * 18 * 18);  // the original's cap
}

// Two bones meeting at one joint, the child pulled at its tip: one Gauss-Seidel pass solves a
// single joint exactly (it is the closed form of eq. 6-11), so one pass leaves no mismatch.
TEST(JointForces, OneJointIsSolvedExactlyInOnePass) {
  Scene scene = test::scene_for(make_chain_rig(2), test::bare_params(), 1);
  scene.control_points.push_back(test::control(1, 1.0, Vec3(1.0, 0.5, 1.0), 10.0));
  scene.params.joint_eps = 1e-300;  // never stop on eps
  scene.params.max_passes = 1;
  SimState s;
  init_state(scene, s);
  const JointSolveStats st = forces_and_solve(scene, s);
  EXPECT_EQ(st.passes, 1);
  EXPECT_LT(st.mismatch, 1e-12);
}

}  // namespace
}  // namespace physik
