// The scaling experiment's measuring tools (experiments/scaling.h): what its error columns rest on.
//  - on a moving state, with the velocity terms both share (centripetal on, angular-velocity
//    factor 1), the Gauss-Seidel fixed point is the exact solution: a tight Gauss-Seidel solve's
//    joint forces equal the articulated-body algorithm's; the paper's eps leaves an error;
//  - the mj_step replay of a same-forces run follows the exact solve (the gap column) and
//    replaying the recorded forces reproduces the recorded run.
#include "experiments/scaling.h"

#include <cmath>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/joint_forces.h"
#include "reference/compare.h"

namespace physik::experiments {
namespace {

// the exact run's state after `steps` steps from rest: moving
SimState moving_state(const Scene& exact, int steps) {
  SimState s;
  init_state(exact, s);
  for (int k = 0; k < steps; ++k) step(exact, s);
  return s;
}

double relative_error(const std::vector<Vec3>& f, const std::vector<Vec3>& exact) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    num += (f[i] - exact[i]).squaredNorm();
    den += exact[i].squaredNorm();
  }
  return std::sqrt(num / den);
}

TEST(Scaling, OnAMovingStateTightGaussSeidelForcesEqualTheExactOnes) {
  for (const char* kind : {"chain", "tree2"}) {
    SCOPED_TRACE(kind);
    const int n = 40;
    const Scene exact = scaling_scene(kind, n, Scheme::kExact);
    const SimState s = moving_state(exact, 8);
    double fastest = 0.0;
    for (const Vec3& w : s.omega_world) fastest = std::max(fastest, w.norm());
    EXPECT_GT(fastest, 1e-2);  // velocity terms matter here
    const std::vector<Vec3> ref = joint_forces_at(exact, s);
    const std::vector<Vec3> tight =
        joint_forces_at(scaling_scene(kind, n, Scheme::kGaussSeidel, 1e-11), s);
    const std::vector<Vec3> paper =
        joint_forces_at(scaling_scene(kind, n, Scheme::kGaussSeidel, 1e-3), s);
    EXPECT_LT(relative_error(tight, ref), 1e-8);
    EXPECT_GT(relative_error(paper, ref), 10.0 * relative_error(tight, ref));
    // without the shared velocity terms the solves differ: the comparison needs them
    Scene no_centripetal = scaling_scene(kind, n, Scheme::kGaussSeidel, 1e-11);
    SimState t = s;
    apply_forces(no_centripetal, t);
    solve_joint_forces(no_centripetal.rig, no_centripetal.params, t);
    EXPECT_GT(relative_error(t.joint_force_world, ref), 1e-6);
  }
}

TEST(Scaling, MjStepReplayFollowsTheExactSolveAndRepeatsItself) {
  const Scene scene = scaling_scene("tree2", 25, Scheme::kExact);
  const int steps = 6;
  MjStepReplay r = record_mj_step_replay(scene, steps);
  ASSERT_EQ(r.xfrc.size(), static_cast<std::size_t>(steps));
  SimState s;
  init_state(scene, s);
  for (int k = 0; k < steps; ++k) step(scene, s);
  SimState rest;
  init_state(scene, rest);
  EXPECT_GT(pose_gap(s.frames, rest.frames), 1e-3);     // it moved
  EXPECT_LT(pose_gap(r.final_frames, s.frames), 1e-9);  // MuJoCo = exact, same forces
  // the replay runs the same mj_steps: its qpos after the last one equals the reference's
  EXPECT_GT(time_mj_step_replay(r), 0.0);
  const mjModel* m = r.model.get();
  mjData* again = mj_makeData(m);
  mj_copyData(again, m, r.start.get());
  for (const auto& f : r.xfrc) {
    std::copy(f.begin(), f.end(), again->xfrc_applied);
    mj_step(m, again);
  }
  for (int i = 0; i < m->nq; ++i) EXPECT_EQ(again->qpos[i], r.data->qpos[i]) << i;
  mj_deleteData(again);
}

}  // namespace
}  // namespace physik::experiments
