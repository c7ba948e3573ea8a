// Orocos KDL on a scene's goals: see kdl_solve.h.
#include "kdl/kdl_solve.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_wdls.hpp>

#include "physik/engine/measures.h"
#include "physik/model/errors.h"

namespace physik::kdl {

namespace {

// What the chain solves: its tip bone and point, the goal frame, which rows count.
struct TipGoal {
  int bone = -1;
  double alpha = 1.0;  // 1 (the tail) when only an orientation target is on the tip
  bool position = false, orientation = false;
  Vec3 target_world = Vec3::Zero();
  Quat orientation_world = Quat::Identity();
};

// One joint of the chain: its bone and its axis (0 x, 1 y, 2 z of the bone's rest frame).
struct ChainJoint {
  int bone, axis;
};

struct KdlChain {
  KDL::Chain chain;
  std::vector<ChainJoint> joints;  // (nj) in the chain's order
};

KDL::Rotation kdl_rotation(const Quat& q) {
  return KDL::Rotation::Quaternion(q.x(), q.y(), q.z(), q.w());
}
KDL::Vector kdl_vector(const Vec3& v) {
  return KDL::Vector(v.x(), v.y(), v.z());
}

[[noreturn]] void refuse(const Scene& scene, const std::string& field, const std::string& why) {
  throw_input_error(scene.file, field, "", "--solver kdl and kdl-nr " + why);
}

// a control point the chain's fixed base holds: on the root bone's head at its rest position
bool held_by_base(const Scene& scene, const ControlPoint& c, const Vec3& target) {
  return c.bone == 0 && c.alpha == 0.0 &&
         (target - scene.rig.bone_rest_head_world[0]).norm() <= 1e-12 * scene.rig.height();
}

// The tip and its goals, or InputError for what one chain cannot take (kdl_solve.h).
TipGoal tip_goal(const Scene& scene) {
  if (const char* field = scene.world_field()) {
    const std::string f = field;
    if (f != "orientation_targets" && f != "aim_targets" && f != "pins") {
      refuse(scene, f, "solve the rig's geometry and its goals only (--solver physik reads it)");
    }
  }
  if (!scene.aim_targets.empty()) {
    refuse(scene, "aim_targets", "take no aims (the engine does: --solver physik)");
  }
  if (!scene.pins.empty()) refuse(scene, "pins", "take no pins (dls and the engine do)");
  TipGoal tip;
  const std::vector<IkGoal> goals = scene_goals(scene);
  const auto take = [&](int bone, const char* field) {
    if (tip.bone >= 0 && tip.bone != bone) {
      refuse(scene, field,
             "solve one chain: their goals must be on one bone (here '" +
                 scene.rig.bone_name[tip.bone] + "' and '" + scene.rig.bone_name[bone] +
                 "'), besides control points holding the root's head where it is");
    }
    tip.bone = bone;
  };
  for (std::size_t c = 0; c < scene.control_points.size(); ++c) {
    const ControlPoint& cp = scene.control_points[c];
    if (held_by_base(scene, cp, goals[c].target_world)) continue;
    take(cp.bone, "control_points");  // goals on two bones first: the likelier fault
    if (tip.position) {
      refuse(scene, "control_points", "take one position goal on the tip (the scene has more)");
    }
    tip.position = true;
    tip.alpha = cp.alpha;
    tip.target_world = goals[c].target_world;
  }
  for (const OrientationTarget& t : scene.orientation_targets) {
    if (tip.orientation) refuse(scene, "orientation_targets", "take one orientation target");
    take(t.bone, "orientation_targets");
    tip.orientation = true;
    tip.orientation_world = t.target_world;
  }
  if (tip.bone < 0) {
    refuse(scene, "control_points",
           "need a goal off the root's head (a control point or an orientation target)");
  }
  if (!tip.position) tip.target_world = Vec3::Zero();
  return tip;
}

// the bones from the root to the tip, root first
std::vector<int> chain_bones(const Rig& rig, int tip) {
  std::vector<int> bones;
  for (int b = tip; b >= 0; b = rig.bone_parent[b]) bones.insert(bones.begin(), b);
  return bones;
}

bool locked_at_zero(const AxisLimit& l) {
  return l.limited && l.min == 0.0 && l.max == 0.0;
}

KdlChain build_chain(const Scene& scene, const TipGoal& tip) {
  const Rig& rig = scene.rig;
  KdlChain out;
  for (int i : chain_bones(rig, tip.bone)) {
    if (rig.bone_weld[i] >= 0 && rig.bone_weld[i] != rig.bone_parent[i]) {
      refuse(scene, "rig",
             "solve a chain of bones each turning at its parent's tail; '" + rig.bone_name[i] +
                 "' is welded to a sibling");
    }
    const Vec3 head = i == 0 ? rig.bone_rest_head_world[0] : rig.bone_head_in_parent[i];
    out.chain.addSegment(
        KDL::Segment(KDL::Joint(KDL::Joint::None),
                     KDL::Frame(kdl_rotation(rig.bone_rest_orient_parent[i]), kdl_vector(head))));
    if (rig.welded(i)) continue;
    const KDL::Joint::JointType types[3] = {KDL::Joint::RotX, KDL::Joint::RotY, KDL::Joint::RotZ};
    for (int a = 0; a < 3; ++a) {
      if (locked_at_zero(rig.bone_limit[i][a])) continue;
      out.chain.addSegment(KDL::Segment(KDL::Joint(types[a])));
      out.joints.push_back({i, a});
    }
  }
  out.chain.addSegment(
      KDL::Segment(KDL::Joint(KDL::Joint::None),
                   KDL::Frame(KDL::Vector(0.0, tip.alpha * rig.bone_length[tip.bone], 0.0))));
  return out;
}

// the start: each chain bone's local rotation of the scene's initial pose as Rx Ry Rz angles
// (the axes without a joint dropped)
KDL::JntArray start_angles(const Scene& scene, const KdlChain& kc) {
  KDL::JntArray q(static_cast<unsigned>(kc.joints.size()));
  for (std::size_t j = 0; j < kc.joints.size(); ++j) {
    const ChainJoint& cj = kc.joints[j];
    const Vec3 xyz =
        scene.initial_pose.bone_local_rotation[cj.bone].toRotationMatrix().eulerAngles(0, 1, 2);
    q(static_cast<unsigned>(j)) = xyz[cj.axis];
  }
  return q;
}

// the pose of the joint angles: the scene's initial pose with each chain bone's local rotation
// Rx Ry Rz of its angles
Pose pose_of(const Scene& scene, const KdlChain& kc, const KDL::JntArray& q) {
  Pose pose = scene.initial_pose;
  std::vector<Vec3> angles(scene.rig.nbone, Vec3::Zero());
  std::vector<char> in_chain(scene.rig.nbone, 0);
  for (std::size_t j = 0; j < kc.joints.size(); ++j) {
    angles[kc.joints[j].bone][kc.joints[j].axis] = q(static_cast<unsigned>(j));
    in_chain[kc.joints[j].bone] = 1;
  }
  for (int b = 0; b < scene.rig.nbone; ++b) {
    if (!in_chain[b]) continue;
    pose.bone_local_rotation[b] = Quat(Eigen::AngleAxisd(angles[b].x(), Vec3::UnitX()) *
                                       Eigen::AngleAxisd(angles[b].y(), Vec3::UnitY()) *
                                       Eigen::AngleAxisd(angles[b].z(), Vec3::UnitZ()));
  }
  return pose;
}

// NR_JL's forward kinematics for a tip without a position or an orientation goal: the ignored
// part of the frame is the target's, so that its stop test (every twist component within eps)
// reads the goals' rows alone; it counts its calls (NR_JL's iterations, plus its last check)
class PartialFk : public KDL::ChainFkSolverPos {
 public:
  PartialFk(const KDL::Chain& chain, const TipGoal& tip, const KDL::Frame& goal)
      : fk_(chain), tip_(tip), goal_(goal) {}
  int JntToCart(const KDL::JntArray& q, KDL::Frame& out, int segment = -1) override {
    ++calls;
    const int status = fk_.JntToCart(q, out, segment);
    if (!tip_.orientation) out.M = goal_.M;
    if (!tip_.position) out.p = goal_.p;
    return status;
  }
  int JntToCart(const KDL::JntArray& q, std::vector<KDL::Frame>& out, int segment = -1) override {
    return fk_.JntToCart(q, out, segment);
  }
  void updateInternalDataStructures() override { fk_.updateInternalDataStructures(); }
  int calls = 0;

 private:
  KDL::ChainFkSolverPos_recursive fk_;
  TipGoal tip_;
  KDL::Frame goal_;
};

constexpr double kWdlsLambda = 1e-3;  // wdls's damping of its near-zero singular values

struct Tolerances {
  double position = 0.0, angle = 0.0;  // rig units, rad
};

// one solve of the chain from q0 by `solver` (kdl or kdl-nr); q gets the result; returns the
// iterations and sets `seconds` to CartToJnt's time
int run_kdl(const Scene& scene, const SceneSolveOptions& o, const KdlChain& kc, const TipGoal& tip,
            const Tolerances& tol, KDL::JntArray& q, double& seconds) {
  const KDL::Frame goal(kdl_rotation(tip.orientation_world), kdl_vector(tip.target_world));
  const double wp = tip.position ? 1.0 : 0.0;
  const double wr = tip.orientation ? tol.position / tol.angle : 0.0;
  const KDL::JntArray q0 = q;
  using Clock = std::chrono::steady_clock;
  if (o.solver == "kdl") {
    Eigen::Matrix<double, 6, 1> weights;
    weights << wp, wp, wp, wr, wr, wr;
    KDL::ChainIkSolverPos_LMA lma(kc.chain, weights, tol.position, o.max_iterations, 1e-15);
    const auto t0 = Clock::now();
    lma.CartToJnt(q0, goal, q);
    seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return lma.lastNrOfIter;
  }
  const unsigned nj = kc.chain.getNrOfJoints();
  // KDL's weighted-damped velocity solver (ChainIkSolverVel_wdls) takes blocks of its 6 x nj
  // Jacobian's SVD that do not exist below 6 joint axes (an Eigen assertion, an abort): a goal
  // near the root (pinhead's torso: 5 axes) is refused rather than crashed on
  if (nj < 6) {
    throw_input_error(scene.file, "solver", "",
                      "--solver kdl-nr needs at least 6 joint axes from the root to the goal's "
                      "bone (KDL's wdls velocity solver); this chain has " +
                          std::to_string(nj) + ": use --solver kdl (Levenberg-Marquardt) or dls");
  }
  KDL::JntArray q_min(nj), q_max(nj);
  for (unsigned j = 0; j < nj; ++j) {
    const AxisLimit& l = scene.rig.bone_limit[kc.joints[j].bone][kc.joints[j].axis];
    const bool limited = l.limited && !o.no_limits;
    q_min(j) = limited ? l.min : -std::numeric_limits<double>::infinity();
    q_max(j) = limited ? l.max : std::numeric_limits<double>::infinity();
  }
  PartialFk fk(kc.chain, tip, goal);
  KDL::ChainIkSolverVel_wdls vel(kc.chain);
  Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(6, 6);
  weights.diagonal() << wp, wp, wp, wr, wr, wr;
  vel.setWeightTS(weights);
  // The weighted Jacobian's zero rows (a goal's ignored rows) give zero singular values, which
  // wdls divides as S / (S^2 + lambda^2): its default lambda 0 makes that 0/0, NaN. Any lambda > 0
  // makes them 0; it damps only singular values below wdls's eps (1e-5), scaled from 0 there.
  vel.setLambda(kWdlsLambda);
  // NR_JL's stop: every component of the twist error within eps (the norm within sqrt(3) eps)
  const double eps =
      std::min(tip.position ? tol.position : HUGE_VAL, tip.orientation ? tol.angle : HUGE_VAL) /
      std::sqrt(3.0);
  KDL::ChainIkSolverPos_NR_JL nr(kc.chain, q_min, q_max, fk, vel, o.max_iterations, eps);
  const auto t0 = Clock::now();
  nr.CartToJnt(q0, goal, q);
  seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return std::max(fk.calls - 1, 0);
}

// the classic report of the solved pose: every control point's and orientation target's
// residual (rig units, rad), the tolerances, converged by each goal's own measure
IkReport report_of(const Scene& scene, const BoneFrames& frames, const Tolerances& tol,
                   int iterations, double reach) {
  IkReport rep;
  rep.iterations = iterations;
  rep.tolerance = tol.position;
  rep.orientation_tolerance = tol.angle;
  rep.reach = reach;
  const std::vector<IkGoal> goals = scene_goals(scene);
  std::vector<Vec3> targets;
  for (const IkGoal& g : goals) targets.push_back(g.target_world);
  rep.converged = true;
  for (int g = 0; g < goal_count(scene); ++g) {
    const GoalRef ref = goal_ref(scene, g);
    const double r = goal_residual(scene, frames, targets, g);
    rep.converged =
        rep.converged && r <= (ref.kind == GoalKind::kControlPoint ? tol.position : tol.angle);
    if (ref.kind == GoalKind::kControlPoint) {
      rep.residuals.push_back(r);
      rep.residual = std::max(rep.residual, r);
    } else {
      rep.orientation_residuals.push_back(r);
      rep.orientation_residual = std::max(rep.orientation_residual, r);
    }
  }
  return rep;
}

}  // namespace

SceneSolveResult solve_scene_kdl(const Scene& scene, const SceneSolveOptions& o) {
  check_solve_options(o);
  const TipGoal tip = tip_goal(scene);
  const KdlChain kc = build_chain(scene, tip);
  const double reach = scene.rig.chain_length(tip.bone, 1.0);
  const Tolerances tol{o.tol > 0.0 ? o.tol : 1e-4 * reach, o.tol_angle};
  KDL::JntArray q = start_angles(scene, kc);
  double seconds = 0.0;
  const int iterations = run_kdl(scene, o, kc, tip, tol, q, seconds);
  SceneSolveResult r;
  r.solver = o.solver;
  r.scene = scene;
  r.pose = pose_of(scene, kc, q);
  r.frames = forward_kinematics(scene.rig, r.pose);
  r.classic = report_of(scene, r.frames, tol, iterations, reach);
  r.classic.solver = o.solver;
  r.classic.time_s = seconds;
  r.classic.stalled = !r.classic.converged && iterations < o.max_iterations;
  r.time_s = seconds;
  return r;
}

void register_solvers() {
  register_outside_solver("kdl", solve_scene_kdl);
  register_outside_solver("kdl-nr", solve_scene_kdl);
}

}  // namespace physik::kdl
