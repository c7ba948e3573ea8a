// A human body inside a converted skeleton: the template's segments (human_template.h) fitted to
// the bones a converter made of a pivot tree (pivot_rig.h), each pivot named onto a segment by
// the joint-name table (physik/io/skeleton_names.h).
//
// Body axes from the skeleton's rest pose (rig world, rig units):
//   R = head of the right thigh - head of the left thigh        (right, normalised)
//   U = top - midpoint of the thighs' heads, R removed          (up; top: the first neck or head
//                                                                bone's head, else the spine's
//                                                                highest tail)
//   L = -R,  F = L x U                                          (left, forward)
// Height: the extent of every joint and end point of the rest pose along U (a figure lying down
// has its height all the same; `up_tilt` says how far U is from the rig's +Z).
//
// Each bone takes its pivot's segment (a pivot the table leaves out takes its parent's; the root's
// is the pelvis). Its rest frame is anatomical: the template's frame T = [x0, d0, x0 x d0] in body
// axes, turned by the shortest rotation W that takes d0 onto the bone's own direction:
//   S = W P,   P = B T (B = [F L U]) where the bone starts a chain (pelvis, a clavicle, an upper
//              arm, a thigh, the first spine bone above the pelvis);
//   P = S_parent T_parent^T T further down a chain (spine, neck and head; forearm, hand, fingers;
//              shank, foot, toes): the parent's frame carried over.
// So a knee's x axis is the body's left-right axis however the leg stands at rest, and an elbow
// bent or a T-pose's arm keeps its hinge across the arm (the elbow of a T-pose arm turns about
// the body's up axis: the template's palms-forward anatomical pose turned by 90 deg about F).
// Limits per local axis (rig.h AxisLimit) are the template's ranges; a region's ranges are shared
// by its bones (divided by their number); a shoulder's and a hip's are offset by the rest's turn
// from the anatomical direction, the rotation vector of W in the bone's frame (a T-pose's
// shoulder rests at 90 deg abduction: its abduction range starts from there). Locked axes stay at
// 0 (a hinge's other two axes). Then fit_limits_to_rest widens a range whose torsion band holds
// the rest angle (a knee's [0, 135] -> [-15, 135] at tolerance 0.1): a limit starting at rest
// would push the bone from the first step.
//
// Welds: a bone of a rigid segment (the pelvis, a clavicle, an upper arm, a forearm, a hand's
// palm, a thigh, a shank, a foot) whose parent is of the same segment is welded to it: the pelvis
// is one rigid body (CMU's LHipJoint and RHipJoint, three.js's buttocks, MakeHuman's pelvis.L and
// .R below the root), and a second bone of a long bone is a twist or deform helper, not a joint
// (MakeHuman's upperarm02.L, lowerleg02.L; DAZ's lThighTwist). The spine, the neck, the fingers
// and the toes keep their joints. Bones welded by the converter stay welded. A welded bone has no
// limits.
//
// Masses (kg): each de Leva row's share of the total mass, per side (a hand's 0.61 % to each
// hand), split among the bones of its segments as their rods' volumes (L^3, every radius being
// 0.14 L): a hand's bones and its fingers share the hand's, a foot's and its toes' the foot's. A
// row with no bone at all passes its share to the next one up its chain (a hand to its forearm, a
// foot to its shank, the head to the upper trunk, the middle trunk to the upper trunk, then to
// the lower). Inertia (kg m^2) about each bone's centre, local x, y, z:
//   I_x = m (r_trans L)^2,  I_y = m (r_long L)^2,  I_z = m (r_sag L)^2
// with the row's radii of gyration as fractions of the bone's own length L (the table's axes: x
// medio-lateral, z antero-posterior, y along the bone). The rig model puts a bone's centre of
// mass at its midpoint (rig.h): the table's centre-of-mass fractions (0.41 of a thigh from the
// hip, 0.79 of a hand from the wrist) are kept in the report, not in the rig.
//
// Forward axes (the face, a palm, the front of a knee): each bone's local vector of the body's F
// carried with its frame, T^T F: (0, 0, 1) on the spine, neck and head, (0, 0, -1) on a left
// limb hanging down, (0, 1, 0) on a foot.
#pragma once

#include <string>
#include <vector>

#include "physik/model/human_template.h"
#include "physik/model/pivot_rig.h"

namespace physik {

struct HumanBodyOptions {
  double total_mass = 0.0;         // kg; 0: kReferenceMass
  double torsion_tolerance = 0.1;  // 1, the band fit_limits_to_rest fits the limits to
};

// One de Leva row on one side: the table's mass beside the rig's.
struct HumanMassRow {
  std::string segment;       // "thigh.L", "head (with neck)", "upper trunk"
  double table_share = 0.0;  // 1, of the total mass
  double rig_share = 0.0;    // 1, the bones' masses over the rig's total
  int nbone = 0;             // bones that carry it (0: passed on)
  std::string passed_to;     // the row that took its mass, when it has no bone
  double table_com = 0.0;    // 1, the table's centre of mass from the lower end (the rig: 0.5)
};

struct HumanBodyFit {
  Vec3 forward_world = Vec3::UnitX(), left_world = Vec3::UnitY(), up_world = Vec3::UnitZ();
  double height = 0.0;              // rig units, along up_world
  double up_tilt = 0.0;             // rad, between up_world and the rig's +Z
  double total_mass = 0.0;          // kg
  std::vector<int> spec_segment;    // (nspec) index into human_segments()
  std::vector<std::string> welded;  // bones welded here ("LHipJoint to Hips")
  std::vector<HumanMassRow> masses;
  std::vector<std::string> widened;   // limits widened by fit_limits_to_rest (describe())
  std::vector<std::string> warnings;  // implausible proportions, feet pointing backward
};

// The body axes and the height of a skeleton whose pivots carry `node_segment` (index into
// human_segments(), -1 for none) at rest; `ok` false when a thigh is missing or the hips and the
// top coincide.
struct BodyAxes {
  bool ok = false;
  Vec3 forward = Vec3::UnitX(), left = Vec3::UnitY(), up = Vec3::UnitZ();
  double height = 0.0;  // rig units
};
BodyAxes human_body_axes(const std::vector<PivotNode>& nodes, const std::vector<int>& node_segment);

// Every pivot's segment: its own, else its parent's, the root's the pelvis.
std::vector<int> inherit_segments(const std::vector<PivotNode>& nodes,
                                  const std::vector<int>& node_segment);

// Fits the template to `bones` (frames, limits, welds, masses, inertias, segments and forward
// axes of the specs; radii and collision radii are the caller's). `node_segment` as
// inherit_segments returns it. Never produces a non-finite value: a degenerate skeleton (hips
// and top at one point) keeps the world's axes and says so in the warnings.
HumanBodyFit fit_human_body(const std::vector<PivotNode>& nodes,
                            const std::vector<int>& node_segment, PivotBones& bones,
                            const HumanBodyOptions& options = {});

}  // namespace physik
