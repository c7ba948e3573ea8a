// Rig -> MJCF: the same rig as a MuJoCo articulated model
// (docs/engine.md "MuJoCo as the reference").
//
// Bodies: one per rigid body of the rig, nested in DFS order and named after its first bone: a
// bone that is not welded starts one, and every bone welded to it (rig.h "Welds") joins it as a
// geom, MuJoCo's own form of one rigid body. Every body frame sits at its first bone's centre of
// mass with that bone's axes (local +Y along the bone), so for a body of one bone
//   xipos = xpos = centre of mass,  xquat = orientation world<-bone,
//   head = xpos - R (0, L/2, 0),  tail = xpos + R (0, L/2, 0);
// a welded bone sits at the fixed offset mjcf_body_offset in its body's frame. A body of one bone
// carries <inertial pos="0 0 0" mass="m" diaginertia="Ixx Iyy Izz"/> with PhysIK's rod (rig.h:
// solid cylinder about its centre, bone-local axes); a welded group its composite mass, centre
// and full inertia (parallel axes) in the body frame. In its parent bone's frame a child body sits
// at
//   pos  = h - (0, L_parent/2, 0) + Q (0, L/2, 0)     h = bone_head_in_parent (the parent's tail)
//   quat = Q = R_rest_in_parent * exp(locked angles)
// (then moved into the frame of the parent bone's body) and its joints are at its head,
// pos = (0, -L/2, 0).
//
// Joints (JointModel):
//   kRigJoints (exact-constraints mode, `physik export-mjcf` default):
//     root                     free joint (6 DOF; its qpos is the body's world pose); a pinned
//                              root's joint to the world is a ball's (below) at its head, a fixed
//                              root has none
//     welded bone              no joint: a geom of its group's body
//     3 free, unlimited axes   ball joint (no limit)
//     3 DOF, some axis limited three hinges x, y, z, each with its range (a ball's limit is a cone,
//                              which cannot express per-axis intervals)
//     2 DOF (one axis locked)  two hinges about the free local axes, in x, y, z order, with their
//                              ranges. Their composition exp(t1 a1) exp(t2 a2) has rotation-vector
//                              components (t1, t2) only to first order: the rotation vector puts
//                              about t1 t2 / 2 rad (second order) on the locked axis. They are
//                              the engine's universal joint, and the violation is measured in its
//                              coordinates (joint_angles.h, LockedAxes::kRemoved), which read 0.
//     1 DOF                    one hinge about the free axis, range = the limit (rad)
//     0 DOF                    no joint: welded at its locked angles
//   kHingeJoints (same-forces mode of the exact and implicit schemes): the joints of the rig's
//     joint model (rig.h "Locked axes"), no limits: a ball where no axis is locked, one hinge
//     (two locked axes), two hinges in x, y, z order (one locked axis: MuJoCo has no universal
//     joint, and its hinges in one body turn in sequence, the second's axis with the first, the
//     engine's universal joint), no joint (three locked), the body turned by the lock rotation L
//     as above; exactly the engine's coordinates, whose limits on free axes are torsion springs
//     applied as forces.
//   kBallJoints (same-forces mode of the gauss-seidel scheme): a ball at every non-root bone that
//     is not welded and no limits, i.e. exactly the freedom of the paper's bones, whose limits,
//     locked axes included, are torsion springs applied as forces.
// Physics: the Euler integrator, timestep = the scene's dt. Geoms are the bones' collision
// capsules (rig.h bone_collision_radius, by default 0.06 x the length) and carry no mass
// (inertiafromgeom="false"). By default (MjcfOptions without contacts) no gravity, contacts
// disabled and every geom contype = conaffinity = 0: the capsules are for viewing only.
// With the scene's contacts and gravity (mjcf_contacts):
//   <option gravity> the scene's; the ground a plane geom (contype 0, conaffinity 1) through
//   height x normal with its z axis along the normal; each static obstacle a box geom in the
//   worldbody (size = its half extents, pos and quat its centre and rotation, contype 0,
//   conaffinity 1); the bones contype 1, conaffinity 1 with self-collision (else 0: they touch
//   the plane and the boxes only); friction "mu 0.005 0.0001" (sliding mu,
//   MuJoCo's default torsional and rolling); MuJoCo's default solref (0.02 1) and solimp: its
//   soft contacts are its own, not PhysIK's penalty law (ground_contacts.h, self_contacts.h), and
//   the comparison says so. Bones that share a joint never collide in PhysIK: MuJoCo's filterparent
//   flag (on by default) drops parent-child pairs, and <contact><exclude> drops the rest (two
//   children of one parent) and the scene's and the rig's collision_exclude pairs.
// Units: the rig's (rig units, kg, s), angles in radians (compiler angle="radian").
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "physik/model/rig.h"
#include "physik/model/scene.h"

namespace physik {

enum class JointModel { kRigJoints, kHingeJoints, kBallJoints };

struct MjcfOptions {
  JointModel joints = JointModel::kRigJoints;
  double dt = 0.05;             // s, <option timestep>
  std::string source;           // the rig's file, for error messages ("" = the rig's name)
  std::string contacts_source;  // the scene whose contacts these are (mjcf_contacts), or ""
  // contacts and gravity (none by default: the MJCF of a rig as it has always been written)
  Vec3 gravity = Vec3::Zero();  // rig units/s^2
  ContactModel collision;       // the ground and self-collision
  double friction = 1.0;        // sliding mu
};

// The options above with a scene's gravity, ground, self-collision and friction.
MjcfOptions mjcf_contacts(const Scene& scene, MjcfOptions options);

// Deepest body tree written (bones from the root to the deepest leaf): the writer recurses once
// per level, and MuJoCo's compile grows about as N^3 on chains long before this; a deeper rig is an
// InputError naming the rig file.
constexpr int kMaxMjcfDepth = 5000;

// MuJoCo 2.2's buffers for the model, written as <size nconmax njmax> (MuJoCo's defaults, 100
// contacts and 500 constraint rows, drop contacts on the 1,000-bone coil, and MuJoCo only warns):
//   contacts  2 per bone on the ground (a capsule on a plane touches at its two end spheres),
//             2 per bone and box it can touch at once (boxes a capsule touches together lie within
//             its length and diameter of each other: at most the most boxes within the longest
//             capsule's extent of one box, by their bounding spheres; boxes far apart count one),
//             and with self-collision 2 per bone pair (parallel capsules touch
//             at two points) for the candidate pairs (bones sharing a joint and the excluded
//             pairs left out) up to one pair per bone;
//   rows      4 per contact (condim 3 in MuJoCo's pyramidal friction cone: 2 (condim - 1)) and
//             one per limited hinge (JointModel::kRigJoints);
// never below MuJoCo's defaults. MuJoCo 2.2.2 allocates mjData in one buffer of at most INT_MAX
// bytes holding two njmax x nv Jacobians and an njmax x njmax matrix (efc_AR): njmax stops where
// those pass kMjcfConstraintBytes, and a run that needs more rows raises MuJoCo's constraint-full
// warning, which the runner reports (mujoco_runner.h mujoco_warning). nstack is MuJoCo's own
// default, which grows with njmax.
constexpr int kMujocoDefaultNconmax = 100;
constexpr int kMujocoDefaultNjmax = 500;
constexpr double kMjcfConstraintBytes = 1.5e9;  // bytes
struct MjcfSize {
  int nconmax = kMujocoDefaultNconmax;
  int njmax = kMujocoDefaultNjmax;
  long rows_needed = 0;  // the rows the counts above ask for (njmax unless capped)
};
MjcfSize mjcf_size(const Rig& rig, const MjcfOptions& options);

// The MJCF text of the rig, in one file (names as XML entities where they hold & < > " ', and
// unique where MuJoCo needs them so: a bone named "world", MuJoCo's world body, is written
// "world_2", and a ground or box whose name a bone has takes the first free "_2", "_3" suffix;
// comments carry names with "--" broken up).
// MuJoCo 2.2.2's XML parser rejects elements nested about 100 deep (XML_ELEMENT_DEPTH_EXCEEDED):
// one file holds rigs up to about 95 bones deep.
std::string rig_to_mjcf(const Rig& rig, const MjcfOptions& options);

// The MJCF of a rig of any depth: files[0] is the main file (named main_name); once a file's
// bodies nest kMjcfBodiesPerFile deep, the children of the deepest body go into an include file
// stem.partK.xml (stem = main_name without .xml; <include file="..."/> inside the body, the
// bodies inside <mujocoinclude>), which may include further files. MuJoCo resolves every include
// relative to the main file's folder: write them all beside it. A rig within one file's depth
// gives exactly rig_to_mjcf's text.
struct MjcfFile {
  std::string name;  // file name (files[0]: main_name; includes: names relative to its folder)
  std::string text;
};
constexpr int kMjcfBodiesPerFile = 64;
// InputError "<option>: must be a positive finite number of seconds" unless dt is one (the CLI's
// --dt, Python's dt).
void check_mjcf_timestep(double dt, const std::string& option);

std::vector<MjcfFile> rig_to_mjcf_files(const Rig& rig, const MjcfOptions& options,
                                        const std::string& main_name = "physik_rig.xml");

// The fixed rotation between bone i's rest frame and its body frame at zero joint angles: the
// lock rotation L (Rig::bone_joint_lock) for rig and hinge joints, identity for a free or fixed
// root, welds, ball joints and every bone of kBallJoints.
Quat mjcf_joint_offset(const Rig& rig, int bone, JointModel joints);

// The name of each bone's body and geom in the MJCF: the bone's, but "world" (MuJoCo's world
// body) which takes a "_2" suffix.
std::vector<std::string> mjcf_bone_names(const Rig& rig);

// Where bone i sits in the frame of its body (the body of its first bone, Rig::bone_body): its
// centre of mass and axes, fixed; zero and identity for a body's first bone.
struct MjcfBodyOffset {
  Vec3 pos = Vec3::Zero();       // rig units, body frame
  Quat quat = Quat::Identity();  // body <- bone
};
MjcfBodyOffset mjcf_body_offset(const Rig& rig, int bone);

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

// Compile MJCF text from memory (mjVFS on the heap). Throws std::runtime_error with MuJoCo's
// message if the compiler rejects it (MjcfAllocationError where it runs out of memory).
MjModelPtr compile_mjcf(const std::string& xml);
// Compile a main file and its include files (rig_to_mjcf_files), all through the VFS.
MjModelPtr compile_mjcf(const std::vector<MjcfFile>& files);

// compile_mjcf's error when MuJoCo cannot allocate the model's buffers ("Could not allocate
// memory": its compiler makes an mjData of nconmax contacts and njmax constraint rows).
class MjcfAllocationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// compile_mjcf of the rig's MJCF files (rig_to_mjcf_files with `options`): where MuJoCo cannot
// allocate the buffers, an InputError naming the contacts' scene (options.contacts_source, else
// the rig's file), the field that sized them and the sizes asked for.
MjModelPtr compile_rig_mjcf(const Rig& rig, const MjcfOptions& options,
                            const std::vector<MjcfFile>& files);

// rig_to_mjcf_files + compile_rig_mjcf (any depth).
MjModelPtr rig_to_mjmodel(const Rig& rig, const MjcfOptions& options);

// mj_makeData, with MuJoCo's error when it cannot allocate the data (mju_error "Could not
// allocate memory", whose default handler ends the process with status 1) thrown as
// MjcfAllocationError: the handler is MuJoCo's own pattern for its Python bindings, a longjmp
// back to this call (no C++ frame lies between, so nothing is skipped that needs unwinding),
// installed for the call alone. What MuJoCo had allocated before the error is not freed.
MjDataPtr make_mjdata(const mjModel* m);
// make_mjdata of a model rig_to_mjmodel made: where MuJoCo cannot allocate the data, the
// InputError compile_rig_mjcf gives when it cannot allocate the model.
MjDataPtr make_rig_mjdata(const Rig& rig, const MjcfOptions& options, const mjModel* m);

}  // namespace physik
