// The PhysIK engine as a whole: analytic single-rod cases, damping stability, articulated
// joints, convergence on pinhead. Stage-level checks live in the per-stage test files.
#include "physik/engine/engine.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physik/engine/integrate.h"
#include "physik/io/scene_io.h"
#include "physik/io/summary_io.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// One rod pulled at its centre of mass (alpha = 0.5) by a linear spring: no torque, so the
// centre of mass follows the scalar semi-implicit Euler recurrence of a harmonic oscillator
//   v_{n+1} = v_n + (k/m)(t - x_n) dt,   x_{n+1} = x_n + v_{n+1} dt,
// integrated here by hand, at several dt.
TEST(Engine, OneRodOnASpringFollowsSemiImplicitEuler) {
  for (double dt : {0.01, 0.05, 0.1}) {
    const double m = 2.0, k = 7.0;
    Scene scene = test::scene_for(test::one_rod(1.0, m), test::bare_params(dt), 60);
    const Vec3 target(0.3, -0.4, 0.5 + 1.2);
    scene.control_points.push_back(test::control(0, 0.5, target, k));
    SimState s;
    init_state(scene, s);
    Vec3 x(0, 0, 0.5), v(0, 0, 0);
    for (int n = 0; n < 60; ++n) {
      step(scene, s);
      v += (k / m) * (target - x) * dt;
      x += v * dt;
      ASSERT_TRUE(test::near(s.com_world[0], x, 1e-12)) << "dt " << dt << " step " << n;
      ASSERT_TRUE(test::near(s.vel_world[0], v, 1e-12)) << "dt " << dt << " step " << n;
      ASSERT_LT(s.omega_world[0].norm(), 1e-14);
    }
  }
}

// Pulled at its tail, the rod also turns. Integrate the same scheme by hand with rotation
// matrices (not quaternions) and an explicit inertia tensor: a_cm = F/m, alpha = I^-1(tau - w x
// Iw), w <- f w + alpha dt, R <- exp(w dt) R, cm <- cm + v dt.
TEST(Engine, OneRodPulledAtItsTipMatchesAHandIntegratedRigidBody) {
  for (double dt : {0.01, 0.05}) {
    const double m = 1.5, k = 4.0, f = 0.7, L = 1.2, radius = 0.3;
    EngineParams p = test::bare_params(dt);
    p.angular_velocity_factor = f;
    Scene scene = test::scene_for(test::one_rod(L, m, radius), p, 80);
    const Vec3 target(0.8, 0.5, 0.4);
    scene.control_points.push_back(test::control(0, 1.0, target, k));
    SimState s;
    init_state(scene, s);

    Mat3 R = scene.rig.bone_rest_orient_world[0].toRotationMatrix();
    Vec3 cm(0, 0, L / 2), v = Vec3::Zero(), w = Vec3::Zero();
    const Mat3 I_local = scene.rig.bone_inertia_local[0].asDiagonal();
    for (int n = 0; n < 80; ++n) {
      step(scene, s);
      const Vec3 tip = cm + R * Vec3(0, L / 2, 0);
      const Vec3 F = k * (target - tip);
      const Vec3 tau = (tip - cm).cross(F);
      const Mat3 I = R * I_local * R.transpose();
      const Vec3 alpha = I.inverse() * (tau - w.cross(I * w));
      v += F / m * dt;
      cm += v * dt;
      w = f * w + alpha * dt;
      if (w.norm() > 0) R = Eigen::AngleAxisd(w.norm() * dt, w.normalized()).toRotationMatrix() * R;
      ASSERT_TRUE(test::near(s.com_world[0], cm, 1e-10)) << "dt " << dt << " step " << n;
      ASSERT_TRUE(test::near(s.omega_world[0], w, 1e-10)) << "dt " << dt << " step " << n;
      ASSERT_TRUE(test::near(s.frames.tail_world[0], cm + R * Vec3(0, L / 2, 0), 1e-10));
    }
  }
}

// Damping alone on a rod of mass m, length L, radius r (f = 1, no springs). Both ends feel
// -c v(end).
//  translation: m dv/dt = -2 c v, and the semi-implicit step gives v_{n+1} = (1 - 2 c dt/m) v_n;
//               |1 - 2 c dt/m| <= 1  <=>  c <= m/dt.
//  rotation about a transverse axis: the end forces -c (w x r_end), r_end = +-L/2, give a torque
//               -c L^2/2 w, so w_{n+1} = (1 - c L^2 dt/(2 I_perp)) w_n, stable iff
//               c <= 4 I_perp/(L^2 dt) = (m/dt)(r^2/L^2 + 1/3)   (I_perp = m(3r^2 + L^2)/12).
// The step is stable iff c <= c* = min of the two. For the original's r = 0.5 on a unit rod the
// rotational bound (0.58 m/dt) is the tighter one; here r = L makes translation the binding mode
// (round-off always seeds some rotation, so the other mode must be stable too).
// Below c* kinetic energy never grows; above it it grows every step: reported as diverged.
TEST(Engine, DampingStabilityBoundForARod) {
  const double m = 1.0, dt = 0.05, L = 1.0, r = 1.0;
  const double translation_bound = m / dt;
  const double rotation_bound = (m / dt) * (r * r / (L * L) + 1.0 / 3.0);
  const double bound = std::min(translation_bound, rotation_bound);
  ASSERT_DOUBLE_EQ(bound, 20.0);  // the paper's c = 20 sits exactly on it for this rod
  for (double ratio : {0.5, 0.9, 0.99}) {
    EngineParams p = test::bare_params(dt);
    p.damping = ratio * bound;
    Scene scene = test::scene_for(test::one_rod(L, m, r), p, 300);
    scene.initial_velocity_world = Vec3(1.0, -2.0, 0.5);
    SimState s;
    init_state(scene, s);
    double prev = kinetic_energy(scene.rig, s);
    for (int n = 0; n < 300; ++n) {
      const StepStats st = step(scene, s);
      ASSERT_LE(st.kinetic_energy, prev * (1 + 1e-12)) << "c/bound " << ratio << " step " << n;
      prev = st.kinetic_energy;
    }
    EXPECT_FALSE(run_scene(scene).diverged) << ratio;
  }
  for (double ratio : {1.1, 1.5}) {
    EngineParams p = test::bare_params(dt);
    p.damping = ratio * bound;
    Scene scene = test::scene_for(test::one_rod(L, m, r), p, 2000);
    scene.initial_velocity_world = Vec3(1.0, -2.0, 0.5);
    const RunSummary res = run_scene(scene);
    EXPECT_TRUE(res.diverged) << "c/bound " << ratio;
    EXPECT_LT(res.steps_run, 2000);
    EXPECT_FALSE(res.divergence_reason.empty());
  }
}

// The rotational mode alone, on the original's rod (r = 0.5, L = 1). With the per-step factor f,
//   w' = f w + alpha dt = (f - c L^2 dt / (2 I_perp)) w,  stable iff c <= (1 + f) 2 I_perp/(L^2 dt)
//      = ((1 + f)/2) (m/dt)(r^2/L^2 + 1/3):
// 11.67 N s/m for f = 1 and 8.75 for the original's f = 0.5, both below the translational m/dt =
// 20, so c just above them must blow up a spinning rod and c just below must not.
TEST(Engine, DampingRotationalBoundIsTheTighterOneForThinRods) {
  for (double f : {1.0, 0.5}) {
    const double m = 1.0, dt = 0.05, L = 1.0, r = 0.5;
    const double rotation_bound = 0.5 * (1.0 + f) * (m / dt) * (r * r / (L * L) + 1.0 / 3.0);
    for (double ratio : {0.95, 1.05}) {
      EngineParams p = test::bare_params(dt);
      p.angular_velocity_factor = f;
      p.damping = ratio * rotation_bound;  // below m/dt = 20 either way
      Scene scene = test::scene_for(test::one_rod(L, m, r), p, 200);
      SimState s;
      init_state(scene, s);
      s.omega_world[0] = Vec3(0.3, -0.2, 0.0);  // transverse spin (the rod lies along Z)
      double prev = kinetic_energy(scene.rig, s), first = prev;
      bool grew = false;
      for (int n = 0; n < 200; ++n) {
        const double e = step(scene, s).kinetic_energy;
        grew = grew || e > prev * (1 + 1e-12);
        prev = e;
      }
      if (ratio < 1.0) {
        EXPECT_FALSE(grew) << "f " << f;
        EXPECT_LT(prev, first) << "f " << f;
      } else {
        EXPECT_TRUE(grew) << "f " << f;
        EXPECT_GT(prev, first) << "f " << f;
      }
    }
  }
}

TEST(Engine, ArticulatedSchemeKeepsJointsTogetherToRoundOff) {
  Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  scene.steps = 200;
  double worst = 0.0;
  run_scene(scene, [&](const SimState&, const StepStats& st) {
    worst = std::max(worst, st.joint_separation);
  });
  EXPECT_LT(worst, 1e-12);
}

TEST(Engine, FreeRodsSchemeMeasuresJointSeparation) {
  Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  scene.params.free_rods = true;
  scene.steps = 50;
  const RunSummary r = run_scene(scene);
  // the rods integrate independently: the joints drift apart, and the drift is reported
  EXPECT_GT(r.max_joint_separation, 1e-6);
  EXPECT_TRUE(std::isfinite(r.max_joint_separation));
}

// Free rods are only held together by equal joint accelerations, so their joint points drift
// apart by the integrator's error: with the centripetal term and no velocity factor the joint
// velocities agree at every step and the positions separate by O(w^2 r dt^2) per step, i.e.
// O(dt) over a fixed time. Halving dt must halve the separation (first order).
TEST(Engine, FreeRodsSeparationIsFirstOrderInDt) {
  const Rig rig = load_rig(test::model_path("rigs/chain3.json"));
  std::vector<double> sep;
  for (double dt : {0.02, 0.01, 0.005}) {
    EngineParams p = test::bare_params(dt);
    p.free_rods = true;
    p.centripetal = true;
    Scene scene = test::scene_for(rig, p, static_cast<int>(std::lround(2.0 / dt)));
    scene.control_points.push_back(test::control(2, 1.0, Vec3(1.5, 0.5, 2.0), 5.0));
    sep.push_back(run_scene(scene).max_joint_separation);
  }
  EXPECT_GT(sep[0], 1e-3);
  EXPECT_NEAR(sep[0] / sep[1], 2.0, 0.2);
  EXPECT_NEAR(sep[1] / sep[2], 2.0, 0.2);
}

TEST(Engine, PinheadReachesTwoHandTargets) {
  const Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  const RunSummary r = run_scene(scene);
  ASSERT_FALSE(r.diverged) << r.divergence_reason;
  EXPECT_TRUE(r.converged);
  const double height = scene.rig.height();
  ASSERT_EQ(r.final_residuals.size(), 2u);
  for (double res : r.final_residuals) EXPECT_LT(res, 0.01 * height);
}

TEST(Engine, ThePapersDampingDivergesOnPinheadAndIsReported) {
  Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  scene.params.damping = 20.0;  // paper Sec. 4, with dt = 0.05
  const RunSummary r = run_scene(scene);
  EXPECT_TRUE(r.diverged);
}

TEST(Engine, RunsAreDeterministicAndTheHashSeesAnyChange) {
  Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  scene.steps = 60;
  const RunSummary a = run_scene(scene), b = run_scene(scene);
  EXPECT_EQ(state_hash(a.final_frames), state_hash(b.final_frames));
  scene.control_points[0].target_world.x() += 1e-12;  // a change far below any tolerance
  EXPECT_NE(state_hash(run_scene(scene).final_frames), state_hash(a.final_frames));
}

TEST(Engine, SummaryJsonHasTheDocumentedKeys) {
  const Scene scene = load_scene(test::model_path("scenes/pinhead_two_hands.json"));
  Scene short_scene = scene;
  short_scene.steps = 5;
  const nlohmann::json j = summary_to_json(short_scene, run_scene(short_scene));
  for (const char* key : {"converged", "diverged", "steps_run", "steps_to_converge",
                          "final_residuals", "max_joint_separation", "mean_passes_per_step"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["steps_run"], 5);
}

}  // namespace
}  // namespace physik
