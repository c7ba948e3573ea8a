// BVH and qBVH reader and writer; the format, the semantics and the rig mapping are documented
// in bvh.h and models/README.md.
#include "physik/io/bvh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

#include "physik/model/errors.h"

namespace physik {

namespace {

// ---------------------------------------------------------------- parsing

struct Token {
  std::string text;
  int line;  // 1-based
};

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool channel_from_name(const std::string& name, BvhChannel& out) {
  static const std::pair<const char*, BvhChannel> kNames[] = {
      {"XPOSITION", BvhChannel::kXpos},    {"YPOSITION", BvhChannel::kYpos},
      {"ZPOSITION", BvhChannel::kZpos},    {"XROTATION", BvhChannel::kXrot},
      {"YROTATION", BvhChannel::kYrot},    {"ZROTATION", BvhChannel::kZrot},
      {"WQUATERNION", BvhChannel::kWquat}, {"XQUATERNION", BvhChannel::kXquat},
      {"YQUATERNION", BvhChannel::kYquat}, {"ZQUATERNION", BvhChannel::kZquat}};
  const std::string u = upper(name);
  for (const auto& [n, c] : kNames) {
    if (u == n) {
      out = c;
      return true;
    }
  }
  return false;
}

bool is_rotation(BvhChannel c) {
  return c == BvhChannel::kXrot || c == BvhChannel::kYrot || c == BvhChannel::kZrot;
}
bool is_quaternion(BvhChannel c) {
  return c == BvhChannel::kWquat || c == BvhChannel::kXquat || c == BvhChannel::kYquat ||
         c == BvhChannel::kZquat;
}

class Parser {
 public:
  Parser(const std::string& text, std::string source) : source_(std::move(source)) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(line);
    }
    tokenize_from(0);
  }

  BvhFile parse() {
    expect_keyword("HIERARCHY");
    const Token& root = next("ROOT");
    if (upper(root.text) != "ROOT") fail(root.line, root.text, "expected ROOT");
    parse_joint(root, -1);
    if (at_end()) fail(last_line(), "MOTION", "missing MOTION section after the hierarchy");
    const Token& t = peek();
    if (t.text == "}") {
      fail(t.line, "}", "unbalanced braces: a '}' closes nothing");
    }
    if (upper(t.text) == "ROOT") {
      fail(t.line, "ROOT", "a second ROOT: the rig model has exactly one root");
    }
    if (upper(t.text) != "MOTION") fail(t.line, t.text, "expected MOTION after the hierarchy");
    parse_motion(t.line);
    return std::move(bvh_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& field, const std::string& reason) const {
    throw_input_error(source_, "line " + std::to_string(line), field, reason);
  }
  int last_line() const { return std::max<int>(1, static_cast<int>(lines_.size())); }

  void tokenize_from(std::size_t first_line) {
    tokens_.clear();
    pos_ = 0;
    for (std::size_t l = first_line; l < lines_.size(); ++l) {
      std::string cur;
      auto flush = [&] {
        if (!cur.empty()) tokens_.push_back({cur, static_cast<int>(l) + 1});
        cur.clear();
      };
      for (char c : lines_[l]) {
        if (std::isspace(static_cast<unsigned char>(c))) {
          flush();
        } else if (c == '{' || c == '}') {
          flush();
          tokens_.push_back({std::string(1, c), static_cast<int>(l) + 1});
        } else {
          cur += c;
        }
      }
      flush();
    }
  }

  bool at_end() const { return pos_ >= tokens_.size(); }
  const Token& peek() const { return tokens_[pos_]; }
  const Token& next(const std::string& what) {
    if (at_end()) fail(last_line(), what, "unexpected end of file");
    return tokens_[pos_++];
  }
  void expect_keyword(const std::string& kw) {
    const Token& t = next(kw);
    if (upper(t.text) != kw) fail(t.line, kw, "expected " + kw + ", got '" + t.text + "'");
  }

  double number(const Token& t, const std::string& field) const {
    const char* s = t.text.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0') fail(t.line, field, "'" + t.text + "' is not a number");
    if (!std::isfinite(v) || errno == ERANGE) {
      fail(t.line, field, "'" + t.text + "' is not a finite number");
    }
    return v;
  }

  Vec3 offset() {
    Vec3 v;
    for (int k = 0; k < 3; ++k) {
      const Token& t = next("OFFSET");
      if (t.text == "}" || t.text == "{") {
        fail(t.line, "OFFSET", "expected 3 numbers, got " + std::to_string(k));
      }
      v[k] = number(t, "OFFSET");
    }
    return v;
  }

  // the name is the rest of the keyword's line (names may hold spaces), without braces
  std::string name_after(const Token& kw) {
    std::string name;
    while (!at_end() && peek().line == kw.line && peek().text != "{" && peek().text != "}") {
      if (!name.empty()) name += ' ';
      name += tokens_[pos_++].text;
    }
    if (name.empty()) fail(kw.line, kw.text, "missing joint name");
    return name;
  }

  void expect_open(const Token& kw, const std::string& what) {
    const Token& t = next("{");
    if (t.text != "{") {
      fail(t.line, "{", "unbalanced braces: expected '{' to open " + what + " (line " +
                            std::to_string(kw.line) + "), got '" + t.text + "'");
    }
  }

  void parse_channels(BvhJoint& j, const Token& kw) {
    if (!j.channels.empty()) fail(kw.line, "CHANNELS", "a second CHANNELS line for this joint");
    const Token& nt = next("CHANNELS");
    char* end = nullptr;
    const long n = std::strtol(nt.text.c_str(), &end, 10);
    if (end == nt.text.c_str() || *end != '\0' || n < 0 || n > 64) {
      fail(nt.line, "CHANNELS", "'" + nt.text + "' is not a channel count");
    }
    for (long k = 0; k < n; ++k) {
      if (at_end()) fail(last_line(), "CHANNELS", "unexpected end of file");
      const Token& t = peek();
      BvhChannel c;
      if (!channel_from_name(t.text, c)) {
        const std::string u = upper(t.text);
        if (u == "JOINT" || u == "END" || u == "OFFSET" || u == "}" || u == "{" ||
            u == "CHANNELS" || u == "MOTION") {
          fail(t.line, "CHANNELS", "the count says " + std::to_string(n) + " but " +
                                       std::to_string(k) + " channel names follow");
        }
        fail(t.line, "CHANNELS", "unknown channel '" + t.text + "'");
      }
      ++pos_;
      if (std::find(j.channels.begin(), j.channels.end(), c) != j.channels.end()) {
        fail(t.line, "CHANNELS", "channel '" + t.text + "' listed twice");
      }
      j.channels.push_back(c);
    }
    BvhChannel extra;
    if (!at_end() && channel_from_name(peek().text, extra)) {
      fail(peek().line, "CHANNELS",
           "the count says " + std::to_string(n) + " but more channel names follow");
    }
    const long nquat = std::count_if(j.channels.begin(), j.channels.end(), is_quaternion);
    const long neuler = std::count_if(j.channels.begin(), j.channels.end(), is_rotation);
    if (nquat != 0 && nquat != 4) {
      fail(kw.line, "CHANNELS", "qBVH needs all four quaternion channels (W, X, Y, Z)");
    }
    if (nquat != 0 && neuler != 0) {
      fail(kw.line, "CHANNELS", "mixes Euler rotation and quaternion channels");
    }
  }

  void parse_joint(const Token& kw, int parent) {
    BvhJoint j;
    j.name = name_after(kw);
    j.parent = parent;
    j.line = kw.line;
    expect_open(kw, "joint '" + j.name + "'");
    const int index = static_cast<int>(bvh_.joints.size());
    bvh_.joints.push_back(j);
    bool have_offset = false;
    for (;;) {
      if (at_end() || upper(peek().text) == "MOTION") {
        fail(at_end() ? last_line() : peek().line, "}",
             "unbalanced braces: joint '" + j.name + "' opened at line " +
                 std::to_string(kw.line) + " is never closed");
      }
      const Token t = next("}");
      const std::string u = upper(t.text);
      if (u == "}") break;
      if (u == "OFFSET") {
        bvh_.joints[index].offset = offset();
        have_offset = true;
      } else if (u == "CHANNELS") {
        parse_channels(bvh_.joints[index], t);
      } else if (u == "JOINT") {
        parse_joint(t, index);
      } else if (u == "END") {
        const Token& site = next("End Site");
        if (upper(site.text) != "SITE") fail(site.line, "End Site", "expected 'Site' after 'End'");
        expect_open(t, "an End Site");
        const Token& o = next("OFFSET");
        if (upper(o.text) != "OFFSET") fail(o.line, "End Site", "expected OFFSET");
        bvh_.joints[index].end_sites.push_back(offset());
        const Token& close = next("}");
        if (close.text != "}") {
          fail(close.line, "}", "unbalanced braces: the End Site at line " +
                                    std::to_string(t.line) + " is not closed after its OFFSET");
        }
      } else if (u == "{") {
        fail(t.line, "{", "unbalanced braces: a '{' without ROOT, JOINT or End Site");
      } else if (u == "ROOT") {
        fail(t.line, "ROOT", "ROOT inside a joint (unbalanced braces?)");
      } else {
        fail(t.line, t.text, "unknown keyword in joint '" + j.name + "'");
      }
    }
    if (!have_offset) fail(kw.line, "OFFSET", "joint '" + j.name + "' has no OFFSET");
  }

  void parse_motion(int motion_line) {
    // reparse line by line from the MOTION line: "Frames: N", "Frame Time: t", then one frame a line
    std::size_t l = static_cast<std::size_t>(motion_line);  // index of the line after MOTION
    {
      // anything after MOTION on its own line is not allowed
      std::istringstream rest(lines_[motion_line - 1]);
      std::string w;
      rest >> w;
      if (rest >> w) fail(motion_line, "MOTION", "unexpected '" + w + "' after MOTION");
    }
    auto skip_blank = [&] {
      while (l < lines_.size() &&
             lines_[l].find_first_not_of(" \t") == std::string::npos) {
        ++l;
      }
    };
    auto words = [&](std::size_t li) {
      std::istringstream s(lines_[li]);
      std::vector<std::string> w;
      std::string x;
      while (s >> x) w.push_back(x);
      return w;
    };
    skip_blank();
    if (l >= lines_.size()) fail(last_line(), "Frames", "missing 'Frames:' after MOTION");
    std::vector<std::string> w = words(l);
    const int frames_line = static_cast<int>(l) + 1;
    // "Frames: N" or "Frames : N"
    std::vector<std::string> value;
    if (upper(w[0]) == "FRAMES:") {
      value.assign(w.begin() + 1, w.end());
    } else if (upper(w[0]) == "FRAMES" && w.size() > 1 && w[1] == ":") {
      value.assign(w.begin() + 2, w.end());
    } else {
      fail(frames_line, "Frames", "expected 'Frames: N', got '" + lines_[l] + "'");
    }
    if (value.size() != 1) fail(frames_line, "Frames", "expected one frame count");
    char* end = nullptr;
    const long nframe = std::strtol(value[0].c_str(), &end, 10);
    if (end == value[0].c_str() || *end != '\0' || nframe < 0) {
      fail(frames_line, "Frames", "'" + value[0] + "' is not a frame count");
    }
    ++l;
    skip_blank();
    if (l >= lines_.size()) fail(last_line(), "Frame Time", "missing 'Frame Time:'");
    w = words(l);
    const int time_line = static_cast<int>(l) + 1;
    if (w.size() < 2 || upper(w[0]) != "FRAME" || upper(w[1]) != "TIME:" || w.size() != 3) {
      fail(time_line, "Frame Time", "expected 'Frame Time: t', got '" + lines_[l] + "'");
    }
    bvh_.frame_time = number(Token{w[2], time_line}, "Frame Time");
    if (!(bvh_.frame_time > 0.0)) fail(time_line, "Frame Time", "must be positive");
    ++l;

    // channel columns
    int col = 0;
    for (BvhJoint& j : bvh_.joints) {
      j.channel_start = col;
      col += static_cast<int>(j.channels.size());
    }
    bvh_.nchannel = col;

    for (; l < lines_.size(); ++l) {
      w = words(l);
      if (w.empty()) continue;
      const int line = static_cast<int>(l) + 1;
      if (static_cast<long>(bvh_.frames.size()) == nframe) {
        fail(line, "Frames", "more frames than 'Frames: " + std::to_string(nframe) +
                                 "' (line " + std::to_string(frames_line) + ")");
      }
      if (static_cast<int>(w.size()) != bvh_.nchannel) {
        fail(line, "MOTION", "frame " + std::to_string(bvh_.frames.size()) + " has " +
                                 std::to_string(w.size()) + " values, the hierarchy has " +
                                 std::to_string(bvh_.nchannel) + " channels");
      }
      std::vector<double> row(w.size());
      for (std::size_t k = 0; k < w.size(); ++k) row[k] = number(Token{w[k], line}, "MOTION");
      // qBVH: unit quaternions
      for (const BvhJoint& j : bvh_.joints) {
        double n2 = 0.0;
        bool quat = false;
        for (std::size_t c = 0; c < j.channels.size(); ++c) {
          if (is_quaternion(j.channels[c])) {
            quat = true;
            n2 += row[j.channel_start + c] * row[j.channel_start + c];
          }
        }
        if (quat && std::abs(std::sqrt(n2) - 1.0) > 1e-3) {
          fail(line, "MOTION", "joint '" + j.name + "': quaternion norm " +
                                   std::to_string(std::sqrt(n2)) + " is not 1");
        }
      }
      bvh_.frames.push_back(std::move(row));
    }
    if (static_cast<long>(bvh_.frames.size()) != nframe) {
      fail(frames_line, "Frames", "says " + std::to_string(nframe) + " frames but the file has " +
                                      std::to_string(bvh_.frames.size()));
    }
  }

  std::string source_;
  std::vector<std::string> lines_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  BvhFile bvh_;
};

int axis_index(char c) { return c == 'X' ? 0 : c == 'Y' ? 1 : 2; }

void check_order(const std::string& order) {
  std::string s = upper(order);
  std::sort(s.begin(), s.end());
  if (order.size() != 3 || s != "XYZ") {
    throw_input_error("", "", "euler order", "'" + order + "' is not a permutation of XYZ");
  }
}

std::string fmt(double v) {
  if (std::abs(v) < 1e-12) v = 0.0;
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

std::string bvh_name(std::string n, std::set<std::string>& used) {
  for (char& c : n) {
    if (std::isspace(static_cast<unsigned char>(c)) || c == '{' || c == '}') c = '_';
  }
  if (n.empty()) n = "bone";
  std::string out = n;
  for (int k = 2; !used.insert(out).second; ++k) out = n + "_" + std::to_string(k);
  return out;
}

}  // namespace

// ---------------------------------------------------------------- reading

BvhFile parse_bvh(const std::string& text, const std::string& source) {
  return Parser(text, source).parse();
}

BvhFile read_bvh_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(path, "", "", "cannot open file");
  std::ostringstream s;
  s << in.rdbuf();
  return parse_bvh(s.str(), path);
}

Quat bvh_local_rotation(const BvhJoint& joint, const std::vector<double>& row) {
  Quat q = Quat::Identity();
  double quat[4] = {1, 0, 0, 0};  // w x y z
  bool have_quat = false;
  for (std::size_t c = 0; c < joint.channels.size(); ++c) {
    const double v = row.empty() ? 0.0 : row[joint.channel_start + c];
    switch (joint.channels[c]) {
      case BvhChannel::kXrot: q = q * Eigen::AngleAxisd(deg2rad(v), Vec3::UnitX()); break;
      case BvhChannel::kYrot: q = q * Eigen::AngleAxisd(deg2rad(v), Vec3::UnitY()); break;
      case BvhChannel::kZrot: q = q * Eigen::AngleAxisd(deg2rad(v), Vec3::UnitZ()); break;
      case BvhChannel::kWquat: quat[0] = row.empty() ? 1.0 : v; have_quat = true; break;
      case BvhChannel::kXquat: quat[1] = v; have_quat = true; break;
      case BvhChannel::kYquat: quat[2] = v; have_quat = true; break;
      case BvhChannel::kZquat: quat[3] = v; have_quat = true; break;
      default: break;
    }
  }
  if (have_quat) q = Quat(quat[0], quat[1], quat[2], quat[3]);
  return q.normalized();
}

Vec3 bvh_local_translation(const BvhJoint& joint, const std::vector<double>& row) {
  Vec3 t = joint.offset;
  if (row.empty()) return t;
  for (std::size_t c = 0; c < joint.channels.size(); ++c) {
    const double v = row[joint.channel_start + c];
    switch (joint.channels[c]) {
      case BvhChannel::kXpos: t.x() = v; break;
      case BvhChannel::kYpos: t.y() = v; break;
      case BvhChannel::kZpos: t.z() = v; break;
      default: break;
    }
  }
  return t;
}

void bvh_world(const BvhFile& bvh, int frame, std::vector<Quat>& rot_world,
               std::vector<Vec3>& pos_world) {
  static const std::vector<double> kRest;
  const std::vector<double>& row = frame < 0 ? kRest : bvh.frames[frame];
  const std::size_t n = bvh.joints.size();
  rot_world.resize(n);
  pos_world.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BvhJoint& j = bvh.joints[i];
    const Quat local = bvh_local_rotation(j, row);
    const Vec3 t = bvh_local_translation(j, row);
    if (j.parent < 0) {
      rot_world[i] = local;
      pos_world[i] = t;
    } else {
      rot_world[i] = (rot_world[j.parent] * local).normalized();
      pos_world[i] = pos_world[j.parent] + rot_world[j.parent] * t;
    }
  }
}

Quat bvh_axes_to_rig(BvhAxes axes) {
  if (axes == BvhAxes::kZUp) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));  // file Y -> rig Z, file Z -> rig -Y
}

BvhAnimation bvh_to_rig(const BvhFile& bvh, const std::string& source,
                        const BvhImportOptions& options) {
  if (!(options.scale > 0.0) || !std::isfinite(options.scale)) {
    throw_input_error(source, "", "scale", "must be a positive number");
  }
  const Quat a = bvh_axes_to_rig(options.axes);
  const double s = options.scale;

  std::vector<Quat> rot;
  std::vector<Vec3> pos;
  bvh_world(bvh, -1, rot, pos);
  std::vector<PivotNode> nodes(bvh.joints.size());
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    nodes[i].name = j.name;
    nodes[i].parent = j.parent;
    nodes[i].rest_world = s * (a * pos[i]);
    for (const Vec3& e : j.end_sites) nodes[i].ends_world.push_back(s * (a * (pos[i] + e)));
  }
  const PivotBones bones =
      pivot_bones(nodes, source, options.mass_per_length, options.radius);
  BvhAnimation anim;
  anim.pivots = finish_pivot_rig(nodes, bones, source, "");
  anim.frame_time = bvh.frame_time;

  // per frame: every pivot's rotation and position in rig axes -> pose; check FK against BVH
  std::vector<Quat> node_rot(nodes.size());
  std::vector<Vec3> node_pos(nodes.size());
  BoneFrames scratch, fk;
  std::vector<Vec3> want_head, want_tail;
  anim.poses.resize(bvh.frames.size());
  for (std::size_t f = 0; f < bvh.frames.size(); ++f) {
    bvh_world(bvh, static_cast<int>(f), rot, pos);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      node_rot[i] = (a * rot[i] * a.conjugate()).normalized();
      node_pos[i] = s * (a * pos[i]);
    }
    pivot_pose(anim.pivots, node_rot, node_pos[0], scratch, anim.poses[f]);
    forward_kinematics(anim.rig(), anim.poses[f], fk);
    pivot_bone_targets(anim.pivots, node_pos, node_rot, want_head, want_tail);
    for (int b = 0; b < anim.rig().nbone; ++b) {
      anim.max_position_error = std::max({anim.max_position_error,
                                          (fk.head_world[b] - want_head[b]).norm(),
                                          (fk.tail_world[b] - want_tail[b]).norm()});
    }
  }
  return anim;
}

BvhAnimation load_bvh(const std::string& path, const BvhImportOptions& options) {
  return bvh_to_rig(read_bvh_file(path), path, options);
}

// ---------------------------------------------------------------- Euler angles

Quat rotation_from_euler(const Vec3& angles, const std::string& order) {
  check_order(order);
  Quat q = Quat::Identity();
  for (int k = 0; k < 3; ++k) {
    q = q * Eigen::AngleAxisd(angles[k], Vec3::Unit(axis_index(std::toupper(order[k]))));
  }
  return q;
}

Vec3 euler_from_rotation(const Quat& q, const std::string& order) {
  check_order(order);
  // R = R_i(a) R_j(b) R_k(c); s = +1 for cyclic orders (XYZ, YZX, ZXY), -1 otherwise
  const int i = axis_index(std::toupper(order[0]));
  const int j = axis_index(std::toupper(order[1]));
  const int k = axis_index(std::toupper(order[2]));
  const double s = j == (i + 1) % 3 ? 1.0 : -1.0;
  const Mat3 m = q.normalized().toRotationMatrix();
  // cos b from the two other entries of row i: M(i,i) = cos b cos c, M(i,j) = -s cos b sin c
  const double cb = std::hypot(m(i, i), m(i, j));
  const double b = std::atan2(s * m(i, k), cb);
  double a, c;
  if (cb > 1e-9) {
    a = std::atan2(-s * m(j, k), m(k, k));
    c = std::atan2(-s * m(i, j), m(i, i));
  } else {
    // gimbal lock: only a + c (or a - c) is defined; put it all in a
    c = 0.0;
    const Mat3 mi = m * Eigen::AngleAxisd(b, Vec3::Unit(j)).toRotationMatrix().transpose();
    a = std::atan2(mi((i + 2) % 3, (i + 1) % 3), mi((i + 1) % 3, (i + 1) % 3));
  }
  return Vec3(a, b, c);
}

namespace {

// the equivalent Euler triple closest to `prev` (the other branch (a+pi, pi-b, c+pi) and 2 pi turns)
Vec3 closest_euler(const Vec3& e, const Vec3& prev) {
  auto wrap_near = [](double v, double ref) {
    return v + 2.0 * kPi * std::round((ref - v) / (2.0 * kPi));
  };
  Vec3 best = e;
  double best_d = std::numeric_limits<double>::infinity();
  for (const Vec3& cand : {e, Vec3(e[0] + kPi, kPi - e[1], e[2] + kPi)}) {
    Vec3 w;
    for (int k = 0; k < 3; ++k) w[k] = wrap_near(cand[k], prev[k]);
    const double d = (w - prev).cwiseAbs().sum();
    if (d < best_d) {
      best_d = d;
      best = w;
    }
  }
  return best;
}

}  // namespace

// ---------------------------------------------------------------- writing

bool is_qbvh_path(const std::string& path) {
  return path.size() >= 5 && upper(path.substr(path.size() - 5)) == ".QBVH";
}

void write_bvh(const Rig& rig, const std::vector<Pose>& poses_in, const BvhExportOptions& options,
               std::ostream& out) {
  std::string order = upper(options.euler_order);
  check_order(order);
  if (!(options.scale > 0.0)) throw_input_error("", "", "scale", "must be positive");
  if (!(options.frame_time > 0.0)) throw_input_error("", "", "frame time", "must be positive");
  const std::vector<Pose> rest{rest_pose(rig)};
  const std::vector<Pose>& poses = poses_in.empty() ? rest : poses_in;
  const Quat a = bvh_axes_to_rig(options.axes);
  const Quat ainv = a.conjugate();
  const double s = options.scale;
  auto to_file = [&](const Vec3& v) { return Vec3(s * (ainv * v)); };

  std::set<std::string> used;
  std::vector<std::string> names(rig.nbone);
  for (int b = 0; b < rig.nbone; ++b) names[b] = bvh_name(rig.bone_name[b], used);

  std::string rot_channels;
  if (options.quaternion) {
    rot_channels = "Wquaternion Xquaternion Yquaternion Zquaternion";
  } else {
    for (char c : order) rot_channels += std::string(rot_channels.empty() ? "" : " ") + c + "rotation";
  }
  const int nrot = options.quaternion ? 4 : 3;

  out << "HIERARCHY\n";
  // recursive writer over the rig's DFS tree
  std::function<void(int, int)> joint = [&](int b, int depth) {
    const std::string ind(2 * depth, ' ');
    const int p = rig.bone_parent[b];
    const Vec3 off = to_file(p < 0 ? rig.bone_rest_head_world[b]
                                   : Vec3(rig.bone_rest_head_world[b] - rig.bone_rest_head_world[p]));
    out << ind << (p < 0 ? "ROOT " : "JOINT ") << names[b] << "\n" << ind << "{\n";
    out << ind << "  OFFSET " << fmt(off.x()) << " " << fmt(off.y()) << " " << fmt(off.z()) << "\n";
    if (p < 0) {
      out << ind << "  CHANNELS " << 3 + nrot << " Xposition Yposition Zposition " << rot_channels
          << "\n";
    } else {
      out << ind << "  CHANNELS " << nrot << " " << rot_channels << "\n";
    }
    for (int c : rig.bone_children[b]) joint(c, depth + 1);
    if (rig.bone_children[b].empty()) {
      const Vec3 e = to_file(rig.bone_rest_tail_world[b] - rig.bone_rest_head_world[b]);
      out << ind << "  End Site\n" << ind << "  {\n" << ind << "    OFFSET " << fmt(e.x()) << " "
          << fmt(e.y()) << " " << fmt(e.z()) << "\n" << ind << "  }\n";
    }
    out << ind << "}\n";
  };
  joint(0, 0);

  out << "MOTION\nFrames: " << poses.size() << "\nFrame Time: " << fmt(options.frame_time)
      << "\n";
  BoneFrames fk;
  std::vector<Quat> rw(rig.nbone);
  std::vector<Vec3> prev_euler(rig.nbone, Vec3::Zero());
  std::vector<Quat> prev_quat(rig.nbone, Quat::Identity());
  for (std::size_t f = 0; f < poses.size(); ++f) {
    forward_kinematics(rig, poses[f], fk);
    const Vec3 root = to_file(fk.head_world[0]);
    out << fmt(root.x()) << " " << fmt(root.y()) << " " << fmt(root.z());
    for (int b = 0; b < rig.nbone; ++b) {
      // world rotation from rest, then relative to the parent's, in file axes
      rw[b] = (fk.orient_world[b] * rig.bone_rest_orient_world[b].conjugate()).normalized();
      const int p = rig.bone_parent[b];
      const Quat local = p < 0 ? rw[b] : Quat(rw[p].conjugate() * rw[b]);
      Quat lf = (ainv * local * a).normalized();
      if (options.quaternion) {
        if (lf.coeffs().dot(prev_quat[b].coeffs()) < 0.0) lf.coeffs() *= -1.0;
        prev_quat[b] = lf;
        out << " " << fmt(lf.w()) << " " << fmt(lf.x()) << " " << fmt(lf.y()) << " "
            << fmt(lf.z());
      } else {
        Vec3 e = euler_from_rotation(lf, order);
        if (f > 0) e = closest_euler(e, prev_euler[b]);
        prev_euler[b] = e;
        out << " " << fmt(rad2deg(e[0])) << " " << fmt(rad2deg(e[1])) << " "
            << fmt(rad2deg(e[2]));
      }
    }
    out << "\n";
  }
}

void save_bvh(const std::string& path, const Rig& rig, const std::vector<Pose>& poses,
              const BvhExportOptions& options) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  std::ofstream out(p);
  if (!out) throw_input_error(path, "", "", "cannot write file");
  write_bvh(rig, poses, options, out);
  if (!out) throw_input_error(path, "", "", "write failed");
}

BvhRecorder::BvhRecorder(const Rig& rig, double dt, int every, BvhExportOptions options)
    : rig_(rig), every_(every), options_(std::move(options)) {
  if (every < 1) throw_input_error("", "", "every", "must be at least 1");
  if (!(dt > 0.0)) throw_input_error("", "", "dt", "must be positive");
  options_.frame_time = dt * every;
}

void BvhRecorder::record(const Pose& pose) {
  if (calls_++ % every_ == 0) poses_.push_back(pose);
}

void BvhRecorder::record(const BoneFrames& frames) {
  if (calls_++ % every_ != 0) return;
  Pose p;
  local_rotations_from_world(rig_, frames, p);
  poses_.push_back(std::move(p));
}

void BvhRecorder::write(std::ostream& out) const { write_bvh(rig_, poses_, options_, out); }

void BvhRecorder::save(const std::string& path) const {
  BvhExportOptions o = options_;
  o.quaternion = o.quaternion || is_qbvh_path(path);
  save_bvh(path, rig_, poses_, o);
}

}  // namespace physik
