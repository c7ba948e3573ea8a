// The paper's scheme on a welded rig against MuJoCo (docs/engine.md "Welded bones and anchored
// roots"): MuJoCo's humanoid converted as `rig from-mjcf` converts it (its jointless bodies and a
// body's extra segments welded: one composite body each), and the same rig with its welds taken
// out (every bone a free ball), pulled by the README's three-point reach under preset original at
// dt 0.01, the paper's scheme against MuJoCo's same-forces run of the same rig.
//
// Measured (the 4000 steps): before the welded root body moved its centre of mass by F / m
// (integrate.h), the welded run never converged (residuals 0.10 at step 4000, 0.03 at 16,000) and
// ended 0.33 of the height from MuJoCo's pose; the unwelded run converged at step 2545, 0.085 away.
// Now the welded run converges at step 5993, 0.196 away: 2.35 times the unwelded run's steps,
// where the paper's factor damps the welded root body's turn by its composite inertia, 2.29 times
// the sum of its bones' own inertias that damp the unwelded rig's. With the factor in the joint
// solve (factor_in_joint_solve) both converge with MuJoCo (962 and 1028 steps against its 952 and
// 996) and end 0.0022 and 0.0015 of the height from it: what is left at the paper's setting is the
// factor's heuristic (every body's w halved after the joint forces), not the joint solve over
// composite bodies, and the final pose of a reach that fixes no unique pose follows the path.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

#include "experiments/outside_rigs.h"
#include "physik/engine/engine.h"
#include "physik/engine/newton_euler.h"
#include "physik/io/rig_io.h"
#include "physik/model/kinematics.h"
#include "reference/compare.h"
#include "reference/mjcf_import.h"
#include "reference/mujoco_runner.h"

namespace physik {
namespace {

const std::string kHumanoid =
    std::string(experiments::outside_rigs::kSamplesDir) + "/humanoid/humanoid.xml";

Rig without_welds(const Rig& rig) {
  nlohmann::json doc = rig_to_json(rig);
  for (nlohmann::json& bone : doc["bones"]) bone.erase("weld");
  return rig_from_json(doc, "humanoid without welds");
}

// the README's first scene, the paper's scheme at dt 0.01, stopping once converged
Scene reach(const Rig& rig, int steps, bool factor_in_solve) {
  Scene s;
  s.file = "<welded reach>";
  s.rig = rig;
  s.params = preset_params("original");
  s.params.dt = 0.01;
  s.params.factor_in_joint_solve = factor_in_solve;
  s.steps = steps;
  s.initial_pose = rest_pose(rig);
  s.convergence.stop_when_converged = true;
  const std::pair<const char*, Vec3> points[] = {{"right_hand", Vec3(0.3, -0.5, 1.9)},
                                                 {"left_foot", Vec3(0.16, 0.13, 0.24)},
                                                 {"right_foot", Vec3(0.16, -0.13, 0.24)}};
  for (const auto& [bone, target] : points) {
    ControlPoint cp;
    cp.bone = rig.find_bone(bone);
    cp.target_world = target;
    s.control_points.push_back(cp);
  }
  return s;
}

struct Outcome {
  RunSummary physik;
  RunSummary mujoco;
  double gap = 0.0;  // final pose gap over the rig's height
};

Outcome run_both(const Rig& rig, int steps, bool factor_in_solve) {
  const Scene s = reach(rig, steps, factor_in_solve);
  Outcome o;
  o.physik = run_scene(s);
  o.mujoco = run_mujoco(s, ReferenceMode::kSameForces);
  o.gap = pose_gap(o.physik.final_frames, o.mujoco.final_frames) / rig.reference_length();
  return o;
}

void print(const char* name, const Outcome& o) {
  std::cout << "[welded reach] " << name << ": physik converged " << o.physik.converged
            << " at step " << o.physik.steps_to_converge << " (MuJoCo " << o.mujoco.converged
            << " at " << o.mujoco.steps_to_converge << "), final pose gap " << o.gap
            << " of the height\n";
}

// The trace of a welded body's inertia about its centre over the sum of its bones' own inertias
// about theirs, at rest: how much more the paper's w <- f w damps the body's turn than it damps
// the same bones unwelded (docs/engine.md "Welded bones and anchored roots", its paragraph "What
// is left: the factor on a composite body").
double composite_over_own_inertia(const Rig& rig, int body) {
  const BoneFrames f = forward_kinematics(rig, rest_pose(rig));
  const auto centre = [&](int i) {
    return Vec3(f.head_world[i] + f.orient_world[i] * Vec3(0, rig.bone_length[i] / 2, 0));
  };
  double m = 0.0;
  Vec3 c = Vec3::Zero();
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_body[i] != body) continue;
    m += rig.bone_mass[i];
    c += rig.bone_mass[i] * centre(i);
  }
  c /= m;
  double own = 0.0, composite = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_body[i] != body) continue;
    const double t = inertia_world(rig, f.orient_world[i], i).trace();
    own += t;
    composite += t + 2.0 * rig.bone_mass[i] * (centre(i) - c).squaredNorm();  // parallel axes
  }
  return composite / own;
}

class WeldedReach : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kHumanoid)) {
      GTEST_SKIP() << kHumanoid << " missing (Debian's libmujoco-samples)";
    }
    welded_ = load_mjcf(kHumanoid).rig();
    ASSERT_TRUE(welded_.has_welds());
    unwelded_ = without_welds(welded_);
    ASSERT_FALSE(unwelded_.has_welds());
  }
  Rig welded_, unwelded_;
};

// The paper's setting. The unwelded rig converges in 2545 steps, the welded one in 5993 (it never
// did before its root body moved by F / m, not even in 16,000): both within 8000, not both within
// the 4000 (the inertia ratio below says why). The final pose of a reach that fixes no
// unique pose follows the path, and the factor's heuristic makes the paths differ from MuJoCo's by
// 0.085 (unwelded) and 0.196 (welded) of the height: the welded gap is held to 3 times the
// unwelded one's, the measured 2.3 with room for a path-dependent pose, below the old welded
// run's 3.9 (0.33, not converged).
TEST_F(WeldedReach, ThePapersSchemeConvergesOnTheWeldedHumanoidNearTheUnweldedGap) {
  const Outcome w = run_both(welded_, 8000, false), u = run_both(unwelded_, 8000, false);
  print("welded, preset original", w);
  print("unwelded, preset original", u);
  ASSERT_TRUE(u.physik.converged && u.mujoco.converged && w.mujoco.converged);
  ASSERT_TRUE(w.physik.converged);
  EXPECT_LE(w.gap, 3.0 * u.gap);
  // the welded run is slower by the root body's inertia ratio (the torso's group of 6 bones:
  // 2.29; steps 5993 / 2545 = 2.35). The reach's slow part is mostly, not only, that body's
  // turn (the other welded bodies' ratios are 1.19 to 1.72), so the prediction is held to 25%:
  // it tells the factor's damping apart from no effect of the welds (1) and from the old run
  // (never converged)
  const double predicted = composite_over_own_inertia(welded_, welded_.bone_body[0]);
  const double ratio = static_cast<double>(w.physik.steps_to_converge) / u.physik.steps_to_converge;
  std::cout << "[welded reach] steps welded / unwelded " << ratio
            << ", the root body's composite / own inertia " << predicted << "\n";
  EXPECT_NEAR(ratio / predicted, 1.0, 0.25);
}

// With the factor as a torque before the joint solve, as MuJoCo applies it, the paper's joint
// solve over composite bodies follows MuJoCo: both rigs converge within a tenth of MuJoCo's step
// count (962 and 1028 against 952 and 996) and end within 0.005 of the height of its pose
// (0.0022 welded, 0.0015 unwelded), the welded within twice the unwelded gap.
TEST_F(WeldedReach, WithTheFactorInTheJointSolveBothRigsFollowMujoco) {
  const Outcome w = run_both(welded_, 4000, true), u = run_both(unwelded_, 4000, true);
  print("welded, factor in the joint solve", w);
  print("unwelded, factor in the joint solve", u);
  for (const Outcome* o : {&w, &u}) {
    ASSERT_TRUE(o->physik.converged && o->mujoco.converged);
    EXPECT_LE(o->physik.steps_to_converge, 1.1 * o->mujoco.steps_to_converge);
    EXPECT_LE(o->gap, 0.005);
  }
  EXPECT_LE(w.gap, 2.0 * u.gap);
}

}  // namespace
}  // namespace physik
