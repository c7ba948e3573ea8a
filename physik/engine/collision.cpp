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
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_box.h>
#include <fcl/narrowphase/distance.h>

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
  d->pairs->emplace_back(a, b);
  return false;  // false: go on
}

}  // namespace

struct CollisionWorld::Impl {
  std::vector<double> radius;  // (nbone) what the world was built for, rig units
  std::vector<double> length;  // (nbone) rig units
  std::vector<std::unique_ptr<CollisionObjectd>> bones;  // (nbone) capsules
  fcl::DynamicAABBTreeCollisionManagerd tree;
  std::vector<std::pair<int, int>> pairs;      // the broad phase's candidates this call, scratch
  std::vector<fcl::ContactPointd> sphere_box;  // FCL's sphere-box answer, scratch (capacity 1)

  bool built_for(const Rig& rig) const {
    return radius == rig.bone_collision_radius && length == rig.bone_length;
  }
  void build(const Rig& rig);
  void place_bones(const BoneFrames& frames);
  void broad_phase(const Scene& scene);
  void pair_contacts(std::vector<Contact>& out) const;
  void box_contacts(const Scene& scene, const BoneFrames& f, std::vector<Contact>& out);
  void sphere_in_box(const fcl::Boxd& box, const fcl::Transform3d& box_tf, const Vec3& centre,
                     double r, Contact& c, std::vector<Contact>& out);
};

void CollisionWorld::Impl::build(const Rig& rig) {
  radius = rig.bone_collision_radius;
  length = rig.bone_length;
  tree.clear();
  bones.clear();
  std::vector<CollisionObjectd*> objs;
  for (int i = 0; i < rig.nbone; ++i) {
    auto shape = std::make_shared<fcl::Capsuled>(radius[i], length[i]);
    bones.push_back(std::make_unique<CollisionObjectd>(shape));
    bones.back()->setUserData(tag(i));
    objs.push_back(bones.back().get());
  }
  tree.registerObjects(objs);
  tree.setup();
  pairs.reserve(4 * static_cast<std::size_t>(rig.nbone));
}

void CollisionWorld::Impl::place_bones(const BoneFrames& f) {
  static const Mat3 kZtoY = z_to_y();
  for (std::size_t i = 0; i < bones.size(); ++i) {
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.linear() = f.orient_world[i].toRotationMatrix() * kZtoY;
    tf.translation() = 0.5 * (f.head_world[i] + f.tail_world[i]);
    bones[i]->setTransform(tf);
    bones[i]->computeAABB();
  }
  tree.update();
}

void CollisionWorld::Impl::broad_phase(const Scene& scene) {
  pairs.clear();
  BroadPhaseData data{&scene, &pairs};
  tree.collide(&data, candidate);
  // the tree's order depends on its history: sort, so the contacts' order depends on the shapes
  std::sort(pairs.begin(), pairs.end());
}

void CollisionWorld::Impl::pair_contacts(std::vector<Contact>& out) const {
  const fcl::DistanceRequestd request(true);  // the witness points too
  for (const auto& [a, b] : pairs) {
    fcl::DistanceResultd res;
    fcl::distance(bones[a].get(), bones[b].get(), request, res);
    const double s = res.min_distance;
    // a touch within round-off of the radii carries no force and has no reliable normal
    if (!(s < -1e-12 * (radius[a] + radius[b]))) continue;
    const Vec3 pa = res.nearest_points[0], pb = res.nearest_points[1];
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
      sphere_in_box(box, box_tf, f.head_world[i], r, c, out);
      sphere_in_box(box, box_tf, f.tail_world[i], r, c, out);
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
    for (const Vec3* e : {&f.head_world[i], &f.tail_world[i]}) {
      Contact c;
      c.bone = i;
      c.normal_world = n;
      c.depth = r - (n.dot(*e) - g.height);
      if (!(c.depth > 0.0)) continue;
      c.point_world = *e - (r - 0.5 * c.depth) * n;  // midway: the sphere's bottom to the plane
      out.push_back(c);
    }
  }
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
  const CollisionSettings& c = scene.collision;
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
  const CollisionSettings& c = scene.collision;
  if (c.ground) ground_contacts(scene, frames, out);
  prepare(scene);
  if (!c.obstacles.empty()) impl_->box_contacts(scene, frames, out);
  if (!c.self_collision) return;
  impl_->place_bones(frames);
  impl_->broad_phase(scene);
  impl_->pair_contacts(out);
}

}  // namespace physik
