// Collision detection for the contacts (ground_contacts.h, self_contacts.h): which shapes of a
// scene overlap, where and how deep. The force laws are those files'; this one only measures the
// geometry.
//
// Source: FCL, the Flexible Collision Library (J. Pan, S. Chitta, D. Manocha, ICRA 2012; Debian
// libfcl-dev 0.7): its dynamic AABB tree for the broad phase and its capsule-capsule signed
// distance (fcl/narrowphase/detail/primitive_shape_algorithm/capsule_capsule.h: the closest
// points of the two centre segments, Ericson, Real-Time Collision Detection, 2005, 5.1.9),
// called directly: fcl::distance dispatches a capsule pair to the same function through a
// generic traversal it sets up per pair.
//
// Shapes (scene.h ContactModel, rig.h bone_collision_radius):
//   bone i   the capsule around its segment head-tail, radius r_i
//   ground   the plane {x : n . x = h}; bodies belong on the side n points to
//   obstacle a static box: centre c, rotation R, half extents e (its points R q + c, |q_j| <= e_j)
// Queries (depth d > 0 means the shapes overlap by d):
//   capsule-capsule  FCL's signed distance s < 0 and its witness points p_a, p_b on the two
//                    surfaces (p_b - p_a = s v, v the unit vector from a's segment point to b's):
//                    d = -s, normal n = -v (from b toward a), point (p_a + p_b) / 2. Centre
//                    lines that cross take v along the cross product of their directions
//                    (FCL's rule).
//   capsule-plane    the deepest point of the capsule is the bottom of one of its two end
//                    spheres (centre e): d = r - (n . e - h) for each end. A bone lying flat
//                    touches at both ends, a tilted one at its deepest end only (MuJoCo's
//                    mjc_PlaneCapsule gives the same two contacts). This is one dot product per
//                    end, so it is written here rather than asked of FCL (whose capsule-halfspace
//                    query returns only one of the two, through a heap-allocated contact list).
//   capsule-box      like the plane, spheres of radius r on the centre segment: one at each end,
//                    and one at the segment's point deepest in the box, t* = argmin_t s(a + t
//                    (b - a)) with s the box's signed distance (convex, so a golden-section
//                    search finds it), when s(t*) is below both ends' (by 1e-6 r): a bone lying
//                    on a face touches at its ends, a bone across an edge at the edge too. Each
//                    sphere against the box is FCL's sphereBoxIntersect (fcl/narrowphase/detail/
//                    primitive_shape_algorithm/sphere_box.h, exact: outside, d = r - |C - N| with
//                    N the box point nearest the centre C, normal (C - N)/|C - N|; inside, d = r +
//                    the distance to the nearest face, normal that face's). The deepest-point
//                    sphere appears at the depth of an end's when a segment turns past an edge:
//                    the force steps there (MuJoCo's capsule-box has such switches as well).
//                    FCL's generic capsule-box (GJK/EPA through libccd) allocates per call; the
//                    sphere-box routine writes into a vector kept with the world.
//   The contact point is midway between the two surfaces (the ground's: the plane), as MuJoCo
//   places its contacts.
//
// Broad phase (self-collision only): FCL's DynamicAABBTreeCollisionManager over the bone
// capsules, refitted at every call. Pairs of bones that share a joint (Rig::bones_share_joint),
// and the scene's and the rig's excluded pairs (Rig::collision_exclude), are dropped before the
// narrow phase; the candidate pairs are sorted so the contacts' order (and the float sums of their
// forces) depends on the shapes only. The ground needs no broad phase: every bone is tested against
// it, O(n). Obstacles: each bone against each box, after a bounding-box test in the box's frame
// (the box grown by r), O(n m).
//
// The world is built on first use for a scene (the FCL objects, allocated once) and rebuilt only
// when the rig or the settings change; a copy of a world starts empty and builds its own.
// Units: rig units.
#pragma once

#include <memory>
#include <vector>

#include "physik/model/kinematics.h"
#include "physik/model/scene.h"

namespace physik {

// One overlap of two shapes: body a is a bone; body b another bone, or the ground.
struct Contact {
  int bone = -1;                      // body a
  int other_bone = -1;                // body b when it is a bone; -1: static (ground, obstacle)
  int obstacle = -1;                  // body b's index in ContactModel::obstacles, or -1
  int feature = 0;                    // which of the pair's contacts: against the ground or a box,
                                      //   0 the head's end sphere, 1 the tail's, 2 the segment's
                                      //   deepest point (a box's edge); 0 between two bones
  Vec3 point_world = Vec3::Zero();    // rig units, midway between the two surfaces
  Vec3 normal_world = Vec3::UnitZ();  // unit, from body b toward body a
  double depth = 0.0;                 // rig units, > 0
  double normal_force =
      0.0;  // N, F_n of the force stage (ground_contacts.h, self_contacts.h); 0 until it runs
};

class CollisionWorld {
 public:
  CollisionWorld();
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&);             // starts empty: builds its own on first use
  CollisionWorld& operator=(const CollisionWorld&);  // likewise
  CollisionWorld(CollisionWorld&&) noexcept;
  CollisionWorld& operator=(CollisionWorld&&) noexcept;

  // Every overlap of the scene's shapes with the bones at `frames`, into `out` (cleared first):
  // the ground's, bone by bone; the obstacles', obstacle by obstacle and bone by bone; then the
  // bone pairs' in order of (a, b), a < b.
  void detect(const Scene& scene, const BoneFrames& frames, std::vector<Contact>& out);
  // Build the FCL objects for a scene now (detect does on first use), so that a run's steps
  // allocate nothing for them.
  void prepare(const Scene& scene);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace physik
