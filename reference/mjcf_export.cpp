#include "reference/mjcf_export.h"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "physik/model/errors.h"
#include "physik/model/unique_names.h"
#include "reference/mujoco_log.h"

namespace physik {

namespace {

const char* const kAxisName[3] = {"x", "y", "z"};
const char* const kAxisVec[3] = {"1 0 0", "0 1 0", "0 0 1"};

std::string vec(const Vec3& v) {
  std::ostringstream s;
  s << std::setprecision(17) << v.x() << " " << v.y() << " " << v.z();
  return s.str();
}

std::string quat(const Quat& q) {  // MuJoCo order: w x y z
  std::ostringstream s;
  s << std::setprecision(17) << q.w() << " " << q.x() << " " << q.y() << " " << q.z();
  return s.str();
}

// a name as an XML attribute value: the five reserved characters as entities (MuJoCo's reader
// decodes them, so the model's names are the rig's); names are printable UTF-8 (names.h)
std::string xml_attr(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// text inside an XML comment, which may not hold "--" (nor end in '-')
std::string xml_comment(std::string text) {
  for (std::size_t i = 0; (i = text.find('-', i)) != std::string::npos; ++i) {
    if (i + 1 == text.size() || text[i + 1] == '-') text.insert(i + 1, " ");
  }
  return text;
}

std::string num(double x) {
  std::ostringstream s;
  s << std::setprecision(17) << x;
  return s.str();
}

void write_hinge(std::ostringstream& x, const std::string& bone, int axis, const AxisLimit& l,
                 double half_length, const std::string& pad) {
  x << pad << "<joint name=\"" << xml_attr(bone) << ":" << kAxisName[axis]
    << "\" type=\"hinge\" axis=\"" << kAxisVec[axis] << "\" pos=\"0 " << num(-half_length)
    << " 0\"";
  if (l.limited) {
    x << " limited=\"true\" range=\"" << num(l.min) << " " << num(l.max) << "\"";
  } else {
    x << " limited=\"false\"";
  }
  x << "/>\n";
}

// a joint is written as one ball (no limit) in `model`
bool written_as_ball(const Rig& rig, int i, JointModel model) {
  const auto& limit = rig.bone_limit[i];
  const bool any_limited = limit[0].limited || limit[1].limited || limit[2].limited;
  switch (model) {
    case JointModel::kBallJoints:
      return rig.joint_type(i, LockedAxes::kSprings) == JointType::kBall;
    case JointModel::kHingeJoints:
      return rig.bone_joint_type[i] == JointType::kBall;
    case JointModel::kRigJoints:
      return rig.bone_joint_type[i] == JointType::kBall && !any_limited;
  }
  return false;
}

// a bone's joint type in `model`: the balls of kBallJoints, else the rig's (rig.h)
JointType model_type(const Rig& rig, int i, JointModel model) {
  return rig.joint_type(
      i, model == JointModel::kBallJoints ? LockedAxes::kSprings : LockedAxes::kRemoved);
}

void write_joints(std::ostringstream& x, const Rig& rig, int i, const std::string& name,
                  JointModel model, const std::string& pad) {
  const double half = 0.5 * rig.bone_length[i];
  switch (model_type(rig, i, model)) {
    case JointType::kFree:
      x << pad << "<joint name=\"" << xml_attr(name) << ":free\" type=\"free\"/>\n";
      return;
    case JointType::kWeld:  // welded into its group's body, locked, or a fixed root: no joint
      return;
    case JointType::kBall:  // below: a ball at the head (a pinned root's, to the world)
    case JointType::kHinge:
    case JointType::kUniversal:
      break;
  }
  if (written_as_ball(rig, i, model)) {
    x << pad << "<joint name=\"" << xml_attr(name) << ":ball\" type=\"ball\" pos=\"0 " << num(-half)
      << " 0\" limited=\"false\"/>\n";
    return;
  }
  // one hinge per axis that is not locked, in x, y, z order: limited by the rig's limits in
  // exact-constraints mode, free in kHingeJoints (the torsion springs are forces there)
  const auto& limit = rig.bone_limit[i];
  for (int k = 0; k < 3; ++k) {
    if (limit[k].locked()) continue;
    write_hinge(x, name, k, model == JointModel::kRigJoints ? limit[k] : AxisLimit{}, half, pad);
  }
}

// The names MuJoCo gets: each bone's body and geom the bone's name, the ground "ground", each box
// "obstacle:" + its name, except where MuJoCo would meet a name twice (its "repeated name" error):
// a bone named "world" (MuJoCo's world body) and a ground or box whose name a bone has take the
// first free "_2", "_3", ... suffix (UniqueNames). Joint names are the body's with ":free",
// ":ball" or ":x" (":y", ":z"), unique since the body names are.
struct MjcfNames {
  std::vector<std::string> bone;      // (nbone) body and geom
  std::string ground;                 // the ground plane's geom
  std::vector<std::string> obstacle;  // (nobstacle) the boxes' geoms
};

MjcfNames mjcf_names(const Rig& rig, const ContactModel& c) {
  MjcfNames out;
  UniqueNames taken;  // one set for bodies and geoms: a bone's name is both
  taken.take("world");
  for (const std::string& b : rig.bone_name) taken.take(b);
  out.bone.reserve(rig.nbone);
  for (const std::string& b : rig.bone_name) out.bone.push_back(b == "world" ? taken.make(b) : b);
  if (c.ground) out.ground = taken.make("ground");
  for (const BoxObstacle& box : c.obstacles)
    out.obstacle.push_back(taken.make("obstacle:" + box.name));
  return out;
}

// Where the bodies go: the main file, and include files once a file's bodies nest too deep.
struct MjcfWriter {
  const Rig& rig;
  const MjcfOptions& o;
  const MjcfNames& names;
  std::string stem;                 // include files are stem.partK.xml
  int bodies_per_file;              // 0: never split
  std::vector<MjcfFile>* includes;  // nullptr: never split
};

void write_body(std::ostringstream& x, const MjcfWriter& w, int i, int depth, int file_depth);

// the bones of the body that bone i (not welded) starts: i and the bones welded to it, directly
// or through one another, in DFS order
std::vector<int> body_members(const Rig& rig, int i) {
  std::vector<int> members{i};
  if (!rig.has_welds()) return members;
  for (int j = i + 1; j < rig.nbone; ++j) {
    if (rig.bone_body[j] == i) members.push_back(j);
  }
  return members;
}

// the bodies below a body: the children of its bones that are not welded into it
std::vector<int> body_children(const Rig& rig, const std::vector<int>& members) {
  std::vector<int> out;
  for (int m : members) {
    for (int c : rig.bone_children[m]) {
      if (rig.bone_weld[c] < 0) out.push_back(c);
    }
  }
  return out;
}

// the children of body i, inline or, at the file's depth limit, in a new include file
void write_children(std::ostringstream& x, const MjcfWriter& w, const std::vector<int>& children,
                    int i, int depth, int file_depth) {
  const Rig& rig = w.rig;
  if (children.empty()) return;
  if (!w.includes || file_depth < w.bodies_per_file) {
    for (int c : children) write_body(x, w, c, depth + 1, file_depth + 1);
    return;
  }
  if (static_cast<int>(w.includes->size()) + 2 >= mjMAXVFS) {
    throw std::runtime_error("MJCF: the rig needs more than " + std::to_string(mjMAXVFS - 2) +
                             " include files (MuJoCo's VFS limit)");
  }
  const std::string name = w.stem + ".part" + std::to_string(w.includes->size() + 1) + ".xml";
  const std::string pad(2 * (depth + 1), ' ');
  x << pad << "<include file=\"" << name << "\"/>\n";
  w.includes->push_back({name, ""});
  const std::size_t slot = w.includes->size() - 1;
  std::ostringstream part;
  part << "<!-- PhysIK rig '" << xml_comment(rig.name) << "': the bodies below '"
       << xml_comment(rig.bone_name[i])
       << "' (included: MuJoCo's XML parser takes about 100 nested elements per file) -->\n";
  part << "<mujocoinclude>\n";
  for (int c : children) write_body(part, w, c, 1, 1);
  part << "</mujocoinclude>\n";
  (*w.includes)[slot].text = part.str();
}

// a body's own inertial: one bone's rod at the frame's origin, or a welded group's composite
// mass, centre and full inertia (parallel axes) in the body frame
void write_inertial(std::ostringstream& x, const Rig& rig, const std::vector<int>& members,
                    const std::string& in) {
  const int i = members[0];
  if (members.size() == 1) {
    x << in << "<inertial pos=\"0 0 0\" mass=\"" << num(rig.bone_mass[i]) << "\" diaginertia=\""
      << vec(rig.bone_inertia_local[i]) << "\"/>\n";
    return;
  }
  double mass = 0.0;
  Vec3 centre = Vec3::Zero();
  for (int m : members) {
    const MjcfBodyOffset o = mjcf_body_offset(rig, m);
    mass += rig.bone_mass[m];
    centre += rig.bone_mass[m] * o.pos;
  }
  centre /= mass;
  Mat3 inertia = Mat3::Zero();
  for (int m : members) {
    const MjcfBodyOffset o = mjcf_body_offset(rig, m);
    const Mat3 R = o.quat.toRotationMatrix();
    const Vec3 r = o.pos - centre;
    inertia += R * rig.bone_inertia_local[m].asDiagonal() * R.transpose() +
               rig.bone_mass[m] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  x << in << "<inertial pos=\"" << vec(centre) << "\" mass=\"" << num(mass) << "\" fullinertia=\""
    << num(inertia(0, 0)) << " " << num(inertia(1, 1)) << " " << num(inertia(2, 2)) << " "
    << num(inertia(0, 1)) << " " << num(inertia(0, 2)) << " " << num(inertia(1, 2)) << "\"/>\n";
}

void write_body(std::ostringstream& x, const MjcfWriter& w, int i, int depth, int file_depth) {
  const Rig& rig = w.rig;
  const MjcfOptions& o = w.o;
  const std::string pad(2 * depth, ' ');
  const double L = rig.bone_length[i];
  Vec3 pos;
  Quat q;
  if (i == rig.root()) {
    // world frame: the rest centre of mass and orientation (the free joint's qpos0)
    q = rig.bone_rest_orient_world[i] * mjcf_joint_offset(rig, i, o.joints);
    pos = 0.5 * (rig.bone_rest_head_world[i] + rig.bone_rest_tail_world[i]);
  } else {
    // in its parent bone's frame, then in the frame of the body that bone belongs to
    const int p = rig.bone_parent[i];
    q = rig.bone_rest_orient_parent[i] * mjcf_joint_offset(rig, i, o.joints);
    pos =
        rig.bone_head_in_parent[i] - Vec3(0, 0.5 * rig.bone_length[p], 0) + q * Vec3(0, 0.5 * L, 0);
    if (rig.bone_body[p] != p) {
      const MjcfBodyOffset po = mjcf_body_offset(rig, p);
      pos = po.pos + po.quat * pos;
      q = po.quat * q;
    }
  }
  q.normalize();
  const std::vector<int> members = body_members(rig, i);
  const std::string& name = w.names.bone[i];
  x << pad << "<body name=\"" << xml_attr(name) << "\" pos=\"" << vec(pos) << "\" quat=\""
    << quat(q) << "\">\n";
  const std::string in = pad + "  ";
  write_joints(x, rig, i, name, o.joints, in);
  write_inertial(x, rig, members, in);
  for (int m : members) {
    // the capsule from head to tail, in the body frame
    x << in << "<geom name=\"" << xml_attr(w.names.bone[m]) << "\" type=\"capsule\" fromto=\"";
    const double half = 0.5 * rig.bone_length[m];
    if (m == i) {
      x << "0 " << num(-half) << " 0 0 " << num(half) << " 0";
    } else {
      const MjcfBodyOffset mo = mjcf_body_offset(rig, m);
      x << vec(mo.pos + mo.quat * Vec3(0, -half, 0)) << " "
        << vec(mo.pos + mo.quat * Vec3(0, half, 0));
    }
    x << "\" size=\"" << num(rig.bone_collision_radius[m]) << "\"/>\n";
  }
  write_children(x, w, body_children(rig, members), i, depth, file_depth);
  x << pad << "</body>\n";
}

// the ground plane: through height x normal, its z axis the normal; it collides with the bones
// (contype 1) but they are not its type (contype 0: planes never collide with each other)
void write_ground(std::ostringstream& x, const GroundPlane& g, const std::string& name) {
  x << "    <geom name=\"" << xml_attr(name) << "\" type=\"plane\" size=\"0 0 1\" pos=\""
    << vec(g.height * g.normal_world) << "\" zaxis=\"" << vec(g.normal_world)
    << "\" contype=\"0\" conaffinity=\"1\" rgba=\"0.5 0.5 0.5 1\"/>\n";
}

// the static boxes: world geoms like the ground (contype 0: they never collide with each other or
// the ground), size = the half extents, named "obstacle:" + the scene's name (MjcfNames)
void write_obstacles(std::ostringstream& x, const std::vector<BoxObstacle>& obstacles,
                     const std::vector<std::string>& names) {
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    const BoxObstacle& b = obstacles[k];
    x << "    <geom name=\"" << xml_attr(names[k]) << "\" type=\"box\" size=\""
      << vec(b.half_extents) << "\" pos=\"" << vec(b.center_world) << "\" quat=\""
      << quat(b.orient_world) << "\" contype=\"0\" conaffinity=\"1\" rgba=\"0.5 0.5 0.6 1\"/>\n";
  }
}

// the pairs PhysIK never collides that MuJoCo's filterparent leaves in: two children of one
// parent, and the scene's and the rig's excluded pairs, as the bodies that carry them (bones
// welded into one body never collide in MuJoCo either)
void write_exclusions(std::ostringstream& x, const Rig& rig, const ContactModel& c,
                      const std::vector<std::string>& names) {
  std::vector<std::pair<int, int>> pairs;
  const auto add = [&](int a, int b) {
    a = rig.bone_body[a];
    b = rig.bone_body[b];
    if (a != b) pairs.emplace_back(std::min(a, b), std::max(a, b));
  };
  for (const auto& [a, b] : c.excluded_pairs) add(a, b);
  for (const auto& [a, b] : rig.collision_exclude) add(a, b);
  for (int p = 0; p < rig.nbone; ++p) {
    const std::vector<int>& kids = rig.bone_children[p];
    for (std::size_t a = 0; a < kids.size(); ++a) {
      for (std::size_t b = a + 1; b < kids.size(); ++b) add(kids[a], kids[b]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  if (pairs.empty()) return;
  x << "  <contact>\n";
  for (const auto& [a, b] : pairs) {
    x << "    <exclude body1=\"" << xml_attr(names[a]) << "\" body2=\"" << xml_attr(names[b])
      << "\"/>\n";
  }
  x << "  </contact>\n";
}

// the joints' generalized velocities: 6 at the free root, 3 at a ball, 1 per hinge (write_joints)
int velocity_count(const Rig& rig, JointModel model) {
  int nv = 0;
  for (int i = 0; i < rig.nbone; ++i) {
    const JointType type = model_type(rig, i, model);
    if (type == JointType::kFree) {
      nv += 6;
    } else if (type != JointType::kWeld) {
      nv += written_as_ball(rig, i, model) ? 3 : rig.bone_dof(i);
    }
  }
  return nv;
}

// the main file around the root body
std::string write_main(const MjcfWriter& w) {
  const Rig& rig = w.rig;
  const MjcfOptions& o = w.o;
  // bones in DFS order: a parent's depth is known before its children's
  std::vector<int> depth(rig.nbone, 1);
  int deepest = 0;
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_parent[i] >= 0) depth[i] = depth[rig.bone_parent[i]] + 1;
    deepest = std::max(deepest, depth[i]);
  }
  if (deepest > kMaxMjcfDepth) {
    throw_input_error(o.source.empty() ? "rig '" + rig.name + "'" : o.source, "", "bones",
                      "the rig is " + std::to_string(deepest) +
                          " bones deep; export-mjcf writes "
                          "body trees at most " +
                          std::to_string(kMaxMjcfDepth) + " deep (mjcf_export.h kMaxMjcfDepth)");
  }
  std::ostringstream x;
  x << "<!-- PhysIK rig '" << xml_comment(rig.name)
    << "' as MJCF (reference/mjcf_export.h): one body per bone "
    << "at its centre of mass, local +Y along the bone; "
    << (o.joints == JointModel::kBallJoints
            ? "ball joints (same-forces mode)"
            : "joint types and limits from the rig (exact-constraints mode)")
    << " -->\n";
  x << "<mujoco model=\"" << xml_attr(rig.name.empty() ? "rig" : rig.name) << "\">\n";
  x << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
  const bool contacts = o.collision.any();
  const std::string gravity = o.gravity.isZero(0.0) ? "0 0 0" : vec(o.gravity);
  x << "  <option timestep=\"" << num(o.dt) << "\" gravity=\"" << gravity
    << "\" integrator=\"Euler\">\n";
  if (!contacts) x << "    <flag contact=\"disable\"/>\n";
  x << "  </option>\n";
  const MjcfSize size = mjcf_size(rig, o);
  x << "  <size nconmax=\"" << size.nconmax << "\" njmax=\"" << size.njmax << "\"/>\n";
  x << "  <default>\n";
  if (contacts) {
    const char* affinity = o.collision.self_collision ? "1" : "0";
    x << "    <geom contype=\"1\" conaffinity=\"" << affinity << "\" friction=\"" << num(o.friction)
      << " 0.005 0.0001\" rgba=\"0.8 0.6 0.4 1\"/>\n";
  } else {
    x << "    <geom contype=\"0\" conaffinity=\"0\" rgba=\"0.8 0.6 0.4 1\"/>\n";
  }
  x << "  </default>\n";
  x << "  <worldbody>\n";
  if (o.collision.ground) write_ground(x, *o.collision.ground, w.names.ground);
  write_obstacles(x, o.collision.obstacles, w.names.obstacle);
  write_body(x, w, rig.root(), 2, 1);
  x << "  </worldbody>\n";
  if (o.collision.self_collision) write_exclusions(x, rig, o.collision, w.names.bone);
  x << "</mujoco>\n";
  return x.str();
}

}  // namespace

namespace {

// The most boxes one bone's capsule can touch at once (mjcf_export.h MjcfSize): boxes it touches
// together lie within its extent D = L + 2 r of each other, so at most the largest count of boxes
// within D of one box (itself among them), each box taken as its bounding sphere (which only
// counts more). O(nbox^2).
long boxes_touching_at_once(const Rig& rig, const std::vector<BoxObstacle>& boxes) {
  double extent = 0.0;  // rig units, the longest capsule's length plus its diameter
  for (int b = 0; b < rig.nbone; ++b) {
    extent = std::max(extent, rig.bone_length[b] + 2.0 * rig.bone_collision_radius[b]);
  }
  long most = 0;
  for (const BoxObstacle& a : boxes) {
    long near = 0;
    for (const BoxObstacle& b : boxes) {
      const double gap =
          (a.center_world - b.center_world).norm() - a.half_extents.norm() - b.half_extents.norm();
      near += gap <= extent ? 1 : 0;
    }
    most = std::max(most, near);
  }
  return most;
}

}  // namespace

MjcfSize mjcf_size(const Rig& rig, const MjcfOptions& o) {
  const ContactModel& c = o.collision;
  const long n = rig.nbone;
  long contacts = 0;
  if (c.ground) contacts += 2 * n;
  contacts += 2 * n * boxes_touching_at_once(rig, c.obstacles);
  if (c.self_collision) {
    // candidate pairs: every pair but those sharing a joint and the excluded ones
    long sharing = 0;
    for (int p = 0; p < rig.nbone; ++p) {
      const long k = static_cast<long>(rig.bone_children[p].size());
      sharing += k + k * (k - 1) / 2;  // parent-child, and children of one parent
    }
    const long pairs =
        std::max(0L, n * (n - 1) / 2 - sharing - static_cast<long>(c.excluded_pairs.size()));
    contacts += 2 * std::min(pairs, n);
  }
  if (!c.any()) contacts = 0;
  long rows = 4 * contacts;
  if (o.joints == JointModel::kRigJoints) {  // a limited hinge's row (write_joints)
    for (int i = 0; i < rig.nbone; ++i) {
      const JointType type = rig.bone_joint_type[i];
      if (type == JointType::kFree || type == JointType::kWeld ||
          written_as_ball(rig, i, o.joints)) {
        continue;
      }
      for (const AxisLimit& l : rig.bone_limit[i]) rows += l.limited && !l.locked() ? 1 : 0;
    }
  }
  // njmax x njmax (efc_AR, doubles and ints) and two njmax x nv Jacobians (doubles and ints),
  // with about 256 bytes of per-row vectors: within kMjcfConstraintBytes
  const double nv = velocity_count(rig, o.joints);
  const double b = 24.0 * nv + 256.0;
  const long max_rows =
      static_cast<long>((-b + std::sqrt(b * b + 48.0 * kMjcfConstraintBytes)) / 24.0);
  MjcfSize size;
  size.nconmax = static_cast<int>(std::max<long>(kMujocoDefaultNconmax, contacts));
  size.njmax = static_cast<int>(std::max<long>(kMujocoDefaultNjmax, std::min(rows, max_rows)));
  size.rows_needed = rows;
  return size;
}

std::vector<std::string> mjcf_bone_names(const Rig& rig) {
  return mjcf_names(rig, ContactModel{}).bone;
}

Quat mjcf_joint_offset(const Rig& rig, int bone, JointModel joints) {
  if (joints == JointModel::kBallJoints || rig.welded(bone)) return Quat::Identity();
  if (bone == 0 && rig.root_joint != RootJoint::kPinned) return Quat::Identity();
  return rig.bone_joint_lock[bone];
}

MjcfBodyOffset mjcf_body_offset(const Rig& rig, int bone) {
  MjcfBodyOffset out;
  const int b = rig.bone_body[bone];
  if (b == bone) return out;
  // at rest: the bone's centre and axes in the body's (its first bone's centre and axes)
  const Quat Rb = rig.bone_rest_orient_world[b];
  const Vec3 cb = 0.5 * (rig.bone_rest_head_world[b] + rig.bone_rest_tail_world[b]);
  const Vec3 ci = 0.5 * (rig.bone_rest_head_world[bone] + rig.bone_rest_tail_world[bone]);
  out.pos = Rb.conjugate() * (ci - cb);
  out.quat = (Rb.conjugate() * rig.bone_rest_orient_world[bone]).normalized();
  return out;
}

MjcfOptions mjcf_contacts(const Scene& scene, MjcfOptions o) {
  o.gravity = scene.gravity_world;
  o.collision = scene.collision;
  o.friction = scene.params.friction;
  o.contacts_source = scene.file;
  return o;
}

std::string rig_to_mjcf(const Rig& rig, const MjcfOptions& o) {
  const MjcfNames names = mjcf_names(rig, o.collision);
  return write_main(MjcfWriter{rig, o, names, "", 0, nullptr});
}

void check_mjcf_timestep(double dt, const std::string& option) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    throw_input_error(option, "", "", "must be a positive finite number of seconds");
  }
}

std::vector<MjcfFile> rig_to_mjcf_files(const Rig& rig, const MjcfOptions& o,
                                        const std::string& main_name) {
  const std::string stem = main_name.size() > 4 && main_name.substr(main_name.size() - 4) == ".xml"
                               ? main_name.substr(0, main_name.size() - 4)
                               : main_name;
  std::vector<MjcfFile> includes;
  const MjcfNames names = mjcf_names(rig, o.collision);
  const std::string main =
      write_main(MjcfWriter{rig, o, names, stem, kMjcfBodiesPerFile, &includes});
  std::vector<MjcfFile> files;
  files.reserve(includes.size() + 1);
  files.push_back({main_name, main});
  for (MjcfFile& f : includes) files.push_back(std::move(f));
  return files;
}

MjModelPtr compile_mjcf(const std::string& xml) {
  return compile_mjcf(std::vector<MjcfFile>{{"physik_rig.xml", xml}});
}

MjModelPtr compile_mjcf(const std::vector<MjcfFile>& files) {
  route_mujoco_warnings_to_stderr();
  if (files.empty()) throw std::runtime_error("MuJoCo: no MJCF to compile");
  // mjVFS holds 2000 file names of 1000 chars: keep it off the stack
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  for (const MjcfFile& file : files) {
    // VFS names are file names without their folder (the includes sit beside the main file)
    const std::string name = std::filesystem::path(file.name).filename().string();
    if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(file.text.size())) != 0) {
      mj_deleteVFS(vfs.get());
      throw std::runtime_error("MuJoCo: cannot make a VFS file for '" + name + "'");
    }
    const int f = mj_findFileVFS(vfs.get(), name.c_str());
    std::memcpy(vfs->filedata[f], file.text.data(), file.text.size());
  }
  char error[1000] = "";
  const std::string main = std::filesystem::path(files[0].name).filename().string();
  mjModel* m = mj_loadXML(main.c_str(), vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (!m && std::strstr(error, "Could not allocate memory")) {
    throw MjcfAllocationError(std::string("MuJoCo could not allocate the model: ") + error);
  }
  if (!m) throw std::runtime_error(std::string("MuJoCo rejected the MJCF: ") + error);
  return MjModelPtr(m);
}

namespace {

// make_mjdata's target for MuJoCo's error handler (one per thread: a handler that finds none
// is not installed)
thread_local std::jmp_buf* mujoco_error_target = nullptr;
thread_local char mujoco_error_message[1000];

void jump_to_target(const char* message) {
  std::snprintf(mujoco_error_message, sizeof(mujoco_error_message), "%s", message);
  std::longjmp(*mujoco_error_target, 1);
}

// the error of a rig's MuJoCo model or data that MuJoCo could not allocate, as an InputError
[[noreturn]] void throw_allocation_error(const Rig& rig, const MjcfOptions& o,
                                         const MjcfAllocationError& e) {
  const MjcfSize size = mjcf_size(rig, o);
  const ContactModel& c = o.collision;
  const std::string field = !c.obstacles.empty() ? "obstacles"
                            : c.self_collision   ? "self_collision"
                            : c.ground           ? "ground"
                                                 : "bones";
  std::ostringstream why;
  why << "MuJoCo ran out of memory making the buffers for the contacts the rig can meet at once, "
      << size.nconmax << " contacts (nconmax) and " << size.njmax
      << " constraint rows (njmax; at most " << kMjcfConstraintBytes << " bytes): " << rig.nbone
      << " bones, " << c.obstacles.size() << " boxes, up to "
      << boxes_touching_at_once(rig, c.obstacles)
      << " of them within a bone's reach of each other: fewer boxes that close together need "
         "fewer rows, or give the process more memory ("
      << e.what() << ")";
  throw_input_error(o.contacts_source.empty() ? o.source : o.contacts_source, "", field, why.str());
}

}  // namespace

MjModelPtr compile_rig_mjcf(const Rig& rig, const MjcfOptions& o,
                            const std::vector<MjcfFile>& files) {
  try {
    return compile_mjcf(files);
  } catch (const MjcfAllocationError& e) {
    throw_allocation_error(rig, o, e);
  }
}

MjDataPtr make_mjdata(const mjModel* m) {
  std::jmp_buf target;
  void (*const previous)(const char*) = mju_user_error;
  mjData* volatile d = nullptr;
  mujoco_error_target = &target;
  mju_user_error = jump_to_target;
  if (setjmp(target) == 0) d = mj_makeData(m);
  mju_user_error = previous;
  mujoco_error_target = nullptr;
  if (!d) {
    throw MjcfAllocationError(std::string("MuJoCo could not allocate the model's data: ") +
                              mujoco_error_message);
  }
  return MjDataPtr(d);
}

MjDataPtr make_rig_mjdata(const Rig& rig, const MjcfOptions& options, const mjModel* m) {
  try {
    return make_mjdata(m);
  } catch (const MjcfAllocationError& e) {
    throw_allocation_error(rig, options, e);
  }
}

MjModelPtr rig_to_mjmodel(const Rig& rig, const MjcfOptions& options) {
  return compile_rig_mjcf(rig, options, rig_to_mjcf_files(rig, options));
}

}  // namespace physik
