#include "reference/mujoco_log.h"
#include "reference/mjcf_export.h"

#include "physik/model/errors.h"

#include <algorithm>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

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
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
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

// the fixed rotation of a bone's locked axes (identity when none is locked away from zero)
Quat locked_rotation(const std::array<AxisLimit, 3>& limit) {
  Vec3 v = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    if (limit[k].locked()) v[k] = limit[k].min;
  }
  const double angle = v.norm();
  return angle > 0.0 ? Quat(Eigen::AngleAxisd(angle, v / angle)) : Quat::Identity();
}

void write_hinge(std::ostringstream& x, const std::string& bone, int axis, const AxisLimit& l,
                 double half_length, const std::string& pad) {
  x << pad << "<joint name=\"" << xml_attr(bone) << ":" << kAxisName[axis] << "\" type=\"hinge\" axis=\""
    << kAxisVec[axis] << "\" pos=\"0 " << num(-half_length) << " 0\"";
  if (l.limited) {
    x << " limited=\"true\" range=\"" << num(l.min) << " " << num(l.max) << "\"";
  } else {
    x << " limited=\"false\"";
  }
  x << "/>\n";
}

void write_joints(std::ostringstream& x, const Rig& rig, int i, JointModel model,
                  const std::string& pad) {
  const std::string& name = rig.bone_name[i];
  const double half = 0.5 * rig.bone_length[i];
  if (i == rig.root()) {
    x << pad << "<joint name=\"" << xml_attr(name) << ":free\" type=\"free\"/>\n";
    return;
  }
  const auto& limit = rig.bone_limit[i];
  const int dof = rig.bone_dof(i);
  const bool any_limited = limit[0].limited || limit[1].limited || limit[2].limited;
  if (model == JointModel::kBallJoints || (dof == 3 && !any_limited)) {
    x << pad << "<joint name=\"" << xml_attr(name) << ":ball\" type=\"ball\" pos=\"0 " << num(-half)
      << " 0\" limited=\"false\"/>\n";
    return;
  }
  // 1, 2 or limited 3 DOF: one hinge per axis that is not locked; 0 DOF: welded
  for (int k = 0; k < 3; ++k) {
    if (!limit[k].locked()) write_hinge(x, name, k, limit[k], half, pad);
  }
}

// one body's opening tag, joints, inertial and geom (its children and </body> follow)
void open_body(std::ostringstream& x, const Rig& rig, int i, const MjcfOptions& o,
               const std::string& pad) {
  const double L = rig.bone_length[i];
  Vec3 pos;
  Quat q;
  if (i == rig.root()) {
    // world frame: the rest centre of mass and orientation (the free joint's qpos0)
    q = rig.bone_rest_orient_world[i];
    pos = 0.5 * (rig.bone_rest_head_world[i] + rig.bone_rest_tail_world[i]);
  } else {
    const int p = rig.bone_parent[i];
    q = rig.bone_rest_orient_parent[i] * mjcf_joint_offset(rig, i, o.joints);
    pos = rig.bone_head_in_parent[i] - Vec3(0, 0.5 * rig.bone_length[p], 0) + q * Vec3(0, 0.5 * L, 0);
  }
  q.normalize();
  x << pad << "<body name=\"" << xml_attr(rig.bone_name[i]) << "\" pos=\"" << vec(pos)
    << "\" quat=\"" << quat(q) << "\">\n";
  const std::string in = pad + "  ";
  write_joints(x, rig, i, o.joints, in);
  x << in << "<inertial pos=\"0 0 0\" mass=\"" << num(rig.bone_mass[i]) << "\" diaginertia=\""
    << vec(rig.bone_inertia_local[i]) << "\"/>\n";
  x << in << "<geom name=\"" << xml_attr(rig.bone_name[i]) << "\" type=\"capsule\" fromto=\"0 "
    << num(-0.5 * L) << " 0 0 " << num(0.5 * L) << " 0\" size=\"" << num(0.06 * L) << "\"/>\n";
}

// the body tree, nested in DFS order with an explicit stack (a rig's depth is its input's)
void write_bodies(std::ostringstream& x, const Rig& rig, const MjcfOptions& o, int depth0) {
  struct Frame {
    int bone;
    int depth;
    bool closing;  // true: write </body>
  };
  std::vector<Frame> stack{{rig.root(), depth0, false}};
  while (!stack.empty()) {
    const Frame f = stack.back();
    stack.pop_back();
    const std::string pad(2 * f.depth, ' ');
    if (f.closing) {
      x << pad << "</body>\n";
      continue;
    }
    open_body(x, rig, f.bone, o, pad);
    stack.push_back({f.bone, f.depth, true});
    const auto& ch = rig.bone_children[f.bone];
    for (auto it = ch.rbegin(); it != ch.rend(); ++it) stack.push_back({*it, f.depth + 1, false});
  }
}

}  // namespace

Quat mjcf_joint_offset(const Rig& rig, int bone, JointModel joints) {
  if (bone == rig.root() || joints == JointModel::kBallJoints) return Quat::Identity();
  return locked_rotation(rig.bone_limit[bone]);
}

std::string rig_to_mjcf(const Rig& rig, const MjcfOptions& o) {
  // bones in DFS order: a parent's depth is known before its children's
  std::vector<int> depth(rig.nbone, 1);
  int deepest = 0;
  for (int i = 0; i < rig.nbone; ++i) {
    if (rig.bone_parent[i] >= 0) depth[i] = depth[rig.bone_parent[i]] + 1;
    deepest = std::max(deepest, depth[i]);
  }
  if (deepest > kMaxMjcfDepth) {
    throw_input_error(o.source.empty() ? "rig '" + rig.name + "'" : o.source, "", "bones",
                      "the rig is " + std::to_string(deepest) + " bones deep; MuJoCo's XML reader "
                      "takes body trees at most " + std::to_string(kMaxMjcfDepth) +
                      " deep (mjcf_export.h kMaxMjcfDepth)");
  }
  std::ostringstream x;
  x << "<!-- PhysIK rig '" << xml_comment(rig.name) << "' as MJCF (reference/mjcf_export.h): one body per bone "
    << "at its centre of mass, local +Y along the bone; "
    << (o.joints == JointModel::kBallJoints ? "ball joints (same-forces mode)"
                                            : "joint types and limits from the rig (exact-constraints mode)")
    << " -->\n";
  x << "<mujoco model=\"" << xml_attr(rig.name.empty() ? "rig" : rig.name) << "\">\n";
  x << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
  x << "  <option timestep=\"" << num(o.dt) << "\" gravity=\"0 0 0\" integrator=\"Euler\">\n";
  x << "    <flag contact=\"disable\"/>\n";
  x << "  </option>\n";
  x << "  <default>\n";
  x << "    <geom contype=\"0\" conaffinity=\"0\" rgba=\"0.8 0.6 0.4 1\"/>\n";
  x << "  </default>\n";
  x << "  <worldbody>\n";
  write_bodies(x, rig, o, 2);
  x << "  </worldbody>\n";
  x << "</mujoco>\n";
  return x.str();
}

MjModelPtr compile_mjcf(const std::string& xml) {
  route_mujoco_warnings_to_stderr();
  // mjVFS holds 2000 file names of 1000 chars: keep it off the stack
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "physik_rig.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    throw std::runtime_error("MuJoCo: cannot make a VFS file for the MJCF");
  }
  const int f = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[f], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("MuJoCo rejected the MJCF: ") + error);
  return MjModelPtr(m);
}

MjModelPtr rig_to_mjmodel(const Rig& rig, const MjcfOptions& options) {
  return compile_mjcf(rig_to_mjcf(rig, options));
}

}  // namespace physik
