// MJCF -> rig: a MuJoCo model, loaded and compiled by MuJoCo itself (mj_loadXML), as a PhysIK rig.
//
// Kinematic tree: every body of the chosen subtree is a pivot (pivot_rig.h) at its rest world
// origin xpos (the model's qpos0 configuration, after mj_kinematics) turning with its world
// rotation xquat. A body's bones run from its origin to each distinct child-body origin; a body
// with no child away from its origin (a leaf) gets a tail from its geometry: the farthest end of
// its geoms (capsule/cylinder: segment end plus capsule radius; box/ellipsoid: the longest
// half-axis; sphere and others: geom centre + bounding radius along the parent -> body direction),
// else a short stub (max(geom rbound, 0.1 x offset from parent, 0.01)) along that direction. A body
// with several children gets one bone per child offset ("<body>><child>"); a root body with several
// gets a synthetic root bone ending at its origin (pivot_rig.h). FK of the rig then puts every
// bone's head at its body's xpos, for any qpos (pose_from_mujoco).
// The model's world body is not a bone. With several top-level bodies (22_humanoids, particles)
// one subtree is taken: the one named by MjcfImportOptions::root_body, else the largest (first on
// ties); the others are listed in the report.
//
// Mass and inertia: a body's mass is shared equally by the bones that follow it (its segments,
// and the synthetic root for the root body); a body with no bone of its own (a zero-offset child)
// gives its mass to the bone ending at its origin. Bone masses sum to the subtree's mass (bodies
// with zero mass give bones a floor of 1e-3 x the mean bone mass, counted in the report).
// Each bone's inertia is explicit (BoneSpec::inertia_local): its share of the body's inertia tensor
// (body_inertia in the frame ximat, about the body's centre of mass xipos) carried to the bone's
// midpoint with the parallel-axis term (m/k)(|r|^2 1 - r r^T), r = midpoint - xipos (equations in
// mjcf_import.cpp), expressed in the bone's rest frame, diagonal kept. What the rod model cannot
// carry is reported, not hidden: the dropped off-diagonal terms (relative to the largest moment)
// and the shift of the centre of mass from the body's xipos to the bones' midpoints (the rig puts
// a bone's mass at its midpoint, so the body's first moment about it is not carried).
//
// Radii: a bone's collision capsule radius (BoneSpec::collision_radius) is the radius (size[0]) of
// the capsule geom best aligned with it among those of its body and of the bodies at its head
// (zero-offset ancestors), in the model's length unit (the rig's: the import does not scale). The
// inertia cylinder's radius (BoneSpec::radius) takes the same value: it matters only where the
// body's inertia is unusable (the cylinder fallback) and for drawing, and the body's own thickness
// is a better guess there than the rig default 0.5. A bone whose bodies have no capsule takes the
// radius of their largest sphere geom (the humanoid's head and hands), the same for both; a bone
// with neither gets kRadiusPerLength x its length for both (rig_sizing.h) and is listed in the
// report (bones_fitted_radius). MjcfImportOptions::sizing can replace radii and masses.
//
// At rest (rest_limits.h, bone_overlaps.h): a limit whose torsion band holds the rest angle (the
// humanoid's knees, -160..2 deg) is widened until the band's edge is at rest, and the bone pairs
// whose capsules overlap at rest are added to the rig's collision_exclude; both are reported by
// bone (and axis), and written into the rig's source notes with every joint dropped, freed or
// clamped.
//
// Joints -> limits (rig.h: per bone-local axis, intervals on the rotation-vector components):
//   no joint (welded)        the bone is welded to its parent (rig.h "Welds"); a body's other
//                            segments are welded to its first, which alone carries its limits
//   hinges                   the bone's roll is chosen so that the first hinge not along the bone
//                            is its local x axis; each hinge maps to the bone-local axis it is
//                            within 20 deg of (range sign-flipped if anti-parallel; an unlimited
//                            hinge leaves its axis free); the axes no hinge maps to are locked. A
//                            hinge more than 20 deg from every axis makes the bone free (reported).
//   ball                     limited: every axis [-r, r] (r = its cone angle); otherwise free
//   free (root)              the rig's root is free; a root body with a hinge or ball to the world
//                            is a pinned root (its head held; arm26's shoulder), with none fixed
//   slide                    cannot be represented (bones have fixed lengths): dropped, reported
// Ranges beyond +-180 deg are clamped (reported). MuJoCo's ranges are radians in the compiled
// model.
#pragma once

#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "physik/model/kinematics.h"
#include "physik/model/pivot_rig.h"
#include "physik/model/rig_sizing.h"
#include "reference/mjcf_export.h"

namespace physik {

struct MjcfImportOptions {
  std::string root_body;  // body whose subtree becomes the rig; empty: the largest top-level one
  // radii and masses (rig_sizing.h): a radius replaces every geom's; mass_per_length replaces
  // the model's masses (cylinder inertias then), total_mass scales them
  SizingOptions sizing;
};

struct MjcfImportReport {
  int nbody_model = 0;                      // bodies in the model, without the world
  int nbody_used = 0;                       // bodies in the chosen subtree
  std::vector<std::string> skipped_bodies;  // other top-level bodies (roots of subtrees left out)
  double model_mass = 0.0;                  // kg, the chosen subtree in MuJoCo
  double rig_mass = 0.0;                    // kg, sum of bone masses
  int mass_floor_bones = 0;                 // bones given the floor mass (massless bodies)
  int slide_joints_dropped = 0;
  int unaligned_hinges = 0;                 // hinges > 20 deg from every bone axis (bone freed)
  double max_hinge_misalignment_deg = 0.0;  // of the mapped hinges
  int clamped_ranges = 0;
  // each joint dropped, freed or clamped, named with the bone it was to move: "bone 'left_foot':
  // hinge 'left_ankle_y' 35 deg from every bone axis", in the order met
  std::vector<std::string> dropped_slides;  // "bone 'b': slide joint 'j' of body 'c' dropped"
  std::vector<std::string> freed_bones;     // the bones an unaligned hinge freed, and why
  std::vector<std::string> clamped;         // "bone 'b': joint 'j' range ... clamped to +-180 deg"
  // limits whose torsion band held the rest angle, widened (rest_limits.h), and the tolerance
  // they were fitted for (the parameter table's torsion_tolerance)
  std::vector<std::string> widened_limits;
  double fitted_tolerance = 0.0;
  // the bone pairs whose capsules overlap at rest, added to the rig's collision_exclude
  std::vector<std::string> rest_overlaps;
  double max_offdiag_inertia = 0.0;  // dropped off-diagonal / largest moment
  double max_com_shift = 0.0;        // rig units, xipos vs the mean of its bones' midpoints
  int cylinder_inertia_bones = 0;    // bones whose body inertia was unusable (cylinder used)
  std::vector<std::string> bones_fitted_radius;  // bones with no capsule or sphere geom: radius
                                                 // fitted to their length (rig_sizing.h)
  std::string root_joint = "free";               // the root's joint to the world (rig.h)
};

struct MjcfRig {
  PivotRig pivots;                    // the rig (pivots.rig); node i <-> MuJoCo body node_body[i]
  std::vector<int> node_body;         // (nnode) MuJoCo body id
  std::vector<Quat> node_rest_xquat;  // (nnode) body orientation at qpos0
  MjcfImportReport report;
  const Rig& rig() const { return pivots.rig; }
};

// Load with mj_loadXML (MuJoCo resolves includes, defaults, assets). Throws InputError naming the
// file with MuJoCo's message if it cannot load it, or if the model has no body.
MjcfRig load_mjcf(const std::string& path, const MjcfImportOptions& options = {});
// From a compiled model; `source` names it in messages.
MjcfRig import_mjcf_model(const mjModel* m, const std::string& source,
                          const MjcfImportOptions& options = {});

// The rig pose of a MuJoCo configuration: `d` must hold xpos/xquat (mj_kinematics done).
Pose pose_from_mujoco(const MjcfRig& mr, const mjData* d);

}  // namespace physik
