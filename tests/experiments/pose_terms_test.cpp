// The implicit step with implicit_linearisation full (physik/engine/implicit_pose_terms.h) against
// the linearisation experiment's dense newton_at_rest step (experiments/linearisation.h), which
// linearises the rest dynamics a(q, 0) by central differences: on random branching trees, moving,
// pulled by linear control springs, with engaged linear torsion springs of either torque, at
// several step lengths, one bare step each (no energy guard).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <ostream>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/linearisation.h"
#include "physik/engine/engine.h"
#include "physik/engine/forces.h"
#include "physik/engine/implicit_advance.h"
#include "physik/engine/implicit_step.h"
#include "physik/engine/integrate_joint_space.h"
#include "physik/engine/interpolation.h"
#include "physik/engine/newton_euler.h"
#include "physik/engine/torsion_springs.h"
#include "physik/model/joint_coordinates.h"
#include "physik/model/params.h"
#include "tests/dense_dynamics.h"

namespace physik {
namespace {

using experiments::linearisation::accelerations;
using experiments::linearisation::bare_step;
using experiments::linearisation::derivatives;
using experiments::linearisation::joint_velocity;
using experiments::linearisation::unit_force_response;
using experiments::linearisation::Variant;
using experiments::linearisation::variant_name;

struct PoseCase {
  Scene scene;
  SimState s;
};

// random_hinged_rig (tests/dense_dynamics.h: hinges, universal joints, welds by locks) with
// narrow limits on some free axes
Rig hinged_limited_rig(std::mt19937& rng, int n) {
  Rig rig = dense::random_hinged_rig(rng, n);
  for (int i = 1; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if ((i + a) % 2 == 0 && !rig.bone_limit[i][a].locked())
        rig.bone_limit[i][a] = {true, -0.2, 0.1 + 0.1 * a};
    }
  }
  refresh_joint_model(rig);
  return rig;
}

// a random tree of n bones: limits on some axes (violated at random poses: engaged torsion
// springs), linear control springs on random bones toward random targets, moving; `hinged`:
// locked axes too (rig.h "Locked axes"), the joints' angles and rates random
PoseCase random_pose_case(std::mt19937& rng, int n, TorsionTorque torque, bool hinged = false) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PoseCase out;
  Scene& sc = out.scene;
  sc.file = "<random>";
  sc.rig = hinged ? hinged_limited_rig(rng, n) : dense::random_limited_rig(rng, n);
  sc.params = preset_params("original");
  sc.params.scheme = Scheme::kImplicit;
  sc.params.implicit_linearisation = ImplicitLinearisation::kFull;
  sc.params.implicit_max_splits = 0;
  sc.params.interpolation = Interpolation::kNone;
  sc.params.damping = 1.5;
  sc.params.angular_velocity_factor = 0.7;
  sc.params.torsion_k = 13.0;
  sc.params.torsion_torque = torque;
  sc.initial_pose = rest_pose(sc.rig);
  for (int k = 0; k < 1 + n / 2; ++k) {
    ControlPoint cp;
    cp.bone = std::uniform_int_distribution<int>(0, n - 1)(rng);
    cp.alpha = 0.5 + 0.5 * u(rng);
    cp.target_world = 2.0 * Vec3(u(rng), u(rng), u(rng));
    cp.k = 5.0 + 20.0 * std::abs(u(rng));
    cp.spring = SpringLaw::kLinear;
    sc.control_points.push_back(cp);
  }
  init_state(sc, out.s);
  SimState& s = out.s;
  for (int i = 1; i < n; ++i) {
    const JointType type = sc.rig.bone_joint_type[i];
    if (type == JointType::kBall) {
      s.pose.bone_local_rotation[i] =
          Quat(Eigen::AngleAxisd(1.5 * u(rng), dense::random_unit(rng)));
    } else if (type != JointType::kWeld) {
      s.joint_space.hinge_angle[i] = Vec2(1.5 * u(rng), type == JointType::kHinge ? 0.0 : u(rng));
      s.pose.bone_local_rotation[i] = hinge_rotation(sc.rig, i, s.joint_space.hinge_angle[i]);
    }
  }
  s.joint_space.root_com_world = Vec3(u(rng), u(rng), u(rng));
  s.joint_space.root_orient_world = Quat(Eigen::AngleAxisd(3.0 * u(rng), dense::random_unit(rng)));
  s.joint_space.root_vel_world = Vec3(u(rng), u(rng), u(rng));
  for (int i = 0; i < n; ++i) {
    const int k = rotational_coordinates(sc.rig.bone_joint_type[i]);
    for (int c = 0; c < 3; ++c) s.joint_space.joint_vel_local[i][c] = c < k ? u(rng) : 0.0;
  }
  world_from_joint_space(sc.rig, s);
  return out;
}

// does the paper torque's clip act on some engaged joint (then the step's block is not the
// dense step's tangent)
bool clip_acts(const Scene& sc, const SimState& s) {
  if (sc.params.torsion_torque != TorsionTorque::kAxes) return false;
  for (int i = 1; i < sc.rig.nbone; ++i) {
    // a hinge's springs act on its angles: no clip there (torsion_springs.h)
    if (torsion_kind(sc.rig, LockedAxes::kRemoved, i) != TorsionKind::kRotationVector) continue;
    const Vec3 theta = rotation_vector(s.pose.bone_local_rotation[i]);
    const Vec3 k = torsion_step_stiffness_local(sc.rig.bone_limit[i], theta, sc.params);
    const Mat3 tangent = k.asDiagonal() * left_jacobian_inverse_transpose(theta).transpose();
    if (!(torsion_step_block_local(k, theta, TorsionTorque::kAxes) - tangent).isZero(1e-14))
      return true;
  }
  return false;
}

// The list's world-held forces whose step stiffness is their tangent, beside the springs: gravity
// and two stiff pins on random bones, each a little off its point
void add_gravity_and_pins(std::mt19937& rng, PoseCase& pc) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Scene& sc = pc.scene;
  sc.gravity_world = Vec3(0.0, 0.0, -9.81);
  for (int k = 0; k < 2; ++k) {
    Pin pin;
    pin.bone = std::uniform_int_distribution<int>(0, sc.rig.nbone - 1)(rng);
    pin.alpha = 0.5 + 0.5 * u(rng);
    pin.point_world =
        point_on_bone(pc.s.frames, pin.bone, pin.alpha) + 0.3 * Vec3(u(rng), u(rng), u(rng));
    pin.k = 30.0 + 20.0 * std::abs(u(rng));
    sc.pins.push_back(pin);
  }
}

// an orientation target, linear, on a random bone, `kMilliradians` from its bone's frame, pulling
// hard (k 40 N m/rad)
template <int kMilliradians>
void add_orientation_target(std::mt19937& rng, PoseCase& pc) {
  OrientationTarget o;
  o.bone = std::uniform_int_distribution<int>(0, pc.scene.rig.nbone - 1)(rng);
  o.target_world = Quat(Eigen::AngleAxisd(1e-3 * kMilliradians, dense::random_unit(rng))) *
                   pc.s.frames.orient_world[o.bone];
  o.spring = SpringLaw::kLinear;
  o.k = 40.0;
  pc.scene.orientation_targets.push_back(o);
}

// an aim, linear, on a random bone, its point `kMilliradians` off the bone's axis seen from its
// head, 2 rig units away, pulling as hard
template <int kMilliradians>
void add_aim_target(std::mt19937& rng, PoseCase& pc) {
  const BoneFrames& f = pc.s.frames;
  AimTarget a;
  a.bone = std::uniform_int_distribution<int>(0, pc.scene.rig.nbone - 1)(rng);
  const Vec3 axis = f.orient_world[a.bone] * a.axis_bone;
  const Vec3 across = axis.cross(dense::random_unit(rng)).normalized();
  a.point_world =
      f.head_world[a.bone] + 2.0 * (Eigen::AngleAxisd(1e-3 * kMilliradians, across) * axis);
  a.spring = SpringLaw::kLinear;
  a.k = 40.0;
  pc.scene.aim_targets.push_back(a);
}

// The O(n) variant's accelerations against the dense variant's linear system
// (1 - h A_v - h^2 A_q) a = a_explicit + h A_q v (linearisation.h (L)), at h = 0.05, 1 and 20 s:
//   - the normwise backward error of the O(n) accelerations in the dense system, every h;
//   - the O(n) system, M^-1 (M + h D + h^2 K) from its responses to unit generalised forces (it is
//     linear in them), against the dense one, h <= 1 (at h = 20 the responses are ~1e-4 of the
//     accelerations they are differences of, and inverting them loses the digits);
//   - the accelerations themselves at h = dt (at longer steps the systems' condition numbers, up
//     to ~1e5 here, amplify the central differences' noise in the dense step's solution).
// Returns the worst of each.
struct Worst {
  double backward = 0.0, system = 0.0, solution = 0.0;
  double system_cond = 1.0;  // the condition number of the step's response where `system` is worst
  int compared = 0;
};

// the engine's bare step (implicit_advance.h take_implicit_step) with the pose terms `context`
void selected_step(const Scene& scene, SimState& s, double h, const void* context) {
  ForceStage stage;
  stage.step = h;
  apply_forces(scene, s, stage);
  solve_implicit(scene, s, h, *static_cast<const PoseTermSelection*>(context));
  integrate_joint_space(scene.rig, h, s);
}

// one bare step of the O(n) full step with these pose terms
void recursive_step(const Scene& scene, SimState& s, double h, const PoseTermSelection& use) {
  Scene bare = scene;
  bare.params.implicit_max_splits = 0;
  bare.params.implicit_linearisation = ImplicitLinearisation::kFull;
  update_targets(bare, s);
  advance_implicit(bare, s, h, selected_step, &use);
  s.step += 1;
  s.time += h;
}

// more forces of the list on a case (none by default)
using Extras = void (*)(std::mt19937&, PoseCase&);

Worst compare_with_dense(PoseTermSelection use, Variant dense_variant, unsigned seed,
                         Extras extras = nullptr, bool hinged = false) {
  use.gauss_newton_retake = false;  // the bare recursion: the dense step has no retake
  std::mt19937 rng(seed);
  Worst w;
  for (int trial = 0; trial < 24; ++trial) {
    const TorsionTorque torque = trial % 2 ? TorsionTorque::kAxes : TorsionTorque::kGradient;
    PoseCase pc = random_pose_case(rng, 2 + trial % 7, torque, hinged);
    if (extras) extras(rng, pc);
    if (clip_acts(pc.scene, pc.s)) continue;
    const Eigen::MatrixXd M_inv = unit_force_response(pc.scene, pc.s, false, 0.05);
    const Eigen::VectorXd v = joint_velocity(pc.scene.rig, pc.s);
    for (double h : {0.05, 1.0, 20.0}) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " n " << pc.scene.rig.nbone << " h "
                                      << h << " torque " << to_string(torque));
      Eigen::MatrixXd A_q, A_v;
      derivatives(pc.scene, pc.s, dense_variant, A_q, A_v, h);
      const int n = static_cast<int>(A_q.rows());
      const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(n, n) - h * A_v - h * h * A_q;
      SimState a = pc.s, b = pc.s;
      recursive_step(pc.scene, a, h, use);
      bare_step(pc.scene, b, h, dense_variant);
      const Eigen::VectorXd acc = (joint_velocity(pc.scene.rig, a) - v) / h,
                            acc_dense = (joint_velocity(pc.scene.rig, b) - v) / h;
      const Eigen::VectorXd rhs = accelerations(pc.scene, pc.s) + h * (A_q * v);
      w.backward =
          std::max(w.backward, (S * acc - rhs).norm() / (S.norm() * acc.norm() + rhs.norm()));
      if (h <= 1.0) {
        const Eigen::MatrixXd response = unit_force_response(pc.scene, pc.s, true, h, use);
        const Eigen::MatrixXd S_step = M_inv * response.inverse();
        const double system = (S_step - S).norm() / S.norm();
        if (system > w.system) {
          const Eigen::JacobiSVD<Eigen::MatrixXd> svd(response);
          const auto& sv = svd.singularValues();
          w.system_cond = sv(0) / sv(sv.size() - 1);
          w.system = system;
        }
      }
      if (h == 0.05) w.solution = std::max(w.solution, (acc - acc_dense).norm() / acc_dense.norm());
      ++w.compared;
    }
  }
  return w;
}

std::ostream& operator<<(std::ostream& o, const Worst& w) {
  return o << "backward error " << w.backward << ", system " << w.system
           << " (response's condition " << w.system_cond << "), accelerations at h = dt "
           << w.solution;
}

void expect_equal(const char* name, const PoseTermSelection& use, Variant dense_variant,
                  Extras extras = nullptr, bool hinged = false) {
  const Worst w = compare_with_dense(use, dense_variant, 5, extras, hinged);
  EXPECT_GT(w.compared, 30);
  EXPECT_LT(w.backward, 1e-8);
  EXPECT_LT(w.system, 1e-8);
  EXPECT_LT(w.solution, 1e-8);
  std::cout << name << " vs " << variant_name(dense_variant) << ": " << w << "\n";
}

TEST(PoseTerms, TheFullStepIsTheDenseNewtonAtRestStep) {
  expect_equal("every pose term", PoseTermSelection{}, Variant::kNewtonAtRest);
}

// The pose terms take every element's forces from the force list (forces.h pose_forces): with
// gravity and pins in, the step is still the dense step (a pin's step stiffness is its tangent;
// gravity supplies none, and none is needed: forces.cpp)
TEST(PoseTerms, WithGravityAndPinsTheFullStepIsTheDenseNewtonAtRestStep) {
  expect_equal("with gravity and pins", PoseTermSelection{}, Variant::kNewtonAtRest,
               add_gravity_and_pins);
}

// rig.h "Locked axes": hinges, universal joints and welds by locks (implicit_pose_terms.h: a
// hinge's terms are a ball's on its axis, a universal's take two corrections), with engaged
// torsion springs on their angles, gravity and pins
TEST(PoseTerms, OnHingedTreesTheFullStepIsTheDenseNewtonAtRestStep) {
  expect_equal("hinged trees", PoseTermSelection{}, Variant::kNewtonAtRest, nullptr, true);
  expect_equal("hinged trees with gravity and pins", PoseTermSelection{}, Variant::kNewtonAtRest,
               add_gravity_and_pins, true);
}

TEST(PoseTerms, TheForcesTermsAloneAreTheDensePoseForcesStep) {
  PoseTermSelection use;
  use.inertia_wrench = use.inertia_turn = use.turning_accelerations = false;
  expect_equal("the forces' terms", use, Variant::kPoseForces);
}

TEST(PoseTerms, TheInertiasTermsAloneAreTheDensePoseInertiaStep) {
  PoseTermSelection use;
  use.forces = use.torque_frame = false;
  expect_equal("the inertia's terms", use, Variant::kPoseInertia);
}

// The shipped full step retakes a step as Gauss-Newton exactly where the recursion with the pose
// terms met a pivot (or the root's 6x6) whose symmetric part is not positive definite, and only
// there; the retaken step is the Gauss-Newton step. The random poses give both cases.
TEST(PoseTerms, APivotNotPositiveRetakesTheStepAsGaussNewton) {
  std::mt19937 rng(11);
  int retaken = 0, kept = 0;
  for (int trial = 0; trial < 40; ++trial) {
    PoseCase pc = random_pose_case(rng, 2 + trial % 7, TorsionTorque::kGradient);
    for (double h : {0.05, 1.0, 20.0}) {
      SCOPED_TRACE(testing::Message() << "trial " << trial << " h " << h);
      PoseTermSelection bare_terms;
      bare_terms.gauss_newton_retake = false;
      SimState shipped = pc.s, bare = pc.s, gauss_newton = pc.s;
      recursive_step(pc.scene, shipped, h, PoseTermSelection{});
      recursive_step(pc.scene, bare, h, bare_terms);
      Scene gn = pc.scene;
      gn.params.implicit_linearisation = ImplicitLinearisation::kGaussNewton;
      step(gn, gauss_newton, h);
      const bool positive = bare.joint_space.articulated.pose_terms_positive;
      const SimState& expected = positive ? bare : gauss_newton;
      EXPECT_EQ(shipped.implicit.gauss_newton_steps, positive ? 0 : 1);
      EXPECT_EQ(joint_velocity(pc.scene.rig, shipped), joint_velocity(pc.scene.rig, expected));
      EXPECT_NE(joint_velocity(pc.scene.rig, bare), joint_velocity(pc.scene.rig, gauss_newton));
      (positive ? kept : retaken) += 1;
    }
  }
  EXPECT_GT(retaken, 0);
  EXPECT_GT(kept, 0);
  std::cout << "retaken as Gauss-Newton " << retaken << ", kept " << kept << " of "
            << retaken + kept << " steps\n";
}

// Term by term: each term dropped from the full step, and the shared DESIGN.md sketch, miss the
// dense step by far more than the central differences' noise (implicit_pose_terms.h)
TEST(PoseTerms, EachTermAndTheSketchMatter) {
  struct Drop {
    const char* name;
    bool PoseTermSelection::*term;
  };
  for (const Drop& d :
       {Drop{"(1..3, 5) the forces' terms", &PoseTermSelection::forces},
        Drop{"(5) the torque frame's turn", &PoseTermSelection::torque_frame},
        Drop{"(1) the d'Alembert wrenches", &PoseTermSelection::inertia_wrench},
        Drop{"(3) the inertia's turn", &PoseTermSelection::inertia_turn},
        Drop{"(4) the joint accelerations' turn", &PoseTermSelection::turning_accelerations}}) {
    PoseTermSelection use;
    use.*d.term = false;
    const Worst w = compare_with_dense(use, Variant::kNewtonAtRest, 5);
    EXPECT_GT(w.backward, 1e-4) << d.name;
    std::cout << "without " << d.name << ": " << w << "\n";
  }
  PoseTermSelection sketch;  // (1) over the whole transmitted wrench, no frame term, no (3), (4)
  sketch.torsion_in_wrench = true;
  sketch.torque_frame = sketch.inertia_turn = sketch.turning_accelerations = false;
  const Worst w = compare_with_dense(sketch, Variant::kNewtonAtRest, 5);
  EXPECT_GT(w.backward, 1e-4);
  std::cout << "the sketch: " << w << "\n";
  sketch.inertia_turn = sketch.turning_accelerations = true;  // its torsion handling alone
  const Worst t = compare_with_dense(sketch, Variant::kNewtonAtRest, 5);
  EXPECT_GT(t.backward, 1e-4);
  std::cout << "the sketch's torsion handling with (3) and (4): " << t << "\n";
}

// An orientation target's couple under the pose terms: its step stiffness is its tangent k J_l^-T
// (orientation_springs.cpp) and its couple is in the transmitted wrench, so the step is the dense
// step, at a small turn and a wide one
TEST(PoseTerms, WithOrientationTargetsTheFullStepIsTheDenseNewtonAtRestStep) {
  expect_equal("with an orientation target 0.05 rad off", PoseTermSelection{},
               Variant::kNewtonAtRest, add_orientation_target<50>);
  expect_equal("with an orientation target 0.6 rad off", PoseTermSelection{},
               Variant::kNewtonAtRest, add_orientation_target<600>);
}

// An aim under the pose terms: its step stiffness is its Hessian in (turn, head), coupling
// included (aim_springs.cpp), and its couple and head force are in the pose terms, so the step is
// the dense step, near the aim's rest and far from it
TEST(PoseTerms, WithAnAimTheFullStepIsTheDenseNewtonAtRestStep) {
  expect_equal("with an aim on its axis", PoseTermSelection{}, Variant::kNewtonAtRest,
               add_aim_target<0>);
  expect_equal("with an aim 0.05 rad off", PoseTermSelection{}, Variant::kNewtonAtRest,
               add_aim_target<50>);
  expect_equal("with an aim 1.2 rad off", PoseTermSelection{}, Variant::kNewtonAtRest,
               add_aim_target<1200>);
}

// Every element's pose forces (forces.h) are the force its stage applies at rest: their
// resultants on each body, force and torque about its centre, against the stage's, element by
// element, on random poses with every kind of target on
TEST(PoseTerms, EachElementsPoseForcesAreTheForceItApplies) {
  class Resultants final : public PoseForces {
   public:
    Resultants(const Rig& rig, const SimState& s)
        : rig_(rig), s_(s), force(rig.nbone, Vec3::Zero()), torque(rig.nbone, Vec3::Zero()) {}
    void point(int b, const Vec3& at, const Vec3& f) override {
      force[b] += f;
      torque[b] += (at - s_.com_world[b]).cross(f);
    }
    void couple(int b, const Vec3& t) override { torque[b] += t; }
    void joint(int i, const Vec3& t) override {
      torque[i] += t;
      torque[rig_.bone_parent[i]] -= t;
    }

   private:
    const Rig& rig_;
    const SimState& s_;

   public:
    std::vector<Vec3> force, torque;
  };
  std::mt19937 rng(17);
  int checked = 0;
  for (int trial = 0; trial < 12; ++trial) {
    PoseCase pc = random_pose_case(rng, 2 + trial % 7,
                                   trial % 2 ? TorsionTorque::kAxes : TorsionTorque::kGradient);
    add_gravity_and_pins(rng, pc);
    add_orientation_target<300>(rng, pc);
    add_aim_target<300>(rng, pc);
    const Scene& sc = pc.scene;
    SimState& s = pc.s;
    for (int i = 0; i < sc.rig.nbone; ++i) s.joint_space.joint_vel_local[i].setZero();
    s.joint_space.root_vel_world.setZero();
    world_from_joint_space(sc.rig, s);
    element_tangents(sc, s);  // the torsion torques the pose terms read
    for (const ForceElement& e : force_elements()) {
      if (!e.pose_forces) continue;
      prepare_bodies(sc.rig, sc.params, s);
      e.apply(sc, s, ForceStage{});
      Resultants r(sc.rig, s);
      e.pose_forces(sc, s, r);
      double scale = 1e-12;
      for (int b = 0; b < sc.rig.nbone; ++b) {
        scale = std::max({scale, s.force_world[b].norm(), s.torque_world[b].norm()});
      }
      for (int b = 0; b < sc.rig.nbone; ++b) {
        SCOPED_TRACE(testing::Message() << e.name << " trial " << trial << " bone " << b);
        EXPECT_LT((r.force[b] - s.force_world[b]).norm(), 1e-12 * scale);
        EXPECT_LT((r.torque[b] - s.torque_world[b]).norm(), 1e-12 * scale);
      }
      checked += scale > 1e-9;
    }
  }
  EXPECT_GT(checked, 12 * 4);  // control, orientation, aim and pins pull in every trial
}

}  // namespace
}  // namespace physik
