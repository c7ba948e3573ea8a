// The human body inside a converted skeleton (physik/model/human_body.h, human_template.h;
// physik/io/skeleton_names.h, bvh_body.h): the joint-name table recognises the common conventions,
// the published tables give the masses and ranges, the anatomical frames put a hinge's axis across
// the limb however the skeleton stands at rest, the pelvis is one rigid body, the unit rule names
// the scale of CMU's unit, inches, decimetres, centimetres and millimetres, and every bad input is
// refused with its option, field and nearest name. The skeletons are experiments/
// human_skeletons.h's.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "experiments/human_skeletons.h"
#include "physik/io/bvh.h"
#include "physik/io/joint_limits.h"
#include "physik/io/rig_io.h"
#include "physik/io/scene_io.h"
#include "physik/io/skeleton_names.h"
#include "physik/model/bone_targets.h"
#include "physik/model/errors.h"
#include "physik/model/human_body.h"
#include "physik/model/kinematics.h"
#include "tests/test_util.h"

namespace physik {
namespace {

namespace hs = experiments::human_skeletons;

BvhAnimation human(const BvhFile& clip, BvhAxes axes, double scale, double total_mass = 0.0) {
  BvhImportOptions o;
  o.axes = axes;
  o.scale = scale;
  o.body = BodyKind::kAuto;
  o.sizing.total_mass = total_mass;
  return bvh_to_rig(clip, "clip.bvh", o);
}

BvhAnimation human(const hs::Shape& shape) {
  return human(shape.clip(6), shape.axes, shape.scale);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

int bone(const Rig& rig, const std::string& name) {
  const int b = rig.find_bone(name);
  EXPECT_GE(b, 0) << name;
  return b;
}

// the first bone of a segment
int bone_of_segment(const Rig& rig, const std::string& segment) {
  for (int b = 0; b < rig.nbone; ++b) {
    if (rig.bone_segment[b] == segment) return b;
  }
  ADD_FAILURE() << "no bone of segment " << segment;
  return 0;
}

// --- the tables -----------------------------------------------------------------------------

TEST(HumanTemplate, DeLevaSharesMakeTheWholeBody) {
  double sum = 0.0;
  for (int r = 0; r < static_cast<int>(LevaSegment::kCount); ++r) {
    const LevaRow& row = leva_row(static_cast<LevaSegment>(r));
    sum += row.mass_share * (static_cast<LevaSegment>(r) >= LevaSegment::kUpperArm ? 2 : 1);
    EXPECT_GT(row.com, 0.0);
    EXPECT_LT(row.com, 1.0);
    // a real body's principal moments obey the triangle inequality
    EXPECT_GE(row.r_sagittal * row.r_sagittal + row.r_transverse * row.r_transverse,
              row.r_long * row.r_long);
  }
  EXPECT_NEAR(sum, 1.0, 1e-4);  // de Leva's males: 100.00 %
}

TEST(HumanTemplate, RangesMirrorAndHingesLockTwoAxes) {
  for (const TemplateSegment& s : human_segments()) {
    for (const auto& r : s.range_deg) EXPECT_LE(r[0], r[1]) << s.name;
    int locked = 0;
    for (const auto& r : s.range_deg) locked += r[0] == r[1] ? 1 : 0;
    const int want = s.kind == JointKind::kHinge     ? 2
                     : s.kind == JointKind::kTwoAxis ? 1
                     : s.kind == JointKind::kBall    ? 0
                                                     : 3;
    EXPECT_EQ(locked, want) << s.name;
    EXPECT_NEAR(s.x0.dot(s.d0), 0.0, 1e-12) << s.name;
    if (s.side >= 0) continue;
    const TemplateSegment& l =
        human_segments()[human_segment_index(s.name.substr(0, s.name.size() - 2) + ".L")];
    // mirrored: x and y negated, z kept (human_template.h "Frames")
    EXPECT_EQ(s.range_deg[0][0], -l.range_deg[0][1]) << s.name;
    EXPECT_EQ(s.range_deg[1][1], -l.range_deg[1][0]) << s.name;
    EXPECT_EQ(s.range_deg[2], l.range_deg[2]) << s.name;
  }
  EXPECT_EQ(human_segment_index("thigh.L") >= 0 && human_segment_index("knee") < 0, true);
}

// --- the joint-name table -------------------------------------------------------------------

TEST(SkeletonNames, TheTableLoadsAndNormalises) {
  const NameTable& t = default_name_table();
  EXPECT_GE(t.conventions.size(), 8u);
  EXPECT_EQ(normalise_joint_name("mixamorig:Left_Fore-Arm.L"), "leftforearml");
  EXPECT_EQ(normalise_joint_name("LeftForeArm"), "leftforearm");
}

TEST(SkeletonNames, EachShapeIsRecognisedByItsConvention) {
  for (const hs::Shape& shape : hs::shapes()) {
    const BvhAnimation a = human(shape);
    EXPECT_TRUE(a.body.human) << shape.name;
    EXPECT_EQ(a.body.match.convention, shape.expected) << shape.name;
    EXPECT_TRUE(a.body.match.missing.empty()) << shape.name;
  }
  // OptiTrack's asset prefix is taken off
  EXPECT_EQ(human(hs::shapes()[3]).body.match.prefix, "Skeleton1_");
}

// the joint names the conventions publish, the root first (only names: match_skeleton reads no
// hierarchy); each is recognised by its own convention and names its knee and its upper arm
struct PublishedNames {
  std::string convention;
  std::vector<std::string> joints;
  std::string knee, upper_arm;  // the left shank's and upper arm's joints
};

std::vector<PublishedNames> published_names() {
  return {
      // SMPL's 24 joints (SMPL's J_regressor order)
      {"SMPL",
       {"Pelvis",  "L_Hip",    "R_Hip",    "Spine1",  "L_Knee",     "R_Knee",
        "Spine2",  "L_Ankle",  "R_Ankle",  "Spine3",  "L_Foot",     "R_Foot",
        "Neck",    "L_Collar", "R_Collar", "Head",    "L_Shoulder", "R_Shoulder",
        "L_Elbow", "R_Elbow",  "L_Wrist",  "R_Wrist", "L_Hand",     "R_Hand"},
       "L_Knee",
       "L_Shoulder"},
      // three.js's pirouette.bvh (Poser's names)
      {"three.js / Poser / DAZ",
       {"hip",     "abdomen",  "chest",    "neck",    "head",    "leftEye",  "rightEye",
        "rCollar", "rShldr",   "rForeArm", "rHand",   "rThumb1", "rIndex1",  "lCollar",
        "lShldr",  "lForeArm", "lHand",    "lThumb1", "lIndex1", "rButtock", "rThigh",
        "rShin",   "rFoot",    "lButtock", "lThigh",  "lShin",   "lFoot"},
       "lShin",
       "lShldr"},
      // Biovision's BVH example
      {"Biovision",
       {"Hips", "LeftUpLeg", "LeftLowLeg", "LeftFoot", "RightUpLeg", "RightLowLeg", "RightFoot",
        "Chest", "LeftCollar", "LeftUpArm", "LeftLowArm", "LeftHand", "RightCollar", "RightUpArm",
        "RightLowArm", "RightHand", "Neck", "Head"},
       "LeftLowLeg",
       "LeftUpArm"},
      // Vicon Plug-in Gait's segments, with a subject prefix
      {"Vicon Plug-in Gait",
       {"Sub01:Pelvis", "Sub01:LFemur", "Sub01:LTibia", "Sub01:LFoot", "Sub01:RFemur",
        "Sub01:RTibia", "Sub01:RFoot", "Sub01:Thorax", "Sub01:Head", "Sub01:LClavicle",
        "Sub01:LHumerus", "Sub01:LRadius", "Sub01:LHand", "Sub01:RClavicle", "Sub01:RHumerus",
        "Sub01:RRadius", "Sub01:RHand"},
       "Sub01:LTibia",
       "Sub01:LHumerus"},
      // Mixamo's, in its namespace
      {"Mixamo / HumanIK",
       {"mixamorig:Hips",         "mixamorig:Spine",         "mixamorig:Spine1",
        "mixamorig:Spine2",       "mixamorig:Neck",          "mixamorig:Head",
        "mixamorig:LeftShoulder", "mixamorig:LeftArm",       "mixamorig:LeftForeArm",
        "mixamorig:LeftHand",     "mixamorig:RightShoulder", "mixamorig:RightArm",
        "mixamorig:RightForeArm", "mixamorig:RightHand",     "mixamorig:LeftUpLeg",
        "mixamorig:LeftLeg",      "mixamorig:LeftFoot",      "mixamorig:RightUpLeg",
        "mixamorig:RightLeg",     "mixamorig:RightFoot"},
       "mixamorig:LeftLeg",
       "mixamorig:LeftArm"},
  };
}

TEST(SkeletonNames, EachConventionsPublishedNamesAreRecognised) {
  for (const PublishedNames& n : published_names()) {
    const SkeletonMatch m = match_skeleton(n.joints, default_name_table());
    EXPECT_TRUE(m.human) << n.convention;
    EXPECT_EQ(m.convention, n.convention);
    const auto segment_of = [&](const std::string& joint) {
      for (std::size_t j = 0; j < n.joints.size(); ++j) {
        if (n.joints[j] == joint && m.node_segment[j] >= 0) {
          return human_segments()[m.node_segment[j]].name;
        }
      }
      return std::string("(none)");
    };
    EXPECT_EQ(segment_of(n.knee), "shank.L") << n.convention;
    EXPECT_EQ(segment_of(n.upper_arm), "upper_arm.L") << n.convention;
  }
}

TEST(SkeletonNames, AnotherSkeletonKeepsTodaysRig) {
  const BvhFile file = parse_bvh(
      "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
      "JOINT b\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n"
      "End Site\n{\nOFFSET 0 1 0\n}\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n"
      "0 0 0 10 0 0\n",
      "chain.bvh");
  BvhImportOptions o;
  o.body = BodyKind::kAuto;
  const BvhAnimation autod = bvh_to_rig(file, "chain.bvh", o);
  o.body = BodyKind::kGeneric;
  const BvhAnimation generic = bvh_to_rig(file, "chain.bvh", o);
  EXPECT_FALSE(autod.body.human);
  EXPECT_EQ(rig_to_json(autod.rig())["bones"], rig_to_json(generic.rig())["bones"]);
  const std::vector<std::string> notes = bvh_body_notes(autod.body);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("not recognised as human"), std::string::npos) << notes[0];
  o.body = BodyKind::kHuman;
  EXPECT_NE(error_of([&] {
              bvh_to_rig(file, "chain.bvh", o);
            }).find("--body: human: chain.bvh is not a human skeleton by its joint names"),
            std::string::npos);
}

// --- masses ---------------------------------------------------------------------------------

TEST(HumanBody, MassesAreDeLevasSharesOfTheTotal) {
  for (const hs::Shape& shape : hs::shapes()) {
    const BvhAnimation a = human(shape.clip(2), shape.axes, shape.scale, 80.0);
    EXPECT_NEAR(a.rig().total_mass(), 80.0, 1e-9) << shape.name;
    for (const HumanMassRow& row : a.body.fit.masses) {
      if (row.nbone == 0) continue;
      EXPECT_NEAR(row.rig_share, row.table_share, 1e-9) << shape.name << " " << row.segment;
    }
  }
  // the default: the reference adult's 73 kg
  EXPECT_NEAR(human(hs::shapes()[0]).rig().total_mass(), kReferenceMass, 1e-9);
}

TEST(HumanBody, InertiaIsTheTablesRadiusOfGyrationOnTheBone) {
  const Rig rig = human(hs::shapes()[1]).rig();
  const int thigh = bone(rig, "mixamorig:LeftUpLeg");
  const double m = rig.bone_mass[thigh], L = rig.bone_length[thigh];
  const LevaRow& r = leva_row(LevaSegment::kThigh);
  EXPECT_NEAR(rig.bone_inertia_local[thigh].x(), m * std::pow(r.r_transverse * L, 2), 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[thigh].y(), m * std::pow(r.r_long * L, 2), 1e-12);
  EXPECT_NEAR(rig.bone_inertia_local[thigh].z(), m * std::pow(r.r_sagittal * L, 2), 1e-12);
}

// --- frames and limits ------------------------------------------------------------------------

TEST(HumanBody, AKneeHingesAcrossTheLegHoweverTheLegStands) {
  // the CMU-like legs splay outward at rest; the MakeHuman-like figure lies down when read as Y up
  for (const hs::Shape& shape : hs::shapes()) {
    for (BvhAxes axes : {BvhAxes::kYUp, BvhAxes::kZUp}) {
      const BvhAnimation a = human(shape.clip(1), axes, shape.scale);
      const Rig& rig = a.rig();
      const HumanBodyFit& fit = a.body.fit;
      for (const char* side : {"shank.L", "shank.R"}) {
        const int knee = bone_of_segment(rig, side);
        const Mat3 f = rig.bone_rest_orient_world[knee].toRotationMatrix();
        // the hinge (local x) lies across the shank, left-right: in the body's frontal plane up
        // to the skeleton's own lean (the CMU-like spine leans back 1.4 deg from the legs' plane)
        const Vec3 along = rig.bone_rest_tail_world[knee] - rig.bone_rest_head_world[knee];
        EXPECT_NEAR(f.col(0).dot(along), 0.0, 1e-12 * along.norm()) << shape.name << side;
        EXPECT_LT(std::abs(f.col(0).dot(fit.forward_world)), std::sin(deg2rad(2.0)))
            << shape.name << side;
        EXPECT_GT(std::abs(f.col(0).dot(fit.left_world)), std::cos(deg2rad(10.0)))
            << shape.name << side;
        EXPECT_TRUE(rig.bone_limit[knee][1].locked() && rig.bone_limit[knee][2].locked());
        EXPECT_EQ(rig.bone_limit[knee][1].min, 0.0);
        EXPECT_FALSE(rig.bone_limit[knee][0].locked());
      }
    }
  }
}

TEST(HumanBody, LimitsAreTheSameWhicheverWayTheFileStands) {
  const hs::Shape shape = hs::shapes()[2];  // MakeHuman-like, Z up
  const Rig up = human(shape.clip(1), BvhAxes::kZUp, 0.1).rig();
  const Rig lying = human(shape.clip(1), BvhAxes::kYUp, 0.1).rig();
  ASSERT_EQ(up.nbone, lying.nbone);
  for (int b = 0; b < up.nbone; ++b) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(up.bone_limit[b][a].min, lying.bone_limit[b][a].min, 1e-9) << up.bone_name[b];
      EXPECT_NEAR(up.bone_limit[b][a].max, lying.bone_limit[b][a].max, 1e-9) << up.bone_name[b];
    }
    EXPECT_TRUE(test::near(up.bone_forward_local[b], lying.bone_forward_local[b], 1e-12));
  }
}

TEST(HumanBody, TheElbowOfATPoseTurnsAboutTheBodysUpAxis) {
  // the template's palms-forward arm raised sideways: the hinge turns with it to the body's up
  const BvhAnimation a = human(hs::shapes()[1]);
  const int forearm = bone(a.rig(), "mixamorig:LeftForeArm");
  const Mat3 f = a.rig().bone_rest_orient_world[forearm].toRotationMatrix();
  EXPECT_GT(std::abs(f.col(0).dot(a.body.fit.up_world)), 1.0 - 1e-9);
  // a T-pose's shoulder rests at 90 deg abduction: its range is offset by it
  const int arm = bone(a.rig(), "mixamorig:LeftArm");
  EXPECT_NEAR(rad2deg(a.rig().bone_limit[arm][2].min), -180.0 + 90.0, 1.0);
  EXPECT_NEAR(rad2deg(a.rig().bone_limit[arm][2].max), 30.0 + 90.0, 1.0);
}

TEST(HumanBody, TheSpineSharesItsRangeAndWeldedBonesHaveNone) {
  const Rig rig = human(hs::shapes()[2]).rig();  // five spine bones
  int spine = 0;
  for (int b = 0; b < rig.nbone; ++b) {
    const std::string& s = rig.bone_segment[b];
    if ((s == "lumbar" || s == "thorax") && !rig.welded(b)) ++spine;
  }
  ASSERT_GE(spine, 5);
  const int first = bone(rig, "spine04");
  EXPECT_NEAR(rad2deg(rig.bone_limit[first][0].max), 80.0 / spine, 1e-9);
  for (int b = 0; b < rig.nbone; ++b) {
    if (!rig.welded(b)) continue;
    for (const AxisLimit& l : rig.bone_limit[b]) EXPECT_FALSE(l.limited) << rig.bone_name[b];
  }
}

TEST(HumanBody, ThePelvisIsOneRigidBody) {
  // CMU's LHipJoint and RHipJoint are welded: the hips keep their width in any pose
  const Rig rig = human(hs::shapes()[0]).rig();
  EXPECT_TRUE(rig.welded(bone(rig, "LHipJoint")));
  EXPECT_TRUE(rig.welded(bone(rig, "RHipJoint")));
  const int l = bone(rig, "LeftUpLeg"), r = bone(rig, "RightUpLeg");
  const double width = (rig.bone_rest_head_world[l] - rig.bone_rest_head_world[r]).norm();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pose pose = rest_pose(rig);
  for (Quat& q : pose.bone_local_rotation) q = Quat(1.0, u(rng), u(rng), u(rng)).normalized();
  const BoneFrames f = forward_kinematics(rig, pose);
  EXPECT_NEAR((f.head_world[l] - f.head_world[r]).norm(), width, 1e-12);
}

TEST(HumanBody, ForwardAxesPointFromTheFaceAndThePalms) {
  const BvhAnimation a = human(hs::shapes()[3]);  // OptiTrack-like
  const Rig& rig = a.rig();
  const BoneFrames f = forward_kinematics(rig, rest_pose(rig));
  const int head = bone(rig, "Skeleton1_Head");
  EXPECT_TRUE(test::near(f.orient_world[head] * rig.bone_forward_local[head],
                         a.body.fit.forward_world, 1e-9));
  // an aim without an axis turns the face; a bone without a forward axis keeps +Y
  EXPECT_TRUE(test::near(default_aim_axis(rig, head), rig.bone_forward_local[head], 0.0));
  const Rig plain = load_rig(test::model_path("rigs/pinhead.json"));
  EXPECT_TRUE(test::near(default_aim_axis(plain, 0), Vec3::UnitY(), 0.0));
  const std::string err = error_of([&] {
    look_at_axis(plain, 0, TargetSource{"--look-at", "'x'"});
  });
  EXPECT_NE(err.find("--look-at: 'x': field 'bone': '"), std::string::npos) << err;
  EXPECT_NE(err.find("has no forward axis"), std::string::npos) << err;
}

TEST(HumanBody, TheRigFileKeepsSegmentsAndForwardAxes) {
  const Rig rig = human(hs::shapes()[0]).rig();
  const Rig back = rig_from_json(rig_to_json(rig), "back.json");
  ASSERT_EQ(back.nbone, rig.nbone);
  for (int b = 0; b < rig.nbone; ++b) {
    EXPECT_EQ(back.bone_segment[b], rig.bone_segment[b]);
    EXPECT_TRUE(test::near(back.bone_forward_local[b], rig.bone_forward_local[b], 1e-15));
    EXPECT_TRUE(test::near(back.bone_inertia_local[b], rig.bone_inertia_local[b],
                           1e-12 * rig.bone_inertia_local[b].norm()));
  }
  Json doc = rig_to_json(rig);
  doc["bones"][1]["segment"] = "thigh.l";
  EXPECT_NE(error_of([&] {
              rig_from_json(doc, "bad.json");
            }).find("field 'segment': unknown segment 'thigh.l' (did you mean 'thigh.L'?)"),
            std::string::npos);
}

TEST(HumanBody, TheClipComesOnTheHumanRigAsOnTheGenericOne) {
  // the welds hold what the clip holds (LHipJoint never turns): every joint where the file puts it
  for (const hs::Shape& shape : hs::shapes()) {
    EXPECT_LT(human(shape).max_position_error, 1e-9 * human(shape).rig().height()) << shape.name;
  }
}

// --- units and axes ---------------------------------------------------------------------------

BvhFile scaled(BvhFile clip, double factor) {
  for (BvhJoint& j : clip.joints) {
    j.offset *= factor;
    for (Vec3& e : j.end_sites) e *= factor;
  }
  for (auto& row : clip.frames) {
    for (int c = 0; c < 3; ++c) row[c] *= factor;
  }
  return clip;
}

TEST(HumanUnits, TheRuleNamesEachUnitsScale) {
  struct Case {
    BvhFile clip;
    BvhAxes axes;
    double scale;
  };
  const double inch_per_cmu = 0.0564444 / 0.0254;
  const Case cases[] = {
      {hs::cmu_like(1), BvhAxes::kYUp, 0.0564444},                     // CMU's unit
      {scaled(hs::cmu_like(1), inch_per_cmu), BvhAxes::kYUp, 0.0254},  // inches
      {hs::makehuman_like(1), BvhAxes::kZUp, 0.1},                     // decimetres
      {hs::optitrack_like(1), BvhAxes::kYUp, 0.01},                    // centimetres
      {scaled(hs::optitrack_like(1), 10.0), BvhAxes::kYUp, 0.001},     // millimetres
  };
  for (const Case& c : cases) {
    const BvhAnimation a = human(c.clip, c.axes, 1.0);
    EXPECT_NEAR(a.body.suggested_scale, c.scale, 1e-12) << a.body.unit_warning;
    EXPECT_NE(a.body.unit_warning.find("--scale"), std::string::npos);
    const BvhAnimation in_metres = human(c.clip, c.axes, c.scale);
    EXPECT_TRUE(in_metres.body.unit_warning.empty()) << in_metres.body.unit_warning;
    const double h = in_metres.body.fit.height;
    EXPECT_GE(h, kHumanHeightMin);
    EXPECT_LE(h, kHumanHeightMax);
  }
  // a size no unit gives: the scale of the reference adult's height
  const BvhAnimation odd = human(scaled(hs::optitrack_like(1), 3.0), BvhAxes::kYUp, 1.0);
  EXPECT_NEAR(odd.body.suggested_scale * odd.body.height_file, kReferenceHeight, 1e-9);
}

TEST(HumanUnits, HeightScalesTheFigureToMetres) {
  BvhImportOptions o;
  o.body = BodyKind::kAuto;
  o.height = 1.8;
  const BvhAnimation a = bvh_to_rig(hs::cmu_like(1), "cmu.bvh", o);
  EXPECT_NEAR(a.body.fit.height, 1.8, 1e-9);
  EXPECT_TRUE(a.body.unit_warning.empty());
  // (0 is "not given" here; the command line refuses a given 0)
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    o.height = bad;
    EXPECT_NE(error_of([&] {
                bvh_to_rig(hs::cmu_like(1), "cmu.bvh", o);
              }).find("--height: must be a positive finite number (metres)"),
              std::string::npos)
        << bad;
  }
}

TEST(HumanUnits, AFigureLyingDownGetsTheAxesThatStandItUp) {
  const BvhAnimation lying = human(hs::makehuman_like(1), BvhAxes::kYUp, 0.1);
  EXPECT_NE(lying.body.axes_hint.find("convert with --axes z-up"), std::string::npos)
      << lying.body.axes_hint;
  EXPECT_TRUE(human(hs::makehuman_like(1), BvhAxes::kZUp, 0.1).body.axes_hint.empty());
  EXPECT_TRUE(human(hs::cmu_like(1), BvhAxes::kYUp, 0.0564444).body.axes_hint.empty());
}

// --- bad input --------------------------------------------------------------------------------

TEST(HumanBadInput, AMappingFileNamesKnownSegmentsAndJoints) {
  const std::string bad_segment = error_of(
      [] { name_table_from_json(Json::parse(R"({"joints": {"Hips": "pelvs"}})"), "m.json"); });
  EXPECT_NE(bad_segment.find("m.json: joints 'Hips': unknown segment 'pelvs' (did you mean "
                             "'pelvis'?)"),
            std::string::npos)
      << bad_segment;
  const NameTable user = name_table_from_json(
      Json::parse(R"({"joints": {"Hips": "pelvis", "LeftUpLge": "thigh.L"}})"), "m.json");
  const std::vector<std::string> names = {"Hips", "LeftUpLeg", "LeftLeg"};
  const std::string bad_joint = error_of([&] { match_skeleton(names, user, true); });
  EXPECT_NE(bad_joint.find("m.json: joints 'LeftUpLge': no joint of the skeleton has this name "
                           "(did you mean 'LeftUpLeg'?)"),
            std::string::npos)
      << bad_joint;
  EXPECT_NE(error_of([] {
              name_table_from_json(Json::parse(R"({"joints": {"a": "head", "A": "neck"}})"),
                                   "m.json");
            }).find("names the same joint as another entry"),
            std::string::npos);
}

TEST(HumanBadInput, ALimitsFileNamingAnUnknownBoneSaysTheNearest) {
  Rig rig = human(hs::shapes()[0]).rig();
  const JointLimits limits = joint_limits_from_json(
      Json::parse(R"({"limits_deg": {"LeftForArm": {"x": [-90, 0]}}})"), "limits.json");
  const std::string err = error_of([&] { apply_joint_limits(rig, limits); });
  EXPECT_NE(err.find("limits.json: limits_deg 'LeftForArm': unknown bone"), std::string::npos)
      << err;
  EXPECT_NE(err.find("(did you mean 'LeftForeArm'?)"), std::string::npos) << err;
  // a known bone's limits win over the template's
  const JointLimits mine = joint_limits_from_json(
      Json::parse(R"({"limits_deg": {"LeftForeArm": {"x": [-90, 0]}}})"), "limits.json");
  apply_joint_limits(rig, mine);
  EXPECT_NEAR(rad2deg(rig.bone_limit[bone(rig, "LeftForeArm")][0].min), -90.0, 1e-9);
}

TEST(HumanBadInput, MassPerLengthIsForGenericBodies) {
  BvhImportOptions o;
  o.body = BodyKind::kAuto;
  o.sizing.mass_per_length = 2.0;
  EXPECT_NE(error_of([&] {
              bvh_to_rig(hs::cmu_like(1), "cmu.bvh", o);
            }).find("--mass-per-length: a human body's masses come from de Leva's table"),
            std::string::npos);
}

TEST(HumanBadInput, ImplausibleProportionsWarnAndStayFinite) {
  // legs eight times too long for the figure
  BvhFile clip = hs::optitrack_like(1);
  for (BvhJoint& j : clip.joints) {
    if (j.name.find("Shin") != std::string::npos || j.name.find("Foot") != std::string::npos) {
      j.offset *= 8.0;
    }
  }
  const BvhAnimation a = human(clip, BvhAxes::kYUp, 0.01);
  bool warned = false;
  for (const std::string& w : a.body.fit.warnings) {
    warned = warned || w.find("left leg (thigh and shank) is") != std::string::npos;
  }
  EXPECT_TRUE(warned);
  for (int b = 0; b < a.rig().nbone; ++b) {
    EXPECT_TRUE(std::isfinite(a.rig().bone_mass[b]));
    EXPECT_TRUE(a.rig().bone_inertia_local[b].allFinite());
    EXPECT_TRUE(a.rig().bone_rest_orient_world[b].coeffs().allFinite());
  }
}

// --- --weld-constant --------------------------------------------------------------------------

bool listed(const std::vector<std::string>& items, const std::string& text) {
  for (const std::string& i : items) {
    if (i.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(WeldConstant, JointsAtRestAllAlongAreWeldedOthersListed) {
  BvhImportOptions o;
  o.scale = 0.0564444;
  o.body = BodyKind::kAuto;
  o.weld_constant = true;
  const BvhAnimation a = bvh_to_rig(hs::cmu_like(6), "cmu.bvh", o);
  const Rig& rig = a.rig();
  EXPECT_TRUE(rig.welded(bone(rig, "LeftHandIndex1")));
  EXPECT_TRUE(rig.welded(bone(rig, "RightHandIndex1")));
  EXPECT_FALSE(rig.welded(bone(rig, "LeftToeBase")));  // held at 5 deg
  EXPECT_FALSE(rig.welded(bone(rig, "LThumb")));       // below LeftHand, which has no bone
  EXPECT_TRUE(listed(a.body.constant_not_welded, "LeftToeBase (constant at a turn of 5 deg)"));
  EXPECT_TRUE(listed(a.body.constant_not_welded,
                     "LThumb (its parent joint 'LeftHand' has no bone of its own, and turns)"));
  EXPECT_TRUE(listed(a.body.welded_constant, "LeftHandIndex1 to LeftFingerBase"));
  // the clip comes on the welded rig where the file puts it
  EXPECT_LT(a.max_position_error, 1e-9);
  EXPECT_TRUE(a.warnings.empty() || !listed(a.warnings, "is welded to"));
}

TEST(WeldConstant, AWeldedJointThatTurnsIsNamed) {
  // MakeHuman's pelvis.L welded by the template, turned by the clip after all
  BvhFile clip = hs::makehuman_like(3);
  int index = -1;
  for (std::size_t j = 0; j < clip.joints.size(); ++j) {
    if (clip.joints[j].name == "pelvis.L") index = static_cast<int>(j);
  }
  ASSERT_GE(index, 0);
  clip.frames[1][clip.joints[index].channel_start] = 7.0;  // Zrotation, deg
  const BvhAnimation a = human(clip, BvhAxes::kZUp, 0.1);
  EXPECT_TRUE(listed(a.warnings, "joint 'pelvis.L'")) << (a.warnings.empty() ? "" : a.warnings[0]);
  EXPECT_TRUE(listed(a.warnings, "but turns up to 7 deg against it in the clip"));
  EXPECT_GT(a.max_position_error, 0.01);
}

// --- the scene file: an aim without an axis ------------------------------------------------------

TEST(HumanBody, AnAimWithoutAnAxisTurnsTheFace) {
  const Rig rig = human(hs::shapes()[3]).rig();
  const Json scene = {{"rig", rig_to_json(rig)},
                      {"aim_targets", {{{"bone", "Skeleton1_Head"}, {"point", {0, 5, 1.6}}}}}};
  const Scene s = scene_from_json(scene, "look.json", ".");
  ASSERT_EQ(s.aim_targets.size(), 1u);
  const int head = bone(rig, "Skeleton1_Head");
  EXPECT_TRUE(test::near(s.aim_targets[0].axis_bone, rig.bone_forward_local[head], 1e-12));
}

}  // namespace
}  // namespace physik
