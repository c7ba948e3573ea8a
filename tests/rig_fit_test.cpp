// A converted skeleton is the body its source describes, and rests where it is put: sizes that fit
// the skeleton (rig_sizing.h), limits whose torsion band leaves the rest pose alone
// (rest_limits.h), no capsule pairs overlapping at rest (bone_overlaps.h, the rig's
// collision_exclude), and a rig file that keeps all of it through a round trip (rig_io.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "experiments/at_rest.h"
#include "experiments/mocap_bvh.h"
#include "physik/engine/bone_overlaps.h"
#include "physik/engine/collision.h"
#include "physik/engine/start_contacts.h"
#include "physik/io/bvh.h"
#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/rest_limits.h"
#include "physik/model/rig_sizing.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

std::string error_of(const std::string& text) {
  try {
    rig_from_json_text(text, "bad.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

const char* kTwoBones = R"("bones": [
  {"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]},
  {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2]},
  {"name": "c", "parent": "b", "head": [0,0,2], "tail": [0,0,3]}])";

// --- the rig file: defaults, exclusions, notes --------------------------------------------------

TEST(RigDefaults, ApplyToEveryBoneThatNamesNoValueOfItsOwn) {
  const Rig r =
      rig_from_json_text(std::string(R"({"defaults": {"radius": 0.07, "collision_radius": 0.03,
                                   "mass_per_length": 2}, "bones": [
  {"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]},
  {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,3], "radius": 0.2, "mass": 5},
  {"name": "c", "parent": "b", "head": [0,0,3], "tail": [0,0,4], "collision_radius": 0.1}]})"),
                         "d.json");
  EXPECT_EQ(r.bone_radius, (std::vector<double>{0.07, 0.2, 0.07}));
  EXPECT_EQ(r.bone_collision_radius, (std::vector<double>{0.03, 0.03, 0.1}));
  EXPECT_EQ(r.bone_mass, (std::vector<double>{2.0, 5.0, 2.0}));
}

TEST(RigWriter, WritesSharedValuesOnceInTheDefaults) {
  const Rig r = rig_from_json_text(
      std::string(R"({"defaults": {"radius": 0.07, "collision_radius": 0.03}, "bones": [
  {"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]},
  {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,3], "radius": 0.2},
  {"name": "c", "parent": "b", "head": [0,0,3], "tail": [0,0,4], "collision_radius": 0.1}]})"),
      "d.json");
  const Json doc = rig_to_json(r);
  EXPECT_EQ(doc["defaults"]["radius"], 0.07);
  EXPECT_EQ(doc["defaults"]["collision_radius"], 0.03);
  EXPECT_FALSE(doc["bones"][0].contains("radius"));
  EXPECT_EQ(doc["bones"][1]["radius"], 0.2);
  EXPECT_FALSE(doc["bones"][2].contains("radius"));
  EXPECT_FALSE(doc["bones"][0].contains("collision_radius"));
  EXPECT_EQ(doc["bones"][2]["collision_radius"], 0.1);
  // a rig whose bones keep the default capsule (0.06 x length) names no collision radius
  const Json chain = rig_to_json(rig_from_json_text(std::string("{") + kTwoBones + "}", "c.json"));
  EXPECT_FALSE(chain["defaults"].contains("collision_radius"));
  for (const Json& b : chain["bones"]) {
    EXPECT_FALSE(b.contains("collision_radius"));
    EXPECT_FALSE(b.contains("radius"));
  }
}

// every derived array equal: the rest frames to round-off (a frame is written as the matrix of
// the rig's quaternion and re-orthonormalised when read), the rest exactly
void expect_same_rig(const Rig& a, const Rig& b, const std::string& what) {
  ASSERT_EQ(a.nbone, b.nbone) << what;
  EXPECT_EQ(a.name, b.name) << what;
  EXPECT_EQ(a.bone_name, b.bone_name) << what;
  EXPECT_EQ(a.bone_parent, b.bone_parent) << what;
  EXPECT_EQ(a.bone_mass, b.bone_mass) << what;
  EXPECT_EQ(a.bone_radius, b.bone_radius) << what;
  EXPECT_EQ(a.collision_exclude, b.collision_exclude) << what;
  EXPECT_EQ(a.comment, b.comment) << what;
  EXPECT_EQ(a.units, b.units) << what;
  EXPECT_EQ(a.source, b.source) << what;
  for (int i = 0; i < a.nbone; ++i) {
    EXPECT_TRUE(test::near(a.bone_rest_head_world[i], b.bone_rest_head_world[i], 0.0)) << what;
    EXPECT_TRUE(test::near(a.bone_rest_tail_world[i], b.bone_rest_tail_world[i], 0.0)) << what;
    EXPECT_LT(a.bone_rest_orient_world[i].angularDistance(b.bone_rest_orient_world[i]), 1e-14)
        << what << " bone " << a.bone_name[i];
    EXPECT_NEAR(a.bone_collision_radius[i], b.bone_collision_radius[i],
                1e-15 * a.bone_collision_radius[i])
        << what;
    EXPECT_TRUE(test::near(a.bone_inertia_local[i], b.bone_inertia_local[i],
                           1e-12 * a.bone_inertia_local[i].norm()))
        << what;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.bone_limit[i][k].limited, b.bone_limit[i][k].limited) << what;
      EXPECT_NEAR(a.bone_limit[i][k].min, b.bone_limit[i][k].min, 1e-15) << what;
      EXPECT_NEAR(a.bone_limit[i][k].max, b.bone_limit[i][k].max, 1e-15) << what;
    }
  }
}

TEST(RigWriter, ReadWriteReadGivesTheSameRig) {
  for (const auto& entry : std::filesystem::directory_iterator(test::model_path("rigs"))) {
    const Rig a = load_rig(entry.path().string());
    expect_same_rig(a, rig_from_json(rig_to_json(a), "back"), entry.path().string());
  }
  // a converted skeleton: radii per bone, explicit collision radii, exclusions, notes
  BvhImportOptions o;
  o.scale = 0.01;
  const Rig mocap =
      bvh_to_rig(parse_bvh(experiments::mocap_bvh(), "mocap.bvh"), "mocap.bvh", o).rig();
  ASSERT_FALSE(mocap.collision_exclude.empty());
  ASSERT_FALSE(mocap.source.empty());
  expect_same_rig(mocap, rig_from_json(rig_to_json(mocap), "back"), "mocap");
}

TEST(RigCollisionExclude, ReadAsPairsOfKnownBones) {
  const Rig r = rig_from_json_text(
      std::string("{") + kTwoBones + R"(, "collision_exclude": [["c", "a"], ["a", "c"]],
                   "source": ["one", "two"], "units": "m", "comment": "x"})",
      "e.json");
  EXPECT_EQ(r.collision_exclude, (std::vector<std::pair<int, int>>{{0, 2}}));
  EXPECT_TRUE(r.collision_excluded(2, 0));
  EXPECT_FALSE(r.collision_excluded(0, 1));
  EXPECT_EQ(r.source, (std::vector<std::string>{"one", "two"}));
  EXPECT_EQ(r.units, "m");
}

TEST(RigCollisionExclude, BadPairsNameFileFieldAndBone) {
  const std::string base = std::string("{") + kTwoBones + R"(, "collision_exclude": )";
  EXPECT_EQ(error_of(base + R"([["a", "c"], ["b", "b"]]})"),
            "bad.json: field 'collision_exclude[1]': bone 'b' is paired with itself (an "
            "exclusion names two different bones)");
  EXPECT_EQ(error_of(base + R"([["a", "zz"]]})"),
            "bad.json: field 'collision_exclude[0]': unknown bone 'zz' (did you mean 'a'?)");
  EXPECT_EQ(error_of(base + R"([["a"]]})"),
            "bad.json: field 'collision_exclude[0]': expected a pair of bone names [\"a\", \"b\"]");
  EXPECT_EQ(error_of(base + "5}"),
            "bad.json: field 'collision_exclude': expected an array of [bone, bone] pairs");
  EXPECT_EQ(error_of(std::string("{") + kTwoBones + R"(, "source": [1]})"),
            "bad.json: field 'source[0]': expected a string");
}

// --- sizes --------------------------------------------------------------------------------------

TEST(RigSizing, RadiusFollowsTheLengthAndMassTheRod) {
  SizingOptions o;
  EXPECT_DOUBLE_EQ(fitted_radius(o, 0.4), kRadiusPerLength * 0.4);
  o.radius = 0.05;
  EXPECT_EQ(fitted_radius(o, 0.4), 0.05);
  std::vector<BoneSpec> specs(2);
  specs[0].head_world = Vec3(0, 0, 0);
  specs[0].tail_world = Vec3(0, 0, 0.4);
  specs[0].radius = 0.05;
  specs[1].head_world = Vec3(0, 0, 0.4);
  specs[1].tail_world = Vec3(0, 0, 0.6);
  specs[1].radius = 0.02;
  specs[1].inertia_local = Vec3(1, 1, 1);
  fit_masses(specs, SizingOptions{});
  // a cylinder of water: rho pi r^2 L
  EXPECT_DOUBLE_EQ(specs[0].mass, 1000.0 * kPi * 0.05 * 0.05 * 0.4);
  EXPECT_DOUBLE_EQ(specs[1].mass, 1000.0 * kPi * 0.02 * 0.02 * 0.2);
  SizingOptions total;
  total.total_mass = 10.0;
  total.mass_per_length = 3.0;
  fit_masses(specs, total);
  EXPECT_DOUBLE_EQ(specs[0].mass + specs[1].mass, 10.0);
  EXPECT_DOUBLE_EQ(specs[0].mass / specs[1].mass, 2.0);  // 3 kg per unit sets the ratio
  EXPECT_TRUE(specs[1].inertia_local.isZero());          // re-massed: the cylinder's again
}

TEST(RigSizing, BadOptionsNameTheOption) {
  auto message = [](SizingOptions o) {
    try {
      check_sizing_options(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  SizingOptions o;
  EXPECT_EQ(message(o), "(no error)");
  o.radius = -1;
  EXPECT_NE(message(o).find("--radius: must be a positive finite number"), std::string::npos);
  o = SizingOptions{};
  o.mass_per_length = std::nan("");
  EXPECT_NE(message(o).find("--mass-per-length: "), std::string::npos);
  o = SizingOptions{};
  o.total_mass = 1e12;
  EXPECT_NE(message(o).find("--total-mass: 1e+12 kg is outside"), std::string::npos);
}

TEST(RigSizing, ACentimetreMocapSkeletonConvertsToAPersonsSizes) {
  const BvhFile file = parse_bvh(experiments::mocap_bvh(), "mocap.bvh");
  BvhImportOptions o;
  o.scale = 0.01;
  const BvhAnimation anim = bvh_to_rig(file, "mocap.bvh", o);
  const Rig& r = anim.rig();
  EXPECT_NEAR(r.height(), 1.83, 1e-12);
  for (int i = 0; i < r.nbone; ++i) {
    EXPECT_DOUBLE_EQ(r.bone_radius[i], kRadiusPerLength * r.bone_length[i]) << r.bone_name[i];
    EXPECT_EQ(r.bone_collision_radius[i], r.bone_radius[i]);
  }
  const int thigh = r.find_bone("LeftUpLeg");
  ASSERT_GE(thigh, 0);
  EXPECT_NEAR(r.bone_radius[thigh], 0.14 * 0.42, 1e-12);  // 5.9 cm, MuJoCo's thigh is 6
  EXPECT_GT(r.total_mass(), 10.0);  // a rod model of a 1.83 m figure: tens of kg, not 479
  EXPECT_LT(r.total_mass(), 100.0);
  double suggested = 0.0;
  EXPECT_EQ(guess_bvh_units(1.83, suggested), "");
  // the same file without --scale: a figure 183 units tall, which looks like centimetres
  const Rig unscaled = bvh_to_rig(file, "mocap.bvh").rig();
  EXPECT_NEAR(unscaled.height(), 183.0, 1e-9);
  EXPECT_EQ(guess_bvh_units(unscaled.height(), suggested), "centimetres");
  EXPECT_EQ(suggested, 0.01);
  EXPECT_EQ(guess_bvh_units(1830.0, suggested), "millimetres");
  EXPECT_EQ(suggested, 0.001);
}

// --- rest: limits -------------------------------------------------------------------------------

TEST(RestLimits, ALimitStartingAtRestIsWidenedToTheBandsEdge) {
  const double t = 0.1;
  BoneSpec root, elbow;
  root.name = "upper";
  root.tail_world = Vec3(0, 0, 1);
  elbow.name = "fore";
  elbow.parent = "upper";
  elbow.head_world = Vec3(0, 0, 1);
  elbow.tail_world = Vec3(0, 0, 2);
  elbow.limit[0] = AxisLimit{true, 0.0, deg2rad(150)};           // 0 is the limit: in the band
  elbow.limit[1] = AxisLimit{true, deg2rad(-160), deg2rad(-2)};  // 0 is past it (a knee)
  elbow.limit[2] = AxisLimit{true, 0.0, 0.0};                    // locked at rest: fine
  for (BoneSpec* b : {&root, &elbow}) {
    b->rest_frame_world = rest_frame_from_roll(b->head_world, b->tail_world, 0.0);
  }
  std::vector<BoneSpec> specs{root, elbow};
  const std::vector<RestBandProblem> fixed = fit_limits_to_rest(specs, t);
  ASSERT_EQ(fixed.size(), 2u);
  EXPECT_EQ(fixed[0].axis, 0);
  EXPECT_EQ(fixed[1].axis, 1);
  for (const RestBandProblem& p : fixed) {
    EXPECT_TRUE(p.fixed());
    const AxisLimit& l = specs[1].limit[p.axis];
    const double band = t * (l.max - l.min);
    // the rest angle sits just inside the band, at its edge
    EXPECT_LE(l.min + band, 0.0);
    EXPECT_GE(l.max - band, 0.0);
    EXPECT_LT(std::min(-(l.min + band), l.max - band), 2 * kRestBandMargin);
  }
  // x: the lower bound moved, the upper kept; y: the upper moved
  EXPECT_EQ(specs[1].limit[0].max, deg2rad(150));
  EXPECT_NEAR(rad2deg(specs[1].limit[0].min), -150.0 * t / (1 - t), 1e-6);
  EXPECT_EQ(specs[1].limit[1].min, deg2rad(-160));
  EXPECT_NEAR(rad2deg(specs[1].limit[1].max), 160.0 * t / (1 - t), 1e-6);
  EXPECT_EQ(describe(fixed[0], "fore"), "fore x: [0, 150] -> [-16.67, 150] deg");
  // fixed, a rig reports nothing more
  const Rig rig = build_rig(specs, "t");
  EXPECT_TRUE(rest_band_problems(rig, t).empty());
  // a locked axis away from rest cannot be widened: reported, left as it is
  specs[1].limit[2] = AxisLimit{true, 0.1, 0.1};
  const std::vector<RestBandProblem> locked = fit_limits_to_rest(specs, t);
  ASSERT_EQ(locked.size(), 1u);
  EXPECT_FALSE(locked[0].fixed());
  EXPECT_EQ(specs[1].limit[2].min, 0.1);
}

// --- rest: overlapping capsules -----------------------------------------------------------------

// a root with two branches that cross: b1 and c1 overlap, and so do their parents' children
Rig crossing_rig() {
  std::vector<BoneSpec> s(4);
  s[0].name = "root";
  s[0].tail_world = Vec3(0, 0, 1);
  s[1].name = "b";
  s[1].parent = "root";
  s[1].head_world = Vec3(0, 0, 1);
  s[1].tail_world = Vec3(1, 0, 1);
  s[2].name = "b1";
  s[2].parent = "b";
  s[2].head_world = Vec3(1, 0, 1);
  s[2].tail_world = Vec3(0.5, 0, 1.5);
  s[3].name = "c";
  s[3].parent = "root";
  s[3].head_world = Vec3(0, 0, 1);
  s[3].tail_world = Vec3(0.5, 0, 1.6);
  for (BoneSpec& b : s) {
    b.rest_frame_world = rest_frame_from_roll(b.head_world, b.tail_world, 0.0);
    b.collision_radius = 0.1;
  }
  return build_rig(s, "crossing");
}

TEST(RestOverlaps, FoundByTheEnginesCapsulesAndExcluded) {
  Rig rig = crossing_rig();
  const std::vector<BoneOverlap> all = rest_overlaps(rig);
  // b/c share the root's joint and never count; b1 and c cross
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(rig.bone_name[all[0].a], "b1");
  EXPECT_EQ(rig.bone_name[all[0].b], "c");
  EXPECT_GT(all[0].depth, 0.0);
  EXPECT_FALSE(all[0].excluded);
  // a scene with self-collision starts in that contact, and says so
  Scene scene = test::scene_for(rig, preset_params("robust"));
  scene.collision.self_collision = true;
  const std::string warning = check_start_contacts(scene);
  EXPECT_NE(warning.find("1 bone pair overlaps at the start under self_collision"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("[\"b1\", \"c\"]"), std::string::npos) << warning;
  EXPECT_NE(warning.find("collision_exclude"), std::string::npos) << warning;
  scene.collision.self_collision = false;
  EXPECT_EQ(check_start_contacts(scene), "");
  // the converters' step: the pair goes into the rig's exclusions, and nothing collides
  const std::vector<BoneOverlap> added = exclude_rest_overlaps(rig);
  ASSERT_EQ(added.size(), 1u);
  EXPECT_TRUE(rig.collision_excluded(all[0].a, all[0].b));
  EXPECT_TRUE(rest_overlaps(rig)[0].excluded);
  EXPECT_TRUE(exclude_rest_overlaps(rig).empty());
  scene.rig = rig;
  scene.collision.self_collision = true;
  EXPECT_EQ(check_start_contacts(scene), "");
  CollisionWorld world;
  std::vector<Contact> contacts;
  world.detect(scene, forward_kinematics(rig, rest_pose(rig)), contacts);
  EXPECT_TRUE(contacts.empty());
}

// --- rest stays rest ----------------------------------------------------------------------------

// The kinetic energy of a rig at rest after 100 steps, no targets, no gravity. With no force
// acting, every scheme's accelerations are exact zeros (sums of zero terms), so the bound is 0.
void expect_rest_stays_rest(const Rig& rig, const std::string& what) {
  for (auto scheme : {experiments::RestScheme::kGaussSeidel, experiments::RestScheme::kExact,
                      experiments::RestScheme::kImplicit}) {
    for (bool self : {false, true}) {
      EXPECT_EQ(experiments::rest_kinetic_energy(rig, scheme, self), 0.0)
          << what << ", " << to_string(scheme) << (self ? ", self_collision" : "");
    }
  }
}

TEST(RestStaysRest, AConvertedMocapSkeleton) {
  BvhImportOptions o;
  o.scale = 0.01;
  const BvhAnimation anim =
      bvh_to_rig(parse_bvh(experiments::mocap_bvh(), "mocap.bvh"), "mocap.bvh", o);
  EXPECT_FALSE(anim.rest_overlaps.empty());  // its hips, chest and shoulders overlap
  expect_rest_stays_rest(anim.rig(), "mocap");
  // without the exclusions its self-collision moves it
  Rig open = anim.rig();
  open.collision_exclude.clear();
  EXPECT_GT(experiments::rest_kinetic_energy(open, experiments::RestScheme::kImplicit, true), 0.0);
}

TEST(RestStaysRest, EveryShippedRigOnceItsRestIsOutOfTheTorsionBands) {
  // the paper's rigs put their rest pose at a limit (pinhead's knees and elbows 0..160 deg, the
  // elbow rig's -90..0, the hand's phalanges 0..10): the torsion band pushes them at rest. The
  // files stay as the paper's scenes use them; fixed in memory, each rests.
  const double t = preset_params("robust").torsion_tolerance;
  for (const auto& entry : std::filesystem::directory_iterator(test::model_path("rigs"))) {
    Rig rig = load_rig(entry.path().string());
    const std::string name = entry.path().stem().string();
    const std::vector<RestBandProblem> bands = rest_band_problems(rig, t);
    EXPECT_EQ(bands.empty(), name == "chain3") << name;
    if (!bands.empty()) {
      EXPECT_GT(experiments::rest_kinetic_energy(rig, experiments::RestScheme::kGaussSeidel, false),
                0.0)
          << name;
    }
    for (const RestBandProblem& p : bands) rig.bone_limit[p.bone][p.axis] = p.after;
    EXPECT_TRUE(rest_overlaps(rig).empty()) << name;
    expect_rest_stays_rest(rig, name);
  }
}

}  // namespace
}  // namespace physik
