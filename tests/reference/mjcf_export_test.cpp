// Rig -> MJCF: every shipped rig compiles in MuJoCo, with the rig's masses, inertias, rest pose and
// joint types (reference/mjcf_export.h).
#include "reference/mjcf_export.h"
#include "physik/engine/engine.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>

#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "physik/io/rig_io.h"
#include "physik/model/errors.h"
#include "physik/model/rig_generators.h"
#include "reference/mujoco_runner.h"
#include "tests/engine_test_util.h"
#include "tests/test_util.h"

namespace physik {
namespace {

// the export's options for a joint model and a time step, the rest at their defaults
MjcfOptions options(JointModel joints, double dt) {
  MjcfOptions o;
  o.joints = joints;
  o.dt = dt;
  return o;
}

std::vector<std::string> shipped_rigs() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(test::model_path("rigs"))) {
    if (e.path().extension() == ".json") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// composite inertia about the total centre of mass, world axes, from per-body mass, centre and
// world inertia
struct Composite {
  double mass = 0.0;
  Vec3 com = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
};

Composite composite(const std::vector<double>& m, const std::vector<Vec3>& c,
                    const std::vector<Mat3>& I) {
  Composite out;
  for (std::size_t i = 0; i < m.size(); ++i) {
    out.mass += m[i];
    out.com += m[i] * c[i];
  }
  out.com /= out.mass;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const Vec3 r = c[i] - out.com;
    out.inertia += I[i] + m[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  return out;
}

TEST(MjcfExport, EveryShippedRigCompilesWithTheRigsMassAndInertia) {
  const auto rigs = shipped_rigs();
  ASSERT_GE(rigs.size(), 4u);
  for (const std::string& path : rigs) {
    SCOPED_TRACE(path);
    const Rig rig = load_rig(path);
    for (JointModel jm : {JointModel::kRigJoints, JointModel::kBallJoints}) {
      MjcfOptions o;
      o.joints = jm;
      const MjModelPtr m = rig_to_mjmodel(rig, o);
      ASSERT_TRUE(m);
      ASSERT_EQ(m->nbody, rig.nbone + 1);
      EXPECT_NEAR(mj_getTotalmass(m.get()), rig.total_mass(), 1e-12 * rig.total_mass());

      // per body: name, mass, principal inertia, centre at the body origin, unrotated inertia
      std::vector<double> mass_rig, mass_mj;
      std::vector<Vec3> com_rig, com_mj;
      std::vector<Mat3> I_rig, I_mj;
      const MjDataPtr d(mj_makeData(m.get()));
      mj_forward(m.get(), d.get());
      const BoneFrames rest = forward_kinematics(rig, rest_pose(rig));
      for (int i = 0; i < rig.nbone; ++i) {
        const int b = i + 1;
        EXPECT_EQ(mj_name2id(m.get(), mjOBJ_BODY, rig.bone_name[i].c_str()), b);
        EXPECT_NEAR(m->body_mass[b], rig.bone_mass[i], 1e-14);
        for (int k = 0; k < 3; ++k) {
          EXPECT_NEAR(m->body_inertia[3 * b + k], rig.bone_inertia_local[i][k], 1e-14);
          EXPECT_NEAR(m->body_ipos[3 * b + k], 0.0, 1e-14);
        }
        EXPECT_NEAR(std::abs(m->body_iquat[4 * b]), 1.0, 1e-14);

        const Mat3 R_rig = rest.orient_world[i].toRotationMatrix();
        mass_rig.push_back(rig.bone_mass[i]);
        com_rig.push_back(0.5 * (rest.head_world[i] + rest.tail_world[i]));
        I_rig.push_back(R_rig * rig.bone_inertia_local[i].asDiagonal() * R_rig.transpose());
        Mat3 R_mj;
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) R_mj(r, c) = d->ximat[9 * b + 3 * r + c];
        }
        const Vec3 diag(m->body_inertia[3 * b], m->body_inertia[3 * b + 1],
                        m->body_inertia[3 * b + 2]);
        mass_mj.push_back(m->body_mass[b]);
        com_mj.push_back(Vec3(d->xipos[3 * b], d->xipos[3 * b + 1], d->xipos[3 * b + 2]));
        I_mj.push_back(R_mj * diag.asDiagonal() * R_mj.transpose());
      }
      // the whole rig at rest: total mass, centre of mass and inertia tensor about it
      const Composite a = composite(mass_rig, com_rig, I_rig);
      const Composite b = composite(mass_mj, com_mj, I_mj);
      EXPECT_NEAR(a.mass, b.mass, 1e-12);
      EXPECT_LT((a.com - b.com).norm(), 1e-12);
      EXPECT_LT((a.inertia - b.inertia).cwiseAbs().maxCoeff(), 1e-11 * a.inertia.norm());
    }
  }
}

TEST(MjcfExport, RestPoseOfTheModelIsTheRigsRestPose) {
  for (const std::string& path : shipped_rigs()) {
    SCOPED_TRACE(path);
    const Rig rig = load_rig(path);
    const BoneFrames rest = forward_kinematics(rig, rest_pose(rig));
    for (JointModel jm : {JointModel::kRigJoints, JointModel::kBallJoints}) {
      const MjModelPtr m = rig_to_mjmodel(rig, options(jm, 0.05));
      const MjDataPtr d(mj_makeData(m.get()));
      mj_forward(m.get(), d.get());  // qpos0
      Scene scene = test::scene_for(rig, preset_params("original"), 1);
      SimState s;
      init_state(scene, s);
      read_mujoco_state(rig, m.get(), d.get(), s);
      for (int i = 0; i < rig.nbone; ++i) {
        EXPECT_LT((s.frames.head_world[i] - rest.head_world[i]).norm(), 1e-12) << rig.bone_name[i];
        EXPECT_LT((s.frames.tail_world[i] - rest.tail_world[i]).norm(), 1e-12) << rig.bone_name[i];
      }
      EXPECT_LT(max_joint_separation(rig, s.frames), 1e-12);
    }
  }
}

TEST(MjcfExport, JointTypesFollowTheDegreesOfFreedom) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const MjModelPtr m = rig_to_mjmodel(rig, MjcfOptions{});
  const auto joints_of = [&](const std::string& bone) {
    std::vector<int> types;
    const int b = rig.find_bone(bone) + 1;
    for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
      types.push_back(m->jnt_type[j]);
    }
    return types;
  };
  EXPECT_EQ(joints_of("head"), std::vector<int>{mjJNT_FREE});                   // the root
  EXPECT_EQ(joints_of("thigh.L"), std::vector<int>{mjJNT_BALL});                // 3 DOF, free
  EXPECT_EQ(joints_of("hip.L"), std::vector<int>{});                            // 0 DOF: welded
  EXPECT_EQ(joints_of("torso"), (std::vector<int>{mjJNT_HINGE, mjJNT_HINGE}));  // 2 DOF
  ASSERT_EQ(joints_of("forearm.L"), std::vector<int>{mjJNT_HINGE});             // 1 DOF
  // the forearm's hinge turns about its free local z axis within [-160, 0] deg
  const int j = m->body_jntadr[rig.find_bone("forearm.L") + 1];
  EXPECT_EQ(m->jnt_axis[3 * j + 2], 1.0);
  EXPECT_TRUE(m->jnt_limited[j]);
  EXPECT_NEAR(m->jnt_range[2 * j], deg2rad(-160.0), 1e-12);
  EXPECT_NEAR(m->jnt_range[2 * j + 1], 0.0, 1e-12);
  // 6 (root) + 2 (torso) + 2 x (3 thigh + 1 shin + 3 foot) + 2 x (3 upper arm + 1 forearm + 3 hand)
  EXPECT_EQ(m->nv, 6 + 2 + 2 * 7 + 2 * 7);

  // ball joints everywhere in the same-forces model: 6 + 3 per non-root bone, no limits
  const MjModelPtr mb = rig_to_mjmodel(rig, options(JointModel::kBallJoints, 0.05));
  EXPECT_EQ(mb->nv, 6 + 3 * (rig.nbone - 1));
  for (int k = 0; k < mb->njnt; ++k) EXPECT_FALSE(mb->jnt_limited[k]);

  // a limited 3-DOF bone (hand rig's first phalanges) becomes three limited hinges
  const Rig hand = load_rig(test::model_path("rigs/hand.json"));
  const MjModelPtr mh = rig_to_mjmodel(hand, MjcfOptions{});
  const int b = hand.find_bone("index.1") + 1;
  EXPECT_EQ(mh->body_jntnum[b], 3);
}

TEST(MjcfExport, PhysicsOptionsAreTheEnginesOwn) {
  const Rig rig = load_rig(test::model_path("rigs/chain3.json"));
  const MjModelPtr m = rig_to_mjmodel(rig, options(JointModel::kRigJoints, 0.02));
  EXPECT_EQ(m->opt.timestep, 0.02);
  EXPECT_EQ(m->opt.integrator, mjINT_EULER);
  EXPECT_EQ(m->opt.gravity[0], 0.0);
  EXPECT_EQ(m->opt.gravity[1], 0.0);
  EXPECT_EQ(m->opt.gravity[2], 0.0);
  EXPECT_TRUE(m->opt.disableflags & mjDSBL_CONTACT);
  for (int g = 0; g < m->ngeom; ++g) {
    EXPECT_EQ(m->geom_contype[g], 0);
    EXPECT_EQ(m->geom_conaffinity[g], 0);
  }
}

TEST(MjcfExport, ShallowRigsStayInOneFile) {
  const Rig rig = load_rig(test::model_path("rigs/pinhead.json"));
  const auto files = rig_to_mjcf_files(rig, MjcfOptions{}, "pinhead.xml");
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].name, "pinhead.xml");
  EXPECT_EQ(files[0].text, rig_to_mjcf(rig, MjcfOptions{}));
}

TEST(MjcfExport, OneFileFailsBeyondMujocosXmlDepthIncludeFilesDoNot) {
  // MuJoCo 2.2.2's parser stops at ~100 nested elements (XML_ELEMENT_DEPTH_EXCEEDED)
  const Rig chain = make_chain_rig(120, 0.5, 0.2);
  EXPECT_THROW(compile_mjcf(rig_to_mjcf(chain, options(JointModel::kBallJoints, 0.05))),
               std::runtime_error);
  const auto files = rig_to_mjcf_files(chain, options(JointModel::kBallJoints, 0.05));
  EXPECT_EQ(files.size(), 2u);  // 64 bodies per file
  EXPECT_EQ(rig_to_mjmodel(chain, options(JointModel::kBallJoints, 0.05))->nbody, 121);
}

TEST(MjcfExport, FiveHundredBoneChainCompilesAndRunsAsTheExactSolve) {
  // through nested include files: the model's rest pose is the rig's, and three steps of MuJoCo's
  // same-forces run equal the exact joint solve's (the tail pulled sideways)
  const int n = 500;
  const Rig chain = make_chain_rig(n, 0.5, 0.2);
  Scene scene = test::scene_for(chain, preset_params("original"), 3);
  scene.params.scheme = Scheme::kExact;
  scene.control_points.push_back(test::control(n - 1, 1.0, Vec3(5.0, 0.0, 0.5 * n), 10.0));
  SimState p;
  init_state(scene, p);
  const auto t0 = std::chrono::steady_clock::now();
  MujocoReference ref(scene, ReferenceMode::kSameForces);  // compiles the ball-joint MJCF
  const double compile_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "[mjcf] " << n << "-bone chain: " << rig_to_mjcf_files(chain, MjcfOptions{}).size()
            << " files, compiled (and first mj_step1) in " << compile_s << " s\n";
  RecordProperty("compile_s_500", std::to_string(compile_s));
  const mjModel* m = ref.model();
  ASSERT_EQ(m->nbody, n + 1);
  ASSERT_EQ(m->nv, 6 + 3 * (n - 1));
  const BoneFrames rest = forward_kinematics(chain, rest_pose(chain));
  for (int i = 0; i < n; ++i) {
    ASSERT_LT((ref.state().frames.tail_world[i] - rest.tail_world[i]).norm(), 1e-9) << i;
  }
  double gap = 0.0;
  for (int k = 0; k < scene.steps; ++k) {
    step(scene, p);
    ref.step();
    for (int i = 0; i < n; ++i) {
      gap = std::max({gap, (p.frames.head_world[i] - ref.state().frames.head_world[i]).norm(),
                      (p.frames.tail_world[i] - ref.state().frames.tail_world[i]).norm()});
    }
  }
  std::cout << "[mjcf] " << n << "-bone chain, 3 steps: exact vs MuJoCo gap " << gap << "\n";
  EXPECT_LT(gap, 1e-9);
  EXPECT_GT((p.frames.tail_world[n - 1] - rest.tail_world[n - 1]).norm(), 1e-3);  // it moved
}

// Names the readers accept (printable UTF-8: quotes, '<', '&', "--" and "-->" that would end an
// XML comment, MuJoCo's own "world", the static geoms' "ground" and "obstacle:..." names, spaces,
// non-ASCII, 300 characters), as the first bones of a chain n bones long up +z, read by the rig
// reader (which accepts every one)
Rig hostile_chain(int n) {
  const std::vector<std::string> hostile = {"a\"b<c>&'d",
                                            "x--y",
                                            "-",
                                            "--",
                                            "-->",
                                            "<!--",
                                            "]]>",
                                            "world",
                                            "ground",
                                            "obstacle:seat",
                                            " ",
                                            "  lead",
                                            "trail ",
                                            "caf\u00e9",
                                            "\u2603",
                                            "\u0085nel",
                                            "\uffff",
                                            "\U0010ffff",
                                            std::string(300, 'x'),
                                            "a:free",
                                            "&amp;",
                                            "%s",
                                            "\\",
                                            "{}",
                                            "seat"};
  Json bones = Json::array();
  for (int i = 0; i < n; ++i) {
    const std::string name =
        i < static_cast<int>(hostile.size()) ? hostile[i] : "b" + std::to_string(i);
    bones.push_back({{"name", name},
                     {"parent", i == 0 ? Json(nullptr) : bones[i - 1]["name"]},
                     {"head", {0.0, 0.0, 0.1 * i + 1.0}},
                     {"tail", {0.0, 0.0, 0.1 * i + 1.1}}});
  }
  return rig_from_json(Json{{"name", "r--<\"&\u00e9>"}, {"bones", bones}}, "hostile.json");
}

// Those names never make MuJoCo reject the file: a chain deep enough for include files (whose
// comments name bones), with a ground, boxes named like bones and self-collision, compiles from
// its exported MJCF, every body but the one named "world" (MuJoCo's world body) named as its bone.
TEST(MjcfExport, HostileNamesCompileAndComeBackUnchanged) {
  const int n = 120;  // deeper than kMjcfBodiesPerFile
  const Rig rig = hostile_chain(n);
  ASSERT_EQ(rig.nbone, n);
  Scene scene = test::scene_for(rig, preset_params("robust"), 1);
  scene.collision.ground = GroundPlane{};
  for (const char* name : {"seat", "ground", "b40", "--"}) {
    BoxObstacle box;
    box.name = name;
    box.center_world = Vec3(3.0, 0.0, 0.5);
    scene.collision.obstacles.push_back(box);
  }
  scene.collision.self_collision = true;
  scene.collision.excluded_pairs = {{0, 5}, {2, 9}};
  for (const JointModel joints : {JointModel::kBallJoints, JointModel::kRigJoints}) {
    MjcfOptions o;
    o.joints = joints;
    const std::vector<MjcfFile> files = rig_to_mjcf_files(rig, mjcf_contacts(scene, o));
    ASSERT_GE(files.size(), 2u);
    MjModelPtr m;
    ASSERT_NO_THROW(m = compile_mjcf(files));
    ASSERT_EQ(m->nbody, n + 1);
    for (int i = 0; i < n; ++i) {
      const char* got = mj_id2name(m.get(), mjOBJ_BODY, i + 1);
      ASSERT_NE(got, nullptr) << i;
      if (rig.bone_name[i] == "world") {
        EXPECT_NE(std::string(got), "world");
      } else {
        EXPECT_EQ(std::string(got), rig.bone_name[i]) << i;
      }
    }
    EXPECT_EQ(m->ngeom, n + 1 + 4);  // the bones, the ground, the boxes
  }
}

TEST(MjcfExport, BadMjcfIsReportedWithMujocosMessage) {
  EXPECT_THROW(
      compile_mjcf(
          "<mujoco><worldbody><body><joint type=\"nonsense\"/></body></worldbody></mujoco>"),
      std::runtime_error);
  EXPECT_THROW(compile_mjcf("not xml"), std::runtime_error);
}

// The bytes of this process's address space (/proc/self/statm: its first field, in pages).
long address_space_bytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0;
  statm >> pages;
  return pages * sysconf(_SC_PAGESIZE);
}

// MuJoCo's error when it cannot allocate a model's data (mju_error, whose default handler ends the
// process with status 1) comes back from make_mjdata as MjcfAllocationError, and from
// make_rig_mjdata as the InputError a model it cannot allocate gives: the stack is sized at 16 GiB
// with the address space capped 1 GiB above what the process holds. Afterwards MuJoCo's own
// handler is back and a data that fits is made.
TEST(MjcfExport, DataMujocoCannotAllocateIsAnErrorNotAnExit) {
  if (PHYSIK_SANITIZED)
    GTEST_SKIP() << "a sanitized process reserves more address space than a cap";
  const Rig rig = load_rig(test::model_path("rigs/elbow.json"));
  const MjcfOptions o = options(JointModel::kRigJoints, 0.01);
  const MjModelPtr m = rig_to_mjmodel(rig, o);
  const int nstack = m->nstack;
  m->nstack = std::numeric_limits<int>::max();
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &old), 0);
  rlimit cap = old;
  cap.rlim_cur = static_cast<rlim_t>(address_space_bytes()) + (rlim_t{1} << 30);
  ASSERT_TRUE(old.rlim_cur == RLIM_INFINITY || cap.rlim_cur < old.rlim_cur);
  ASSERT_EQ(setrlimit(RLIMIT_AS, &cap), 0);
  std::string plain, input;
  try {
    make_mjdata(m.get());
  } catch (const MjcfAllocationError& e) {
    plain = e.what();
  }
  try {
    make_rig_mjdata(rig, o, m.get());
  } catch (const InputError& e) {
    input = e.what();
  }
  ASSERT_EQ(setrlimit(RLIMIT_AS, &old), 0);
  EXPECT_NE(plain.find("MuJoCo could not allocate the model's data: "), std::string::npos) << plain;
  EXPECT_NE(plain.find("allocate memory"), std::string::npos) << plain;  // MuJoCo's own words
  EXPECT_NE(input.find("MuJoCo ran out of memory"), std::string::npos) << input;
  EXPECT_NE(input.find(plain), std::string::npos) << input;
  EXPECT_EQ(mju_user_error, nullptr);
  m->nstack = nstack;
  EXPECT_NE(make_mjdata(m.get()), nullptr);
}

}  // namespace
}  // namespace physik
