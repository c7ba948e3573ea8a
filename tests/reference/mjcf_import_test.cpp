// MJCF -> rig through MuJoCo: FK of the rig matches MuJoCo's xpos in random configurations, masses
// and inertias carry over, hinge ranges become per-axis limits, bad files are InputErrors.
#include "reference/mjcf_import.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "physik/engine/engine.h"
#include "physik/ik/ik_solver.h"
#include "physik/model/errors.h"
#include "physik/model/joint_angles.h"
#include "physik/model/kinematics.h"

namespace physik {
namespace {

// A torso (free joint) with a head, two arms (shoulder ball / hinge elbow) and a leg chain with
// hinges about x, y and z, one body welded, one zero-offset child; capsules give the leaf tips.
const char* kModel = R"(
<mujoco model="testman">
  <compiler angle="degree" autolimits="true"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 .1"/>
    <body name="torso" pos="0 0 1.5">
      <freejoint/>
      <geom type="capsule" fromto="0 0 -0.3 0 0 0.3" size="0.1"/>
      <body name="head" pos="0 0 0.4">
        <geom type="sphere" size="0.1" pos="0 0 0.1"/>
      </body>
      <body name="upper_arm" pos="0.2 0 0.25" euler="0 0 10">
        <joint name="shoulder" type="ball" range="0 60"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
        <body name="forearm" pos="0.3 0 0">
          <joint name="elbow" type="hinge" axis="0 1 0" range="-150 0"/>
          <geom type="capsule" fromto="0 0 0 0.25 0 0" size="0.035" mass="0.7"/>
        </body>
      </body>
      <body name="thigh" pos="0 -0.1 -0.35">
        <joint name="hip_x" type="hinge" axis="1 0 0" range="-30 20"/>
        <joint name="hip_y" type="hinge" axis="0 1 0" range="-90 45"/>
        <joint name="hip_z" type="hinge" axis="0 0 1" range="-10 60"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.06"/>
        <body name="shin" pos="0 0 -0.45">
          <joint name="knee" type="hinge" axis="0 -1 0" range="-160 -2"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.05"/>
          <body name="shin_twist" pos="0 0 0">
            <joint name="ankle_twist" type="hinge" axis="0 0 1"/>
            <body name="foot" pos="0 0 -0.45">
              <geom type="box" size="0.05 0.12 0.03" pos="0 0.05 0"/>
            </body>
          </body>
        </body>
      </body>
    </body>
    <body name="ball" pos="2 0 0.2">
      <freejoint/>
      <geom type="sphere" size="0.1"/>
    </body>
  </worldbody>
</mujoco>
)";

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(MjcfImport, BodiesBecomeBonesAndFkMatchesMujocoXpos) {
  const std::string path = write_temp("testman.xml", kModel);
  const MjcfRig mr = load_mjcf(path);
  const Rig& rig = mr.rig();
  EXPECT_EQ(rig.name, "testman");
  ASSERT_EQ(mr.report.skipped_bodies.size(), 1u);
  EXPECT_EQ(mr.report.skipped_bodies[0], "ball");
  EXPECT_EQ(mr.report.nbody_used, 8);
  // torso has children at 3 offsets + its own capsule is not a leaf: synthetic root "torso",
  // torso>head, torso>upper_arm, torso>thigh, head, upper_arm, forearm, thigh, shin, foot
  EXPECT_TRUE(mr.pivots.synthetic_root);
  for (const char* n : {"torso", "torso>head", "torso>upper_arm", "torso>thigh", "head",
                        "upper_arm", "forearm", "thigh", "shin_twist", "foot"}) {
    EXPECT_GE(rig.find_bone(n), 0) << n;
  }
  EXPECT_EQ(rig.nbone, 10);
  // shin_twist sits at the shin's origin: one bone from there to the foot follows shin_twist
  // (knee and twist together), the shin body has no bone of its own
  EXPECT_EQ(rig.find_bone("shin"), -1);
  EXPECT_EQ(rig.bone_parent[rig.find_bone("shin_twist")], rig.find_bone("thigh"));
  EXPECT_EQ(rig.bone_parent[rig.find_bone("foot")], rig.find_bone("shin_twist"));

  // random configurations: FK heads (and the synthetic root's tail) at every body's xpos
  MjModelPtr m(mj_loadXML(path.c_str(), nullptr, nullptr, 0));
  ASSERT_TRUE(m);
  MjDataPtr d(mj_makeData(m.get()));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    mj_resetData(m.get(), d.get());
    for (int i = 0; i < m->nq; ++i) d->qpos[i] += u(rng);
    // normalise the quaternions of the free and ball joints
    for (int j = 0; j < m->njnt; ++j) {
      const int a = m->jnt_qposadr[j] + (m->jnt_type[j] == mjJNT_FREE ? 3 : 0);
      if (m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL) mju_normalize4(d->qpos + a);
    }
    mj_kinematics(m.get(), d.get());
    const Pose pose = pose_from_mujoco(mr, d.get());
    const BoneFrames fk = forward_kinematics(rig, pose);
    double worst = 0.0;
    for (int b = 0; b < rig.nbone; ++b) {
      const int body = mr.node_body[mr.pivots.bone_node[b]];
      const Vec3 xpos(d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2]);
      const Vec3& p = (b == 0 && mr.pivots.synthetic_root) ? fk.tail_world[b] : fk.head_world[b];
      worst = std::max(worst, (p - xpos).norm());
      // and the tail at the child body it points to
      const int tn = mr.pivots.bone_tail_node[b];
      if (tn >= 0) {
        const int cb = mr.node_body[tn];
        worst = std::max(worst, (fk.tail_world[b] -
                                 Vec3(d->xpos[3 * cb], d->xpos[3 * cb + 1], d->xpos[3 * cb + 2]))
                                    .norm());
      }
    }
    EXPECT_LT(worst, 1e-9) << "trial " << trial;
  }
}

TEST(MjcfImport, MassAndInertiaCarryOver) {
  const MjcfRig mr = load_mjcf(write_temp("testman2.xml", kModel));
  const Rig& rig = mr.rig();
  MjModelPtr m(mj_loadXML((::testing::TempDir() + "testman2.xml").c_str(), nullptr, nullptr, 0));
  // masses: the subtree's total, and the forearm body (one bone) exactly
  EXPECT_NEAR(rig.total_mass(), mr.report.model_mass, 1e-12);
  EXPECT_NEAR(mr.report.rig_mass, mr.report.model_mass, 1e-12);
  const int forearm_body = mj_name2id(m.get(), mjOBJ_BODY, "forearm");
  const int fa = rig.find_bone("forearm");
  EXPECT_NEAR(rig.bone_mass[fa], m->body_mass[forearm_body], 1e-12);
  EXPECT_NEAR(m->body_mass[forearm_body], 0.7, 1e-12);
  // the forearm capsule lies along the bone (x in the body frame): MuJoCo's principal moments
  // are {axial, transverse, transverse}; the bone has the axial one about its local y
  Vec3 mi(m->body_inertia[3 * forearm_body], m->body_inertia[3 * forearm_body + 1],
          m->body_inertia[3 * forearm_body + 2]);
  std::sort(mi.data(), mi.data() + 3);  // axial is the smallest for a long capsule
  // the bone ends at the capsule's tip (0.25 + radius 0.035) while the centre of mass is at the
  // segment's middle 0.125: the midpoint is 0.0175 further out, along the bone, so the parallel-
  // axis term adds m r^2 to the two transverse moments and nothing to the axial one
  const double r = 0.5 * (0.25 + 0.035) - 0.125;
  const double steiner = 0.7 * r * r;
  EXPECT_NEAR(rig.bone_inertia_local[fa].y(), mi[0], 1e-9);
  EXPECT_NEAR(rig.bone_inertia_local[fa].x(), mi[2] + steiner, 1e-9);
  EXPECT_NEAR(rig.bone_inertia_local[fa].z(), mi[2] + steiner, 1e-9);
  // the shared torso body is split over four bones
  const int torso_body = mj_name2id(m.get(), mjOBJ_BODY, "torso");
  EXPECT_NEAR(rig.bone_mass[rig.find_bone("torso>head")], m->body_mass[torso_body] / 4, 1e-12);
}

// Capsule geoms give the bones' radii, in the model's lengths: the capsule of the bone's body, or
// of a body at its head (the shin's for the bone that follows the zero-offset shin_twist); a body
// with only a sphere (the head) gives the sphere's; a bone with neither (the foot's box) gets
// kRadiusPerLength x its length (rig_sizing.h) for both, and is reported.
TEST(MjcfImport, CapsuleRadiiBecomeBoneRadii) {
  const MjcfRig mr = load_mjcf(write_temp("testman_radii.xml", kModel));
  const Rig& rig = mr.rig();
  const std::vector<std::pair<std::string, double>> want = {
      {"torso", 0.1},     {"torso>head", 0.1}, {"torso>thigh", 0.1}, {"upper_arm", 0.04},
      {"forearm", 0.035}, {"thigh", 0.06},     {"shin_twist", 0.05}, {"head", 0.1}};
  for (const auto& [name, r] : want) {
    const int b = rig.find_bone(name);
    ASSERT_GE(b, 0) << name;
    EXPECT_DOUBLE_EQ(rig.bone_collision_radius[b], r) << name;
    EXPECT_DOUBLE_EQ(rig.bone_radius[b], r) << name;
  }
  EXPECT_EQ(mr.report.bones_fitted_radius, std::vector<std::string>{"foot"});
  const int foot = rig.find_bone("foot");
  EXPECT_DOUBLE_EQ(rig.bone_radius[foot], kRadiusPerLength * rig.bone_length[foot]);
  EXPECT_EQ(rig.bone_collision_radius[foot], rig.bone_radius[foot]);
}

TEST(MjcfImport, LimitsCarryOver) {
  const MjcfRig mr = load_mjcf(write_temp("testman2.xml", kModel));
  const Rig& rig = mr.rig();
  MjModelPtr m(mj_loadXML((::testing::TempDir() + "testman2.xml").c_str(), nullptr, nullptr, 0));
  const int forearm_body = mj_name2id(m.get(), mjOBJ_BODY, "forearm");
  const int fa = rig.find_bone("forearm");
  // elbow: hinge about body y, perpendicular to the bone (along body x) -> local x, [-150, 0];
  // the rest angle 0 is inside its torsion band (0.1 of the range from each end), so the max is
  // widened until the band ends at rest: 150 x 0.1 / 0.9 deg (rest_limits.h)
  EXPECT_TRUE(rig.bone_limit[fa][0].limited);
  EXPECT_NEAR(rad2deg(rig.bone_limit[fa][0].min), -150, 1e-9);
  EXPECT_NEAR(rad2deg(rig.bone_limit[fa][0].max), 150 * 0.1 / 0.9, 1e-6);
  EXPECT_TRUE(rig.bone_limit[fa][1].locked());
  EXPECT_TRUE(rig.bone_limit[fa][2].locked());
  EXPECT_EQ(rig.bone_dof(fa), 1);
  // the local x axis of the forearm is the hinge axis in the world
  const Vec3 x_world = rig.bone_rest_orient_world[fa] * Vec3::UnitX();
  MjDataPtr d(mj_makeData(m.get()));
  mj_kinematics(m.get(), d.get());
  const mjtNum* xm = d->xmat + 9 * forearm_body;
  EXPECT_NEAR(std::abs(x_world.dot(Vec3(xm[1], xm[4], xm[7]))), 1.0, 1e-9);
  // thigh: three hinges, the bone along -z: hip_z maps to local y (anti-parallel: range flipped)
  const int th = rig.find_bone("thigh");
  EXPECT_EQ(rig.bone_dof(th), 3);
  EXPECT_NEAR(rad2deg(rig.bone_limit[th][1].min), -60, 1e-9);
  EXPECT_NEAR(rad2deg(rig.bone_limit[th][1].max), 10, 1e-9);
  // knee (hinge about -y, first hinge -> local x, range kept) and the unlimited twist about the
  // bone (local y, free) both drive the shin_twist bone; z stays locked
  const int sh = rig.find_bone("shin_twist");
  EXPECT_EQ(rig.bone_dof(sh), 2);
  EXPECT_NEAR(rad2deg(rig.bone_limit[sh][0].min), -160, 1e-9);
  EXPECT_NEAR(rad2deg(rig.bone_limit[sh][0].max), 160 * 0.1 / 0.9, 1e-6);  // -2, widened
  EXPECT_EQ(mr.report.widened_limits,
            (std::vector<std::string>{"forearm x: [-150, 0] -> [-150, 16.67] deg",
                                      "shin_twist x: [-160, -2] -> [-160, 17.78] deg"}));
  EXPECT_FALSE(rig.bone_limit[sh][1].limited);
  EXPECT_TRUE(rig.bone_limit[sh][2].locked());
  // the shin's mass goes to the bone that starts at its origin
  const int shin_body = mj_name2id(m.get(), mjOBJ_BODY, "shin");
  EXPECT_NEAR(rig.bone_mass[sh], m->body_mass[shin_body], 1e-12);
  // shoulder ball limited to a 60 deg cone -> every axis [-60, 60]
  const int ua = rig.find_bone("upper_arm");
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(rad2deg(rig.bone_limit[ua][a].max), 60, 1e-9);
  // the foot hangs off a zero-offset twist body: the foot bone follows the foot body, welded
  EXPECT_EQ(rig.bone_dof(rig.find_bone("foot")), 0);
  EXPECT_EQ(mr.report.slide_joints_dropped, 0);
}

// A body whose centre of mass is off the bone: explicit inertial (pos, mass, diaginertia in the
// body frame, which is the world frame here), bone from the body origin to the child at -z.
const char* kOffsetModel = R"(
<mujoco model="offset">
  <worldbody>
    <body name="link" pos="0 0 2">
      <joint name="hinge" type="hinge" axis="1 0 0"/>
      <inertial pos="0.1 0.2 -0.3" mass="2" diaginertia="0.05 0.06 0.07"/>
      <body name="tip" pos="0 0 -1">
        <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
        <geom type="sphere" size="0.1" mass="0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
)";

TEST(MjcfImport, InertiaIsCarriedToTheBoneMidpointWithTheParallelAxisTerm) {
  const MjcfRig mr = load_mjcf(write_temp("offset.xml", kOffsetModel));
  const Rig& rig = mr.rig();
  const int link = rig.find_bone("link");
  ASSERT_GE(link, 0);
  // bone from (0,0,2) to (0,0,1): local y = -z world; the hinge about world x is local x, so
  // local z = x cross y = +y world
  const Mat3 frame = rig.bone_rest_orient_world[link].toRotationMatrix();
  EXPECT_NEAR(frame.col(0).dot(Vec3::UnitX()), 1.0, 1e-12);
  EXPECT_NEAR(frame.col(1).dot(-Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_NEAR(frame.col(2).dot(Vec3::UnitY()), 1.0, 1e-12);
  // r = midpoint (0,0,1.5) - com (0.1,0.2,1.7) = (-0.1,-0.2,-0.2); m = 2
  //   world Ixx = 0.05 + 2 (ry^2 + rz^2) = 0.05 + 2 (0.04 + 0.04) = 0.21
  //   world Iyy = 0.06 + 2 (rx^2 + rz^2) = 0.06 + 2 (0.01 + 0.04) = 0.16
  //   world Izz = 0.07 + 2 (rx^2 + ry^2) = 0.07 + 2 (0.01 + 0.04) = 0.17
  // local (x, y, z) = world (x, -z, y)
  EXPECT_NEAR(rig.bone_mass[link], 2.0, 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[link].x(), 0.21, 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[link].y(), 0.17, 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[link].z(), 0.16, 1e-12);
  // dropped products of inertia: -m r r^T, largest |-2 ry rz| = 0.08, relative to 0.21
  // (the tip body's COM lies on its bone axis: no product of inertia there)
  EXPECT_NEAR(mr.report.max_offdiag_inertia, 0.08 / 0.21, 1e-12);
  EXPECT_NEAR(mr.report.max_com_shift, 0.3, 1e-12);
  // tip: a leaf bone from its origin 0.1 (the sphere) along -z: r = 0.05 along the bone
  const int tip = rig.find_bone("tip");
  ASSERT_GE(tip, 0);
  EXPECT_NEAR(rig.bone_inertia_local[tip].x(), 0.01 + 1.0 * 0.05 * 0.05, 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[tip].y(), 0.01, 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[tip].z(), 0.01 + 1.0 * 0.05 * 0.05, 1e-12);
}

TEST(MjcfImport, RootBodyCanBeChosenAndBadInputIsAnInputError) {
  const std::string path = write_temp("testman3.xml", kModel);
  MjcfImportOptions o;
  o.root_body = "ball";
  const MjcfRig ball = load_mjcf(path, o);
  EXPECT_EQ(ball.rig().nbone, 1);
  o.root_body = "nobody";
  EXPECT_THROW(load_mjcf(path, o), InputError);
  const std::string bad = write_temp("bad.xml", "<mujoco><worldbody><body></worldbody></mujoco>");
  try {
    load_mjcf(bad);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.xml: MuJoCo cannot load it"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_mjcf(::testing::TempDir() + "missing.xml"), InputError);
  const std::string empty = write_temp("empty.xml", "<mujoco><worldbody/></mujoco>");
  EXPECT_THROW(load_mjcf(empty), InputError);
}

}  // namespace
}  // namespace physik

namespace physik {
namespace {

// A body is one rigid body: the torso's segments (to the head, the arm and the thigh) are welded
// to the synthetic root that follows the torso; a jointless body's bone is welded to its parent;
// a body's joint limits sit on one bone, not one copy per segment
TEST(MjcfImport, ABodyWithSeveralChildrenIsOneRigidBody) {
  const MjcfRig mr = load_mjcf(write_temp("testman3.xml", kModel));
  const Rig& rig = mr.rig();
  EXPECT_EQ(rig.root_joint, RootJoint::kFree);
  int torso_segments = 0;
  for (int b = 1; b < rig.nbone; ++b) {
    if (rig.bone_name[b].rfind("torso>", 0) != 0) continue;
    ++torso_segments;
    EXPECT_EQ(rig.bone_body[b], 0) << rig.bone_name[b];
    EXPECT_EQ(rig.bone_dof(b), 0) << rig.bone_name[b];
  }
  EXPECT_EQ(torso_segments, 3);
  EXPECT_EQ(rig.bone_joint_type[rig.find_bone("foot")], JointType::kWeld);
  for (int b = 0; b < rig.nbone; ++b) {
    if (!rig.welded(b)) continue;
    for (const AxisLimit& l : rig.bone_limit[b]) EXPECT_FALSE(l.limited) << rig.bone_name[b];
  }
}

// MuJoCo's arm26: the shoulder is a hinge to the world, so the rig's root is pinned at its head,
// a hinge (one free axis), and a pull moves the arm without moving the shoulder
TEST(MjcfImport, ARootHingedToTheWorldStaysHinged) {
  const std::string path = "/usr/share/mujoco/model/tendon_arm/arm26.xml";
  if (!std::ifstream(path)) GTEST_SKIP() << path << " not installed (libmujoco-samples)";
  const MjcfRig mr = load_mjcf(path);
  const Rig& rig = mr.rig();
  EXPECT_EQ(rig.root_joint, RootJoint::kPinned);
  EXPECT_EQ(mr.report.root_joint, "pinned");
  EXPECT_EQ(rig.bone_dof(0), 1);
  EXPECT_EQ(rig.bone_joint_type[0], JointType::kHinge);
  EXPECT_LE((rig.bone_rest_head_world[0] - Vec3::Zero()).norm(), 1e-12);  // the shoulder
}

// The same arm pulled out of its plane (DLS used to "converge" with the shoulder 33 and 66
// degrees past its locked axes, and every summary said 0 degrees of violation): every classic
// solver keeps the shoulder a hinge, and the measure counts the root. The hinges turn about z, so
// the target (0.6, 0.4, 0.5) is 0.5 from the arm's plane z = 0: no pose within the limits
// reaches it.
TEST(MjcfImport, ClassicSolversKeepArm26sShoulderAHinge) {
  const std::string path = "/usr/share/mujoco/model/tendon_arm/arm26.xml";
  if (!std::ifstream(path)) GTEST_SKIP() << path << " not installed (libmujoco-samples)";
  const Rig rig = load_mjcf(path).rig();
  ASSERT_EQ(rig.root_joint, RootJoint::kPinned);
  const Vec3 normal = rig.bone_rest_orient_world[0] * Vec3::UnitX();  // the shoulder's axis
  ASSERT_NEAR(std::abs(normal.z()), 1.0, 1e-9);
  // the measure: the shoulder turned 0.2 rad about a locked axis reads 0.2 rad
  Pose off = rest_pose(rig);
  off.bone_local_rotation[0] = Quat(Eigen::AngleAxisd(0.2, Vec3::UnitZ()));
  EXPECT_NEAR(max_limit_violation(rig, LockedAxes::kSprings, off), 0.2, 1e-12);
  const int hand = rig.find_bone("body2");
  const Vec3 target(0.6, 0.4, 0.5);
  for (const IkMethod m :
       {IkMethod::kDampedLeastSquares, IkMethod::kJacobianTranspose, IkMethod::kCcd,
        IkMethod::kFabrik, IkMethod::kMassSpring, IkMethod::kRotation}) {
    SCOPED_TRACE(to_string(m));
    Pose pose = rest_pose(rig);
    const IkReport rep = solve_ik(m, rig, {{hand, 1.0, target}}, pose);
    EXPECT_LE(max_limit_violation(rig, LockedAxes::kSprings, pose), 1e-9);
    EXPECT_FALSE(rep.converged);
    EXPECT_GE(rep.residual, 0.5 - 1e-9);
  }
}

// arm26's shoulder and elbow are hinges about parallel axes: pulled out of its plane, the arm
// stays in it in the exact and implicit schemes (rig.h "Locked axes": the locked axes are not in
// the coordinates) to round-off; the paper's scheme holds them with torsion springs, which give
// under the pull
TEST(MjcfImport, Arm26StaysInItsPlaneUnderAPullOutOfIt) {
  const std::string path = "/usr/share/mujoco/model/tendon_arm/arm26.xml";
  if (!std::ifstream(path)) GTEST_SKIP() << path << " not installed (libmujoco-samples)";
  const Rig rig = load_mjcf(path).rig();
  ASSERT_EQ(rig.bone_joint_type[0], JointType::kHinge);
  // the plane: through the shoulder, normal to the shoulder's hinge axis at rest
  const Vec3 normal = rig.bone_rest_orient_world[0] *
                      (rig.bone_joint_lock[0] * Vec3::Unit(rig.bone_joint_axes[0][0]));
  const Vec3 origin = rig.bone_rest_head_world[0];
  double size = 0.0;
  for (int i = 0; i < rig.nbone; ++i) {
    size = std::max(size, (rig.bone_rest_tail_world[i] - origin).norm());
    ASSERT_LT(std::abs(normal.dot(rig.bone_rest_tail_world[i] - origin)), 1e-9 * size);
  }
  const int tip = rig.nbone - 1;
  for (const char* scheme : {"exact", "implicit", "gauss-seidel"}) {
    Scene sc;
    sc.file = "<arm26>";
    sc.rig = rig;
    sc.params = preset_params("original");
    sc.params.scheme = scheme == std::string("exact")      ? Scheme::kExact
                       : scheme == std::string("implicit") ? Scheme::kImplicit
                                                           : Scheme::kGaussSeidel;
    sc.steps = 300;
    sc.convergence.stop_when_converged = false;
    sc.initial_pose = rest_pose(rig);
    ControlPoint c;
    c.bone = tip;
    c.alpha = 1.0;
    c.target_world = rig.bone_rest_tail_world[tip] + 0.5 * size * normal;  // out of the plane
    c.k = 10.0 * rig.total_mass();
    sc.control_points.push_back(c);
    double off_plane = 0.0;
    const RunSummary r = run_scene(sc, [&](const SimState& s, const StepStats&) {
      for (int i = 0; i < rig.nbone; ++i) {
        off_plane = std::max(off_plane, std::abs(normal.dot(s.frames.tail_world[i] - origin)));
      }
    });
    std::cout << "[arm26] " << scheme << ": largest distance from the arm's plane "
              << off_plane / size << " of its size\n";
    if (sc.params.scheme == Scheme::kGaussSeidel) {
      EXPECT_GT(off_plane, 1e-3 * size) << "the paper's torsion springs give";
    } else {
      ASSERT_FALSE(r.diverged) << scheme;
      EXPECT_LT(off_plane, 1e-12 * size) << scheme;
    }
  }
}

}  // namespace
}  // namespace physik
