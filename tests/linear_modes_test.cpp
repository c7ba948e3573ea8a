// The linear modes of damping auto (physik/engine/linear_modes.h): the iterative path (Lanczos
// on the articulated-body recursion) against the dense reference (linear_modes_dense.h) on every
// shipped scene and on random trees up to 400 bones; the matrix-free products (mode_operators.h)
// against the dense matrices through the coordinate change between them; a lone rod's mode in
// closed form; no spring, no mode.
#include "physik/engine/linear_modes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "physik/engine/engine.h"
#include "physik/engine/linear_modes_dense.h"
#include "physik/engine/mode_operators.h"
#include "physik/io/scene_io.h"
#include "physik/model/rig_generators.h"
#include "tests/dense_dynamics.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// relative agreement of every reported number, to `tol`
void expect_same_modes(const LinearModes& it, const LinearModes& ref, double tol,
                       const std::string& what) {
  const auto rel = [](double a, double b) {
    return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
  };
  ASSERT_EQ(it.found, ref.found) << what;
  EXPECT_EQ(it.skipped, ref.skipped) << what;
  EXPECT_LE(rel(it.first_constrained_omega, ref.first_constrained_omega), tol)
      << what << ": " << it.first_constrained_omega << " vs " << ref.first_constrained_omega;
  if (!ref.found) return;
  EXPECT_LE(rel(it.slowest_omega, ref.slowest_omega), tol)
      << what << ": " << it.slowest_omega << " vs " << ref.slowest_omega;
  EXPECT_LE(rel(it.critical_damping, ref.critical_damping), tol)
      << what << ": c " << it.critical_damping << " vs " << ref.critical_damping;
  EXPECT_LE(rel(it.slowest_d1, ref.slowest_d1), tol) << what;
  // phi^T Dr phi can be a small difference of the rule's terms: compare it on 2 w's scale
  EXPECT_LE(std::abs(it.slowest_dr - ref.slowest_dr), tol * 2.0 * ref.slowest_omega) << what;
}

// the targets damping auto uses: every control point at its own position (linear_modes.h)
std::vector<Vec3> at_points(const Scene& scene, const SimState& st) {
  std::vector<Vec3> t;
  for (const ControlPoint& cp : scene.control_points) {
    t.push_back(point_on_bone(st.frames, cp.bone, cp.alpha));
  }
  return t;
}

std::vector<Vec3> scene_targets(const Scene& scene) {
  std::vector<Vec3> t;
  for (const ControlPoint& cp : scene.control_points) t.push_back(cp.target_world);
  return t;
}

// every shipped scene in its own scheme and in the implicit scheme: pinhead's joints are balls with
// locked axes as torsion springs in the paper's scheme, hinges, a universal joint and welds by
// locks in the implicit one (rig.h "Locked axes"), and both paths count the same coordinates
TEST(LinearModes, IterativeEqualsDenseOnEveryShippedScene) {
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::model_path("scenes"))) {
    if (entry.path().extension() != ".json") continue;
    for (const bool implicit : {false, true}) {
      Scene scene = load_scene(entry.path().string());
      if (implicit) scene.params.scheme = Scheme::kImplicit;
      SimState st;
      init_state(scene, st);
      for (const std::vector<Vec3>& targets : {at_points(scene, st), scene_targets(scene)}) {
        const LinearModes ref = linear_modes_dense(scene, st, targets).modes;
        const LinearModes it = linear_modes(scene, st, targets);
        expect_same_modes(it, ref, 1e-6,
                          entry.path().filename().string() + (implicit ? " implicit" : ""));
      }
    }
    ++scenes;
  }
  EXPECT_GE(scenes, 10);
}

// a random tree with control springs on random bones (some capped, some far), on half the
// trees torsion springs (random limits, engaged at the random pose, either torque), and a
// velocity factor below 1
// (hinged: hinges, universal joints and welds by locks in the implicit scheme's joint model, their
// free axes limited)
Scene random_mode_scene(std::mt19937& rng, int n, SimState& st, bool hinged = false) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  dense::RandomTree t = dense::random_tree(rng, n, false, hinged);
  EngineParams p = test::bare_params(0.02 + 0.1 * u(rng));
  if (hinged) p.scheme = Scheme::kImplicit;
  p.angular_velocity_factor = 0.5 + 0.5 * u(rng);
  p.torsion_k = u(rng) < 0.5 ? 0.0 : 5.0 * u(rng);
  p.torsion_torque = u(rng) < 0.5 ? TorsionTorque::kAxes : TorsionTorque::kGradient;
  for (int b = 1; b < n && p.torsion_k > 0.0; ++b) {
    for (AxisLimit& a : t.rig.bone_limit[b]) {
      if (u(rng) < 0.3 || a.locked()) continue;
      a.limited = true;
      a.min = -1.5 * u(rng);
      a.max = 1.5 * u(rng);
    }
  }
  Scene scene = test::scene_for(t.rig, p);
  scene.initial_pose = t.s.pose;
  const int springs = 1 + static_cast<int>(u(rng) * std::min(n, 6));
  for (int c = 0; c < springs; ++c) {
    const int bone = std::uniform_int_distribution<int>(0, n - 1)(rng);
    const SpringLaw law = u(rng) < 0.5 ? SpringLaw::kLinear : SpringLaw::kCapped;
    const Vec3 target = 4.0 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    scene.control_points.push_back(test::control(bone, u(rng), target, 1.0 + 50.0 * u(rng), law));
  }
  init_state(scene, st);
  return scene;
}

// The sanitizer run (PHYSIK_SANITIZED) stops at 120 bones: the 400-bone dense reference, O(n^3),
// takes minutes there and adds no path the smaller trees do not take.
TEST(LinearModes, IterativeEqualsDenseOnRandomTreesUpTo400Bones) {
  std::mt19937 rng(35);
  int torsion = 0;
  const int largest = PHYSIK_SANITIZED ? 120 : 400;
  for (int n : {1, 2, 3, 5, 8, 13, 30, 60, 120, 400}) {
    if (n > largest) break;
    for (int trial = 0; trial < (n <= 30 ? 6 : n <= 120 ? 2 : 1); ++trial) {
      SimState st;
      const Scene scene = random_mode_scene(rng, n, st);
      ModeWorkspace ws;
      torsion += ModeOperators(scene, st, scene_targets(scene), ws).workspace().torsion.size();
      for (const std::vector<Vec3>& targets : {at_points(scene, st), scene_targets(scene)}) {
        const LinearModes ref = linear_modes_dense(scene, st, targets).modes;
        const LinearModes it = linear_modes(scene, st, targets);
        expect_same_modes(it, ref, 1e-6,
                          "n " + std::to_string(n) + " trial " + std::to_string(trial));
        if (n == 400) break;  // the dense reference takes seconds there
      }
    }
  }
  EXPECT_GT(torsion, 100);  // engaged torsion springs in K (a test of them, not only of springs)
}

// The O(n) products and solve against the dense matrices: x_opn = T x_dense, T the rotation of
// each ball's (and the free root's turn's) local axes to world axes, identity elsewhere (a
// hinge's angle rates are both paths' coordinates), so A_opn = T A_dense T^T
TEST(LinearModes, OperatorsAreTheDenseMatricesOnHingedTrees) {
  std::mt19937 rng(43);
  for (int trial = 0; trial < 12; ++trial) {
    SimState st;
    const Scene scene = random_mode_scene(rng, 2 + trial % 9, st, trial % 3 != 0);
    const Rig& rig = scene.rig;
    const int nv = rig.velocity_count(scene.params.locked_axes());
    const DenseModeMatrices dm = dense_mode_matrices(scene, st, scene_targets(scene));
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(nv, nv);
    for (int i = 0; i < rig.nbone; ++i) {
      const JointType type = rig.joint_type(i, scene.params.locked_axes());
      if (type != JointType::kBall && type != JointType::kFree) continue;
      const int a = rig.dofadr(i, scene.params.locked_axes()) + (type == JointType::kFree ? 3 : 0);
      T.block<3, 3>(a, a) = st.frames.orient_world[i].toRotationMatrix();
    }
    ModeWorkspace ws;
    ModeOperators ops(scene, st, scene_targets(scene), ws);
    ASSERT_EQ(ops.size(), nv);
    const std::pair<ModeOperators::Matrix, const Eigen::MatrixXd*> pairs[] = {
        {ModeOperators::Matrix::kMass, &dm.M},
        {ModeOperators::Matrix::kStiffness, &dm.K},
        {ModeOperators::Matrix::kEndDampers, &dm.D1},
        {ModeOperators::Matrix::kFactorDamper, &dm.Dr}};
    for (const auto& [which, dense] : pairs) {
      const Eigen::MatrixXd expected = T * (*dense) * T.transpose();
      VecX x(nv), y;
      for (int c = 0; c < nv; ++c) {
        x.setZero();
        x[c] = 1.0;
        ops.multiply(which, x, y);
        EXPECT_LT((y - expected.col(c)).norm(), 1e-9 * std::max(1.0, expected.norm()))
            << "trial " << trial << " matrix " << static_cast<int>(which) << " column " << c;
      }
    }
    // (K + s M)^-1 b
    ops.set_shift(0.7);
    const Eigen::MatrixXd H = T * (dm.K + 0.7 * dm.M) * T.transpose();
    const VecX b = VecX::Random(nv);
    VecX x;
    ops.solve(b, x);
    EXPECT_LT((H * x - b).norm(), 1e-9 * b.norm() * std::max(1.0, H.norm())) << "trial " << trial;
    // the pivots' count of the modes below sigma (Sylvester) against the dense eigenvalues
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(dm.K, dm.M);
    for (int k = 0; k < nv; ++k) {
      const double w2 = eig.eigenvalues()[k];
      if (w2 <= 1e-6 * std::max(1.0, eig.eigenvalues().maxCoeff())) continue;
      EXPECT_EQ(ops.count_below(w2 * (1.0 + 1e-7)), k + 1) << "trial " << trial << " mode " << k;
      EXPECT_EQ(ops.count_below(w2 * (1.0 - 1e-7)), k) << "trial " << trial << " mode " << k;
    }
  }
}

TEST(LinearModes, IterativeEqualsDenseOnHingedRandomTrees) {
  std::mt19937 rng(41);
  int torsion = 0;
  for (int n : {2, 3, 5, 8, 13, 30, 60}) {
    for (int trial = 0; trial < 6; ++trial) {
      SimState st;
      const Scene scene = random_mode_scene(rng, n, st, true);
      ModeWorkspace ws;
      torsion += ModeOperators(scene, st, scene_targets(scene), ws).workspace().torsion.size();
      for (const std::vector<Vec3>& targets : {at_points(scene, st), scene_targets(scene)}) {
        const LinearModes ref = linear_modes_dense(scene, st, targets).modes;
        const LinearModes it = linear_modes(scene, st, targets);
        expect_same_modes(it, ref, 1e-6,
                          "hinged n " + std::to_string(n) + " trial " + std::to_string(trial));
      }
    }
  }
  EXPECT_GT(torsion, 30);
}

// A straight chain of n unit rods pulled at its tail by one spring k: its slowest constrained mode
// is the whole chain's translation along itself against the spring, w^2 = k / (n m) with m the
// rod's mass, which the end dampers damp with phi^T D1 phi = 2 n / (n m) (every head and tail
// moving at 1 / sqrt(n m)), so c = 2 w m / 2. Lanczos must find it without the walk, whose counts
// cost a bisection each: the first Ritz pair, the tail's sideways mode, must not pass for the
// slowest from a start vector that F's shift filtered toward the stiff end.
TEST(LinearModes, LongChainsSlowestModeFoundByLanczos) {
  for (int n : {100, 1000, 10000}) {
    if (PHYSIK_SANITIZED && n > 1000) break;
    EngineParams p = preset_params("original");
    Scene scene = test::scene_for(make_chain_rig(n), p);
    const double k = 10.0;  // N/m
    scene.control_points.push_back(
        test::control(n - 1, 1.0, scene.rig.bone_rest_tail_world[n - 1], k, SpringLaw::kCapped));
    SimState st;
    init_state(scene, st);
    const LinearModes it = linear_modes(scene, st, at_points(scene, st));
    const double m = scene.rig.bone_mass[0];  // kg, every rod's
    const std::string what = std::to_string(n) + " bones";
    ASSERT_TRUE(it.found) << what;
    EXPECT_FALSE(it.walked) << what;
    EXPECT_EQ(it.counts, 2) << what;  // the certificate's two, no walk
    EXPECT_NEAR(it.slowest_omega * it.slowest_omega, k / (n * m), 1e-9 * k / (n * m)) << what;
    EXPECT_NEAR(it.slowest_d1, 2.0 / m, 1e-9) << what;
    EXPECT_NEAR(it.critical_damping, std::sqrt(k / (n * m)) * m, 1e-9 * std::sqrt(k * m / n))
        << what;
  }
}

}  // namespace
}  // namespace physik
