// Collision detection: FCL's broad phase and capsule distance, the plane in closed form
// (collision.h).
#include "physik/engine/collision.h"

#include <algorithm>
#include <cstdint>
#include <utility>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/capsule_capsule.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_box.h>

namespace physik {

namespace {

using fcl::CollisionObjectd;

// FCL's capsule is centred on its frame with its axis along local z; a bone runs along its own
// local y. This rotation takes z to y (a turn of -90 degrees about x).
Mat3 z_to_y() {
  Mat3 r;
  r << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  return r;
}

// user data of an FCL object: its bone index
void* tag(std::size_t index) {
  return reinterpret_cast<void*>(static_cast<std::uintptr_t>(index));
}
int index_of(const CollisionObjectd* o) {
  return static_cast<int>(reinterpret_cast<std::uintptr_t>(o->getUserData()));
}

// A bone's FCL object with the capsule's own bounding box: FCL's computeAABB bounds a turned shape
// by the cube around its bounding sphere (sides 2 sqrt(2 r^2 + (L/2 + r)^2)), which on a coil
// makes each bone a candidate of several turns' bones; the capsule's box is the segment's, grown
// by r.
class BoneObject : public CollisionObjectd {
 public:
  using CollisionObjectd::CollisionObjectd;
  void set_capsule_aabb(const Vec3& head_world, const Vec3& tail_world, double radius) {
    const Vec3 r = Vec3::Constant(radius);
    aabb = fcl::AABBd(head_world.cwiseMin(tail_world) - r, head_world.cwiseMax(tail_world) + r);
  }
};

struct BroadPhaseData {
  const Scene* scene;
  std::vector<std::pair<int, int>>* pairs;
};

// a candidate pair from the AABB tree: kept unless the two bones may never touch
bool candidate(CollisionObjectd* o1, CollisionObjectd* o2, void* data) {
  auto* d = static_cast<BroadPhaseData*>(data);
  int a = index_of(o1), b = index_of(o2);
  if (a > b) std::swap(a, b);
  if (d->scene->rig.bones_share_joint(a, b)) return false;
  const auto& ex = d->scene->collision.excluded_pairs;
  if (std::binary_search(ex.begin(), ex.end(), std::make_pair(a, b))) return false;
  if (d->scene->rig.collision_excluded(a, b)) return false;  // the rig's own exclusions
  d->pairs->emplace_back(a, b);
  return false;  // false: go on
}

// Sort the pairs (a, b) by a, then b, in O(pairs + nbone): a counting sort by a into `scratch`,
// then each a's few partners by b. `start` is scratch of nbone + 1.
void sort_pairs(std::vector<std::pair<int, int>>& pairs, int nbone, std::vector<int>& start,
                std::vector<std::pair<int, int>>& scratch) {
  start.assign(static_cast<std::size_t>(nbone) + 1, 0);
  for (const auto& p : pairs) ++start[p.first + 1];
  for (int a = 0; a < nbone; ++a) start[a + 1] += start[a];
  scratch.resize(pairs.size());
  for (const auto& p : pairs) scratch[start[p.first]++] = p;  // start[a]: now a's end
  for (int a = nbone - 1, end = static_cast<int>(pairs.size()); a >= 0; --a) {
    const int begin = a > 0 ? start[a - 1] : 0;
    std::sort(scratch.begin() + begin, scratch.begin() + end);
    end = begin;
  }
  pairs.swap(scratch);
}

}  // namespace

struct CollisionWorld::Impl {
  std::vector<double> radius;  // (nbone) what the world was built for, rig units
  std::vector<double> length;  // (nbone) rig units
  std::vector<std::unique_ptr<BoneObject>> bones;  // (nbone) capsules
  fcl::DynamicAABBTreeCollisionManagerd tree;
  std::vector<std::pair<int, int>> pairs;  // the broad phase's candidates this call, scratch
  std::vector<std::pair<int, int>> pairs_scratch;  // scratch of sort_pairs
  std::vector<int> pair_start;                     // (nbone + 1) scratch of sort_pairs
  // the last query: its frames and exclusions, and the bone pairs' contacts it found
  BoneFrames last_frames;
  std::vector<int> last_parent;  // (nbone) the rig's parents
  std::vector<std::pair<int, int>> last_excluded;
  std::vector<std::pair<int, int>> last_rig_excluded;
  std::vector<Contact> last_pair_contacts;
  bool has_last = false;
  std::vector<fcl::ContactPointd> sphere_box;  // FCL's sphere-box answer, scratch (capacity 1)

  bool built_for(const Rig& rig) const {
    return radius == rig.bone_collision_radius && length == rig.bone_length;
  }
  bool same_query(const Scene& scene, const BoneFrames& frames) const {
    return has_last && last_frames.head_world == frames.head_world &&
           last_frames.tail_world == frames.tail_world &&
           last_frames.orient_world == frames.orient_world &&
           last_parent == scene.rig.bone_parent &&
           last_excluded == scene.collision.excluded_pairs &&
           last_rig_excluded == scene.rig.collision_exclude;
  }
  void remember(const Scene& scene, const BoneFrames& frames);
  void build(const Rig& rig);
  void place_bones(const BoneFrames& frames);
  void broad_phase(const Scene& scene);
  void pair_contacts(std::vector<Contact>& out) const;
  const fcl::Capsuled& capsule(int bone) const {
    return static_cast<const fcl::Capsuled&>(*bones[bone]->collisionGeometry());
  }
  void box_contacts(const Scene& scene, const BoneFrames& f, std::vector<Contact>& out);
  void sphere_in_box(const fcl::Boxd& box, const fcl::Transform3d& box_tf, const Vec3& centre,
                     double r, Contact& c, std::vector<Contact>& out);
};

void CollisionWorld::Impl::build(const Rig& rig) {
  radius = rig.bone_collision_radius;
  length = rig.bone_length;
  has_last = false;
  tree.clear();
  bones.clear();
  std::vector<CollisionObjectd*> objs;
  for (int i = 0; i < rig.nbone; ++i) {
    auto shape = std::make_shared<fcl::Capsuled>(radius[i], length[i]);
    bones.push_back(std::make_unique<BoneObject>(shape));
    bones.back()->setUserData(tag(i));
    objs.push_back(bones.back().get());
  }
  tree.registerObjects(objs);
  // FCL's update() refits the tree and, once its height passes log2(n) + this level, rebuilds it
  // top-down through a heap-allocated list of leaves (every few steps on a 1,000-bone coil):
  // always the incremental rebalance instead (tree rotations, no allocation)
  tree.max_tree_nonbalanced_level = 1 << 20;
  tree.setup();
  // room for the queries, so that a run's steps allocate nothing (as the state's contact lists)
  pairs.reserve(4 * static_cast<std::size_t>(rig.nbone));
  pairs_scratch.reserve(pairs.capacity());
  pair_start.reserve(static_cast<std::size_t>(rig.nbone) + 1);
  last_pair_contacts.reserve(2 * static_cast<std::size_t>(rig.nbone));
  last_frames.resize(rig.nbone);
  last_parent.reserve(rig.nbone);
}

void CollisionWorld::Impl::remember(const Scene& scene, const BoneFrames& frames) {
  last_frames.head_world = frames.head_world;
  last_frames.tail_world = frames.tail_world;
  last_frames.orient_world = frames.orient_world;
  last_parent = scene.rig.bone_parent;
  last_excluded = scene.collision.excluded_pairs;
  last_rig_excluded = scene.rig.collision_exclude;
  has_last = true;
}

void CollisionWorld::Impl::place_bones(const BoneFrames& f) {
  static const Mat3 kZtoY = z_to_y();
  for (std::size_t i = 0; i < bones.size(); ++i) {
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.linear() = f.orient_world[i].toRotationMatrix() * kZtoY;
    tf.translation() = 0.5 * (f.head_world[i] + f.tail_world[i]);
    bones[i]->setTransform(tf);
    bones[i]->set_capsule_aabb(f.head_world[i], f.tail_world[i], radius[i]);
  }
  tree.update();
}

void CollisionWorld::Impl::broad_phase(const Scene& scene) {
  pairs.clear();
  BroadPhaseData data{&scene, &pairs};
  tree.collide(&data, candidate);
  // the tree's order depends on its history: sort, so the contacts' order depends on the shapes
  sort_pairs(pairs, static_cast<int>(bones.size()), pair_start, pairs_scratch);
}

void CollisionWorld::Impl::pair_contacts(std::vector<Contact>& out) const {
  for (const auto& [a, b] : pairs) {
    // FCL's capsule-capsule distance, the function fcl::distance dispatches a capsule pair to
    // (its GJK solvers' shapeDistance), called directly: the same numbers without the generic
    // traversal's set-up per pair. Signed: negative when the capsules overlap; witness points
    // in the world frame.
    double s = 0.0;
    Vec3 pa, pb;
    fcl::detail::capsuleCapsuleDistance(capsule(a), bones[a]->getTransform(), capsule(b),
                                        bones[b]->getTransform(), &s, &pa, &pb);
    // a touch within round-off of the radii carries no force and has no reliable normal
    if (!(s < -1e-12 * (radius[a] + radius[b]))) continue;
    Contact c;
    c.bone = a;
    c.other_bone = b;
    c.depth = -s;
    c.normal_world = ((pa - pb) / s).normalized();  // -v: p_a - p_b = -s v
    c.point_world = 0.5 * (pa + pb);
    out.push_back(c);
  }
}

namespace {

// signed distance of a point q (box frame) to a box of half extents h: outside, the distance to
// the nearest point of the box; inside, minus the distance to the nearest face. Convex in q.
double box_signed_distance(const Vec3& q, const Vec3& h) {
  const Vec3 outside = (q.cwiseAbs() - h).cwiseMax(0.0);
  if (outside.squaredNorm() > 0.0) return outside.norm();
  return -(h - q.cwiseAbs()).minCoeff();
}

// the t in [0, 1] that minimises the box's signed distance along the segment a + t (b - a):
// golden-section search on a convex function, a fixed 48 shrinks (0.618^48 < 1e-9 of the bone)
double deepest_along(const Vec3& a, const Vec3& b, const Vec3& h) {
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = 0.0, hi = 1.0;
  double t1 = hi - kInvPhi * (hi - lo), t2 = lo + kInvPhi * (hi - lo);
  double f1 = box_signed_distance(a + t1 * (b - a), h);
  double f2 = box_signed_distance(a + t2 * (b - a), h);
  for (int k = 0; k < 48; ++k) {
    if (f1 <= f2) {
      hi = t2, t2 = t1, f2 = f1;
      t1 = hi - kInvPhi * (hi - lo);
      f1 = box_signed_distance(a + t1 * (b - a), h);
    } else {
      lo = t1, t1 = t2, f1 = f2;
      t2 = lo + kInvPhi * (hi - lo);
      f2 = box_signed_distance(a + t2 * (b - a), h);
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

// FCL's sphere-box contact of the sphere (centre, r) with the box; kept when it overlaps by more
// than round-off. FCL's normal points from the sphere into the box: ours, from the box.
void CollisionWorld::Impl::sphere_in_box(const fcl::Boxd& box, const fcl::Transform3d& box_tf,
                                         const Vec3& centre, double r, Contact& c,
                                         std::vector<Contact>& out) {
  sphere_box.clear();
  fcl::Transform3d sphere_tf = fcl::Transform3d::Identity();
  sphere_tf.translation() = centre;
  fcl::detail::sphereBoxIntersect(fcl::Sphered(r), sphere_tf, box, box_tf, &sphere_box);
  if (sphere_box.empty() || !(sphere_box[0].penetration_depth > 1e-12 * r)) return;
  c.depth = sphere_box[0].penetration_depth;
  c.normal_world = -sphere_box[0].normal;
  c.point_world = sphere_box[0].pos;
  out.push_back(c);
}

// each bone against each box: the spheres at its two ends and, where the segment dips deeper
// between them (across an edge or a corner), the sphere at its deepest point
void CollisionWorld::Impl::box_contacts(const Scene& scene, const BoneFrames& f,
                                        std::vector<Contact>& out) {
  const auto& obstacles = scene.collision.obstacles;
  for (std::size_t o = 0; o < obstacles.size(); ++o) {
    const BoxObstacle& b = obstacles[o];
    const fcl::Boxd box(2.0 * b.half_extents);
    fcl::Transform3d box_tf = fcl::Transform3d::Identity();
    box_tf.linear() = b.orient_world.toRotationMatrix();
    box_tf.translation() = b.center_world;
    const Mat3 to_box = box_tf.linear().transpose();
    for (int i = 0; i < scene.rig.nbone; ++i) {
      const double r = scene.rig.bone_collision_radius[i];
      const Vec3 qa = to_box * (f.head_world[i] - b.center_world);
      const Vec3 qb = to_box * (f.tail_world[i] - b.center_world);
      // the capsule's box in the box's frame misses the box grown by r: no contact
      const Vec3 reach = b.half_extents + Vec3::Constant(r);
      if ((qa.cwiseMin(qb).array() > reach.array()).any() ||
          (qa.cwiseMax(qb).array() < -reach.array()).any()) {
        continue;
      }
      Contact c;
      c.bone = i;
      c.obstacle = static_cast<int>(o);
      c.feature = 0;
      sphere_in_box(box, box_tf, f.head_world[i], r, c, out);
      c.feature = 1;
      sphere_in_box(box, box_tf, f.tail_world[i], r, c, out);
      c.feature = 2;
      const double t = deepest_along(qa, qb, b.half_extents);
      const double ends = std::min(box_signed_distance(qa, b.half_extents),
                                   box_signed_distance(qb, b.half_extents));
      if (box_signed_distance(qa + t * (qb - qa), b.half_extents) < ends - 1e-6 * r) {
        sphere_in_box(box, box_tf, f.head_world[i] + t * (f.tail_world[i] - f.head_world[i]), r, c,
                      out);
      }
    }
  }
}

namespace {

// each end sphere of each bone that sinks below the plane
void ground_contacts(const Scene& scene, const BoneFrames& f, std::vector<Contact>& out) {
  const GroundPlane& g = *scene.collision.ground;
  const Vec3& n = g.normal_world;
  for (int i = 0; i < scene.rig.nbone; ++i) {
    const double r = scene.rig.bone_collision_radius[i];
    for (int end = 0; end < 2; ++end) {
      const Vec3* e = end == 0 ? &f.head_world[i] : &f.tail_world[i];
      Contact c;
      c.bone = i;
      c.feature = end;
      c.normal_world = n;
      c.depth = r - (n.dot(*e) - g.height);
      if (!(c.depth > 0.0)) continue;
      c.point_world = *e - (r - 0.5 * c.depth) * n;  // midway: the sphere's bottom to the plane
      out.push_back(c);
    }
  }
}

bool finite_frames(const BoneFrames& f) {
  for (std::size_t i = 0; i < f.head_world.size(); ++i) {
    if (!f.head_world[i].allFinite() || !f.tail_world[i].allFinite() ||
        !f.orient_world[i].coeffs().allFinite()) {
      return false;
    }
  }
  return true;
}

}  // namespace

CollisionWorld::CollisionWorld() = default;
CollisionWorld::~CollisionWorld() = default;
CollisionWorld::CollisionWorld(const CollisionWorld&) {}
CollisionWorld& CollisionWorld::operator=(const CollisionWorld&) {
  impl_.reset();
  return *this;
}
CollisionWorld::CollisionWorld(CollisionWorld&&) noexcept = default;
CollisionWorld& CollisionWorld::operator=(CollisionWorld&&) noexcept = default;

void CollisionWorld::prepare(const Scene& scene) {
  const ContactModel& c = scene.collision;
  if (!c.self_collision && c.obstacles.empty()) return;  // the ground alone needs no FCL objects
  if (!impl_) {
    impl_ = std::make_unique<Impl>();
    impl_->sphere_box.reserve(1);
  }
  if (c.self_collision && !impl_->built_for(scene.rig)) impl_->build(scene.rig);
}

void CollisionWorld::detect(const Scene& scene, const BoneFrames& frames,
                            std::vector<Contact>& out) {
  out.clear();
  const ContactModel& c = scene.collision;
  if (c.ground) ground_contacts(scene, frames, out);
  if (c.obstacles.empty() && !c.self_collision) return;
  // a pose gone non-finite has no box or bone-pair contacts (FCL's tree cannot split non-finite
  // boxes); the run monitor reports the divergence
  if (!finite_frames(frames)) return;
  prepare(scene);
  if (!c.obstacles.empty()) impl_->box_contacts(scene, frames, out);
  if (!c.self_collision) return;
  // the energy guard and the force stage ask about the same pose: answer it once
  if (!impl_->same_query(scene, frames)) {
    impl_->place_bones(frames);
    impl_->broad_phase(scene);
    impl_->last_pair_contacts.clear();
    impl_->pair_contacts(impl_->last_pair_contacts);
    impl_->remember(scene, frames);
  }
  out.insert(out.end(), impl_->last_pair_contacts.begin(), impl_->last_pair_contacts.end());
}

}  // namespace physik
