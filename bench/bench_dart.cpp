// DART (Dynamic Animation and Robotics Toolkit, Debian's libdart-dev 6.12) as a second peer for the
// exact step: the same rig as a DART skeleton (a free joint at the root, a ball joint at every
// other head; each body's mass, centre and principal moments from the rig), stepped by
// dart::simulation::World::step (Featherstone's articulated-body forward dynamics, then DART's
// semi-implicit Euler; no shapes, so no collision, and no gravity), against PhysIK's step() with
// scheme exact and scheme implicit on the scaling experiment's scenario (experiments/scaling.h),
// in thread CPU time. Built only when CMake finds DART, which is installed by hand (`apt-get
// install libdart-dev`: all of Boost), never by the setup script.
//   dart_us_per_bone  World::step, us per step per bone
// DART's chain is pulled at its last tail by a constant force of the spring's k newtons toward the
// scenario's target (the cost of its step does not depend on the force).
// Source: DART's dynamics API (dart/dynamics/Skeleton.hpp, BallJoint.hpp, FreeJoint.hpp).
#include <algorithm>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
// narrower than dart/dart.hpp, whose IkFast header Debian ships without dart/external/ikfast
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>

#include "experiments/scaling.h"

namespace {

using physik::experiments::scaling_scene;
using physik::experiments::thread_seconds;

// the bone's rest frame in world: its head, its rest orientation (local +Y along the bone)
Eigen::Isometry3d rest_frame(const physik::Rig& rig, int i) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = rig.bone_rest_orient_world[i].toRotationMatrix();
  t.translation() = rig.bone_rest_head_world[i];
  return t;
}

dart::dynamics::SkeletonPtr skeleton_of(const physik::Rig& rig) {
  using namespace dart::dynamics;
  SkeletonPtr skel = Skeleton::create(rig.name);
  std::vector<BodyNode*> body(rig.nbone, nullptr);
  for (int i = 0; i < rig.nbone; ++i) {
    const int p = rig.bone_parent[i];
    BodyNode::Properties bp;
    bp.mName = rig.bone_name[i];
    if (p < 0) {
      FreeJoint::Properties jp;
      jp.mName = rig.bone_name[i];
      jp.mT_ParentBodyToJoint = rest_frame(rig, i);
      body[i] = skel->createJointAndBodyNodePair<FreeJoint>(nullptr, jp, bp).second;
    } else {
      BallJoint::Properties jp;
      jp.mName = rig.bone_name[i];
      jp.mT_ParentBodyToJoint = rest_frame(rig, p).inverse() * rest_frame(rig, i);
      body[i] = skel->createJointAndBodyNodePair<BallJoint>(body[p], jp, bp).second;
    }
    const Eigen::Vector3d com(0.0, 0.5 * rig.bone_length[i], 0.0);
    body[i]->setInertia(
        Inertia(rig.bone_mass[i], com, rig.bone_inertia_local[i].asDiagonal().toDenseMatrix()));
  }
  return skel;
}

void BM_DartStep(benchmark::State& state, const std::string& kind) {
  const int n = static_cast<int>(state.range(0));
  const physik::Scene scene = scaling_scene(kind, n);
  const int steps = std::clamp(20000 / n, 2, 100);
  auto world = dart::simulation::World::create();
  world->setGravity(Eigen::Vector3d::Zero());
  // 1 ms, not the scenario's dt: undamped, DART's explicit Euler at 0.05 s whips the pulled chain
  // to a non-finite state within the 100 steps; the cost of a step does not depend on its length
  world->setTimeStep(1e-3);
  dart::dynamics::SkeletonPtr skel = skeleton_of(scene.rig);
  world->addSkeleton(skel);
  const physik::ControlPoint& cp = scene.control_points.front();
  const Eigen::Vector3d pull =
      (cp.target_world - scene.rig.bone_rest_tail_world[cp.bone]).normalized() *
      cp.k.value_or(scene.params.control_k);
  dart::dynamics::BodyNode* last = skel->getBodyNode(cp.bone);
  const Eigen::Vector3d tail_local(0.0, scene.rig.bone_length[cp.bone], 0.0);
  const Eigen::VectorXd q0 = skel->getPositions(), v0 = skel->getVelocities();
  double t = 0.0;
  long count = 0;
  for (auto _ : state) {
    skel->setPositions(q0);
    skel->setVelocities(v0);
    const double t0 = thread_seconds();
    for (int k = 0; k < steps; ++k) {
      last->setExtForce(pull, tail_local, false, true);
      world->step();
    }
    t += thread_seconds() - t0;
    count += steps;
    if (!skel->getPositions().allFinite() || !skel->getVelocities().allFinite()) {
      state.SkipWithError("DART's state went non-finite");
      return;
    }
  }
  state.counters["us_per_step"] = 1e6 * t / count;
  state.counters["us_per_bone"] = 1e6 * t / count / n;
  state.counters["nbone"] = n;
}

// to 100 bones: a 10,000-body DART skeleton was not built after 18 minutes (1.4 GB), nor a run
// at 1,000 within 5
BENCHMARK_CAPTURE(BM_DartStep, chain, std::string("chain"))
    ->RangeMultiplier(10)
    ->Range(10, 100)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DartStep, tree2, std::string("tree2"))
    ->RangeMultiplier(10)
    ->Range(10, 100)
    ->Unit(benchmark::kMillisecond);

}  // namespace
