#include "physik/engine/ground_contacts.h"

#include <algorithm>
#include <tuple>

#include "physik/engine/implicit_elements.h"
#include "physik/engine/newton_euler.h"

namespace physik {

namespace {

// the order the force stage lists a state's contacts in (collision.h detect): the ground's, the
// obstacles' by obstacle, then the bone pairs'; each by bone, then feature
bool contact_before(const FrictionAnchor& a, const Contact& c) {
  const auto group = [](int other_bone, int obstacle) {
    return other_bone >= 0 ? 2 : (obstacle >= 0 ? 1 : 0);
  };
  return std::make_tuple(group(a.other_bone, a.obstacle), a.obstacle, a.bone, a.other_bone,
                         a.feature) < std::make_tuple(group(c.other_bone, c.obstacle), c.obstacle,
                                                      c.bone, c.other_bone, c.feature);
}

bool same_contact(const FrictionAnchor& a, const Contact& c) {
  return a.bone == c.bone && a.other_bone == c.other_bone && a.obstacle == c.obstacle &&
         a.feature == c.feature;
}

// the anchor of the last force stage's contact that `c` continues, or null (a new contact)
const FrictionAnchor* find_anchor(const std::vector<FrictionAnchor>& anchors, const Contact& c) {
  const auto it = std::lower_bound(anchors.begin(), anchors.end(), c, contact_before);
  return it != anchors.end() && same_contact(*it, c) ? &*it : nullptr;
}

Vec3 clamp_length(const Vec3& x, double limit) {
  const double len = x.norm();
  return len > limit ? Vec3(x * (limit / len)) : x;
}

// the stretch an anchor's spring is carried to now, before its limit: stretch + step v_t, v_t the
// tangential relative velocity at its point now; rig units
Vec3 carried_stretch(const SimState& s, const FrictionAnchor& a) {
  Vec3 v = point_velocity(s, a.bone, a.point_world);
  if (a.other_bone >= 0) v -= point_velocity(s, a.other_bone, a.point_world);
  const Vec3& n = a.normal_world;
  return a.stretch_world + a.step * (v - v.dot(n) * n);
}

// its stretch now: at most its limit (the contact slips there)
Vec3 current_stretch(const SimState& s, const FrictionAnchor& a) {
  return clamp_length(carried_stretch(s, a), a.limit);
}

// a ground or obstacle contact's anchor spring at this force stage: the stretch carried over
// from the contact it continues, turned into this contact's tangent plane and held at `limit`
// (mu F_n / k_t), and whether it slips; the contact's anchor is listed for the next force stage
struct AnchorNow {
  Vec3 stretch = Vec3::Zero();  // rig units
  bool slipping = false;        // it slid over the last step, and slides on
};

AnchorNow anchor_contact(SimState& s, const Contact& c, double limit, double h) {
  AnchorNow out;
  const Vec3& n = c.normal_world;
  if (const FrictionAnchor* a = find_anchor(s.contact.anchors, c)) {
    out.stretch = carried_stretch(s, *a);
    out.stretch -= out.stretch.dot(n) * n;
    out.slipping = out.stretch.norm() >= limit;
    out.stretch = clamp_length(out.stretch, limit);
  }
  FrictionAnchor next;
  next.bone = c.bone;
  next.other_bone = c.other_bone;
  next.obstacle = c.obstacle;
  next.feature = c.feature;
  next.point_world = c.point_world;
  next.normal_world = n;
  next.stretch_world = out.stretch;
  next.step = h;
  next.limit = limit;
  s.contact.anchors_next.push_back(next);
  return out;
}

// the anchor spring's stiffness, N/m: k_t along the tangent plane, but none along the slip of a
// slipping one (it pulls a constant mu F_n there)
Mat3 anchor_stiffness(const AnchorNow& anchor, const Mat3& tangent, double k_t) {
  if (!anchor.slipping) return k_t * tangent;
  const Vec3 slip = anchor.stretch.normalized();
  return k_t * (tangent - slip * slip.transpose());
}

}  // namespace

void apply_ground_contacts(const Scene& scene, SimState& s, double h) {
  ContactData& d = s.contact;
  d.anchors_next.clear();
  if (!scene.collision.ground && scene.collision.obstacles.empty()) {
    d.anchors.clear();
    return;
  }
  const EngineParams& p = scene.params;
  for (Contact& c : d.found) {
    if (c.other_bone >= 0) continue;  // a bone pair: self_contacts.h
    const Vec3& n = c.normal_world;
    const Vec3 v = point_velocity(s, c.bone, c.point_world);
    const double vn = v.dot(n);
    const double fn = p.contact_k * c.depth - p.contact_damping * vn;
    c.normal_force = std::max(fn, 0.0);
    if (!(fn > 0.0)) continue;  // separating faster than the spring pushes: no force
    const Vec3 vt = v - vn * n;
    const double coulomb = p.friction * fn;  // N, the most the friction can pull
    const bool anchored = p.friction_stiffness > 0.0 && coulomb > 0.0;
    const AnchorNow anchor =
        anchored ? anchor_contact(s, c, coulomb / p.friction_stiffness, h) : AnchorNow{};
    const Vec3& stretch = anchor.stretch;
    // the viscous share: what the spring leaves of mu F_n, over max(|v_t|, v_s)
    const double spring_pull = p.friction_stiffness * stretch.norm();
    const double friction_damping =
        std::max(coulomb - spring_pull, 0.0) / std::max(vt.norm(), p.friction_speed);
    const Vec3 f = fn * n - p.friction_stiffness * stretch - friction_damping * vt;
    apply_force_at(s, c.bone, f, c.point_world);
    // the implicit step's element (above)
    const Mat3 nn = n * n.transpose();
    const Mat3 tangent = Mat3::Identity() - nn;
    ContactElement e;
    e.bone = c.bone;
    e.point_world = c.point_world;
    e.stiffness = p.contact_k * nn;
    if (anchored) e.stiffness += anchor_stiffness(anchor, tangent, p.friction_stiffness);
    e.damping = p.contact_damping * nn + friction_damping * tangent;
    d.elements.push_back(e);
  }
  // the anchors, in the contacts' order (collision.h detect), for the next force stage
  std::swap(d.anchors, d.anchors_next);
}

double ground_contact_potential(const Scene& scene, const std::vector<Contact>& contacts) {
  double u = 0.0;
  for (const Contact& c : contacts) {
    if (c.other_bone < 0) u += 0.5 * scene.params.contact_k * c.depth * c.depth;
  }
  return u;
}

double friction_potential(const Scene& scene, const SimState& s) {
  double u = 0.0;
  for (const FrictionAnchor& a : s.contact.anchors) {
    u += 0.5 * scene.params.friction_stiffness * current_stretch(s, a).squaredNorm();
  }
  return u;
}

double ground_contacts_potential(const Scene& scene, const SimState& s) {
  if (!scene.collision.ground && scene.collision.obstacles.empty()) return 0.0;
  return ground_contact_potential(scene, s.contact.at_frames) + friction_potential(scene, s);
}

void ground_contacts_rate(const Scene&, double h, SimState& s) {
  for (const ContactElement& e : s.contact.elements) {
    if (e.other_bone >= 0) continue;
    const Vec3 v = point_velocity(s, e.bone, e.point_world);
    apply_force_at(s, e.bone, -h * (e.stiffness * v), e.point_world);
  }
}

void ground_contacts_augment(const Scene&, double h, SimState& s) {
  ArticulatedBodyData& d = s.joint_space.articulated;
  for (const ContactElement& e : s.contact.elements) {
    if (e.other_bone >= 0) continue;
    const Mat3 A = h * h * e.stiffness + h * e.damping;
    add_point_element(A, e.point_world - d.point_world[e.bone], s.implicit.accel_bias[e.bone],
                      d.inertia_art[e.bone], d.bias_force[e.bone]);
  }
}

}  // namespace physik
