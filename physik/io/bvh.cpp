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
#include <iomanip>
#include <limits>
#include <sstream>

#include "physik/io/output_files.h"
#include "physik/model/errors.h"
#include "physik/io/unique_names.h"
#include "physik/model/names.h"

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

// the words of a line, split at the whitespace std::isspace knows (space, \t, \n, \v, \f, \r):
// the tokenizer and the MOTION reader must agree on what a blank line is
std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> w;
  std::string cur;
  for (char c : line) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty()) w.push_back(std::move(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) w.push_back(std::move(cur));
  return w;
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
    tokenize();
  }

  BvhFile parse() {
    expect_keyword("HIERARCHY");
    const Token& root = next("ROOT");
    if (upper(root.text) != "ROOT") fail(root.line, root.text, "expected ROOT");
    parse_hierarchy(root);
    if (at_end()) fail(last_line(), "MOTION", "missing MOTION section after the hierarchy");
    const Token& t = peek();
    if (t.text == "}") {
      fail(t.line, "}", "unbalanced braces: a '}' closes nothing");
    }
    if (upper(t.text) == "ROOT") {
      fail(t.line, "ROOT", "a second ROOT: the rig model has exactly one root");
    }
    if (upper(t.text) != "MOTION") fail(t.line, t.text, "expected MOTION after the hierarchy");
    ++pos_;
    parse_motion(t.line);
    return std::move(bvh_);
  }

 private:
  // a joint whose '{' is open, innermost last
  struct OpenJoint {
    int index;         // into bvh_.joints
    int line;          // of its ROOT/JOINT keyword
    bool have_offset;
  };

  [[noreturn]] void fail(int line, const std::string& field, const std::string& reason) const {
    throw_input_error(source_, "line " + std::to_string(line), field, reason);
  }
  int last_line() const { return std::max<int>(1, static_cast<int>(lines_.size())); }

  void tokenize() {
    for (std::size_t l = 0; l < lines_.size(); ++l) {
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
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0') fail(t.line, field, "'" + t.text + "' is not a number");
    // an underflow to 0 is a number; an overflow is infinite
    if (!std::isfinite(v)) fail(t.line, field, "'" + t.text + "' is not a finite number");
    return v;
  }

  // a coordinate (OFFSET, position channel): bounded so that sums and products stay finite
  double coordinate(const Token& t, const std::string& field) const {
    const double v = number(t, field);
    if (std::abs(v) > kMaxCoordinate) {
      fail(t.line, field, "'" + t.text + "' is beyond +-" + fmt_limit(kMaxCoordinate) +
                              " (rig.h kMaxCoordinate)");
    }
    return v;
  }
  static std::string fmt_limit(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

  Vec3 offset() {
    Vec3 v;
    for (int k = 0; k < 3; ++k) {
      const Token& t = next("OFFSET");
      if (t.text == "}" || t.text == "{") {
        fail(t.line, "OFFSET", "expected 3 numbers, got " + std::to_string(k));
      }
      v[k] = coordinate(t, "OFFSET");
    }
    return v;
  }

  // the name is the rest of the keyword's line (names may hold spaces), without braces; it must
  // be printable UTF-8 (names.h) since it travels into JSON, CSV and BVH files
  std::string name_after(const Token& kw) {
    std::string name;
    while (!at_end() && peek().line == kw.line && peek().text != "{" && peek().text != "}") {
      if (!name.empty()) name += ' ';
      name += tokens_[pos_++].text;
    }
    if (name.empty()) fail(kw.line, kw.text, "missing joint name");
    const std::string bad = name_problem(name);
    if (!bad.empty()) fail(kw.line, "joint name", bad);
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

  // ROOT/JOINT name {: a new joint, now the innermost open one
  void open_joint(const Token& kw, int parent, std::vector<OpenJoint>& open) {
    if (bvh_.joints.size() >= static_cast<std::size_t>(kMaxBones)) {
      fail(kw.line, kw.text, "more than " + std::to_string(kMaxBones) +
                                 " joints (rig.h kMaxBones)");
    }
    BvhJoint j;
    j.name = name_after(kw);
    j.parent = parent;
    j.line = kw.line;
    expect_open(kw, "joint '" + j.name + "'");
    open.push_back({static_cast<int>(bvh_.joints.size()), kw.line, false});
    bvh_.joints.push_back(std::move(j));
  }

  // End Site { OFFSET x y z }
  void end_site(int index, const Token& kw) {
    const Token& site = next("End Site");
    if (upper(site.text) != "SITE") fail(site.line, "End Site", "expected 'Site' after 'End'");
    expect_open(kw, "an End Site");
    const Token& o = next("OFFSET");
    if (upper(o.text) != "OFFSET") fail(o.line, "End Site", "expected OFFSET");
    bvh_.joints[index].end_sites.push_back(offset());
    const Token& close = next("}");
    if (close.text != "}") {
      fail(close.line, "}", "unbalanced braces: the End Site at line " + std::to_string(kw.line) +
                                " is not closed after its OFFSET");
    }
  }

  // The joint tree with an explicit stack of open joints: the file sets the nesting depth, so
  // no recursion may follow it. Every keyword belongs to the innermost open joint.
  void parse_hierarchy(const Token& root) {
    std::vector<OpenJoint> open;
    open_joint(root, -1, open);
    while (!open.empty()) {
      const OpenJoint top = open.back();
      const std::string& name = bvh_.joints[top.index].name;
      if (at_end() || upper(peek().text) == "MOTION") {
        fail(at_end() ? last_line() : peek().line, "}",
             "unbalanced braces: joint '" + name + "' opened at line " +
                 std::to_string(top.line) + " is never closed");
      }
      const Token t = next("}");
      const std::string u = upper(t.text);
      if (u == "}") {
        if (!top.have_offset) fail(top.line, "OFFSET", "joint '" + name + "' has no OFFSET");
        open.pop_back();
      } else if (u == "OFFSET") {
        bvh_.joints[top.index].offset = offset();
        open.back().have_offset = true;
      } else if (u == "CHANNELS") {
        parse_channels(bvh_.joints[top.index], t);
      } else if (u == "JOINT") {
        open_joint(t, top.index, open);
      } else if (u == "END") {
        end_site(top.index, t);
      } else if (u == "{") {
        fail(t.line, "{", "unbalanced braces: a '{' without ROOT, JOINT or End Site");
      } else if (u == "ROOT") {
        fail(t.line, "ROOT", "ROOT inside a joint (unbalanced braces?)");
      } else {
        fail(t.line, t.text, "unknown keyword in joint '" + name + "'");
      }
    }
  }

  // ---- MOTION: read line by line from the MOTION line; blank lines are skipped anywhere

  // index of the first non-blank line at or after l (lines_.size() if none)
  std::size_t skip_blank(std::size_t l) const {
    while (l < lines_.size() && split_words(lines_[l]).empty()) ++l;
    return l;
  }

  // "Frames: N" or "Frames : N" at line index l; returns N
  long frames_header(std::size_t l) const {
    const int line = static_cast<int>(l) + 1;
    const std::vector<std::string> w = split_words(lines_[l]);
    std::vector<std::string> value;
    if (!w.empty() && upper(w[0]) == "FRAMES:") {
      value.assign(w.begin() + 1, w.end());
    } else if (w.size() > 1 && upper(w[0]) == "FRAMES" && w[1] == ":") {
      value.assign(w.begin() + 2, w.end());
    } else {
      fail(line, "Frames", "expected 'Frames: N', got '" + lines_[l] + "'");
    }
    if (value.size() != 1) fail(line, "Frames", "expected one frame count");
    char* end = nullptr;
    errno = 0;
    const long nframe = std::strtol(value[0].c_str(), &end, 10);
    if (end == value[0].c_str() || *end != '\0' || nframe < 0 || errno == ERANGE) {
      fail(line, "Frames", "'" + value[0] + "' is not a frame count");
    }
    return nframe;
  }

  // "Frame Time: t" at line index l
  void frame_time_header(std::size_t l) {
    const int line = static_cast<int>(l) + 1;
    const std::vector<std::string> w = split_words(lines_[l]);
    if (w.size() != 3 || upper(w[0]) != "FRAME" || upper(w[1]) != "TIME:") {
      fail(line, "Frame Time", "expected 'Frame Time: t', got '" + lines_[l] + "'");
    }
    bvh_.frame_time = number(Token{w[2], line}, "Frame Time");
    if (!(bvh_.frame_time > 0.0)) fail(line, "Frame Time", "must be positive");
  }

  // every joint's first column in a frame row
  void assign_columns() {
    int col = 0;
    for (BvhJoint& j : bvh_.joints) {
      j.channel_start = col;
      col += static_cast<int>(j.channels.size());
    }
    bvh_.nchannel = col;
  }

  // one frame row (its words w, at 1-based line `line`): numbers, bounded positions, unit
  // quaternions (qBVH)
  std::vector<double> frame_row(const std::vector<std::string>& w, int line) const {
    if (static_cast<long>(w.size()) != bvh_.nchannel) {
      fail(line, "MOTION", "frame " + std::to_string(bvh_.frames.size()) + " has " +
                               std::to_string(w.size()) + " values, the hierarchy has " +
                               std::to_string(bvh_.nchannel) + " channels");
    }
    std::vector<double> row(w.size());
    for (const BvhJoint& j : bvh_.joints) {
      double n2 = 0.0;
      bool quat = false;
      for (std::size_t c = 0; c < j.channels.size(); ++c) {
        const std::size_t k = j.channel_start + c;
        const BvhChannel ch = j.channels[c];
        const bool position = ch == BvhChannel::kXpos || ch == BvhChannel::kYpos ||
                              ch == BvhChannel::kZpos;
        row[k] = position ? coordinate(Token{w[k], line}, "MOTION")
                          : number(Token{w[k], line}, "MOTION");
        if (is_quaternion(ch)) {
          quat = true;
          n2 += row[k] * row[k];
        }
      }
      if (quat && std::abs(std::sqrt(n2) - 1.0) > 1e-3) {
        fail(line, "MOTION", "joint '" + j.name + "': quaternion norm " +
                                 std::to_string(std::sqrt(n2)) + " is not 1");
      }
    }
    return row;
  }

  void parse_motion(int motion_line) {
    // nothing may follow MOTION on its line
    if (!at_end() && peek().line == motion_line) {
      fail(motion_line, "MOTION", "unexpected '" + peek().text + "' after MOTION");
    }
    std::size_t l = skip_blank(static_cast<std::size_t>(motion_line));
    if (l >= lines_.size()) fail(last_line(), "Frames", "missing 'Frames:' after MOTION");
    const long nframe = frames_header(l);
    const int frames_line = static_cast<int>(l) + 1;
    l = skip_blank(l + 1);
    if (l >= lines_.size()) fail(last_line(), "Frame Time", "missing 'Frame Time:'");
    frame_time_header(l);
    assign_columns();
    for (++l; l < lines_.size(); ++l) {
      const std::vector<std::string> w = split_words(lines_[l]);
      if (w.empty()) continue;
      const int line = static_cast<int>(l) + 1;
      if (static_cast<long>(bvh_.frames.size()) == nframe) {
        fail(line, "Frames", "more frames than 'Frames: " + std::to_string(nframe) +
                                 "' (line " + std::to_string(frames_line) + ")");
      }
      bvh_.frames.push_back(frame_row(w, line));
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

// `where` names the file in the message
void check_order(const std::string& order, const std::string& where = "") {
  std::string s = upper(order);
  std::sort(s.begin(), s.end());
  if (order.size() != 3 || s != "XYZ") {
    throw_input_error(where, "", "euler order", "'" + order + "' is not a permutation of XYZ");
  }
}

std::string fmt(double v) {
  if (std::abs(v) < 1e-12) v = 0.0;
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

std::string bvh_name(std::string n, UniqueNames& used) {
  for (char& c : n) {
    if (std::isspace(static_cast<unsigned char>(c)) || c == '{' || c == '}') c = '_';
  }
  if (n.empty()) n = "bone";
  return used.make(n);
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
  // rest positions in rig units must stay within the rig's coordinate range (rig.h)
  auto rig_point = [&](const BvhJoint& j, const Vec3& file_pos) {
    const Vec3 p = s * (a * file_pos);
    if (!(p.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
      throw_input_error(source, "line " + std::to_string(j.line), "OFFSET",
                        "joint '" + j.name + "' lies beyond +-" + std::to_string(kMaxCoordinate) +
                            " rig units at rest (sum of OFFSETs times the scale; rig.h "
                            "kMaxCoordinate)");
    }
    return p;
  };
  for (std::size_t i = 0; i < bvh.joints.size(); ++i) {
    const BvhJoint& j = bvh.joints[i];
    nodes[i].name = j.name;
    nodes[i].parent = j.parent;
    nodes[i].rest_world = rig_point(j, pos[i]);
    for (const Vec3& e : j.end_sites) nodes[i].ends_world.push_back(rig_point(j, pos[i] + e));
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

namespace {

// the destination in messages
std::string target_name(const BvhExportOptions& o) {
  return o.target.empty() ? std::string("<bvh output>") : o.target;
}

// stage 1: options that would write nan, inf or an unreadable file
void check_export_options(const BvhExportOptions& o) {
  const std::string t = target_name(o);
  check_order(o.euler_order, t);
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) {
    throw_input_error(t, "", "scale", "must be a positive finite number");
  }
  if (!(o.frame_time > 0.0) || !std::isfinite(o.frame_time)) {
    throw_input_error(t, "", "frame time", "must be a positive finite number");
  }
}

// a number for the file; a value the scale pushed past double range is bad input, not "inf"
std::string fmt_checked(double v, const BvhExportOptions& o, const std::string& what) {
  if (!std::isfinite(v)) {
    throw_input_error(target_name(o), what, "scale",
                      "the value is not finite (scale " + fmt(o.scale) + ")");
  }
  return fmt(v);
}

// stage 2: HIERARCHY, one joint per bone, iteratively (a rig may be a 10^6-bone chain);
// indentation stops deepening at 32 levels so the file stays linear in the bone count
void write_hierarchy(const Rig& rig, const std::vector<std::string>& names,
                     const std::string& rot_channels, int nrot, const BvhExportOptions& o,
                     std::ostream& out) {
  const Quat ainv = bvh_axes_to_rig(o.axes).conjugate();
  auto triple = [&](const Vec3& v_rig, const std::string& what) {
    const Vec3 v = o.scale * (ainv * v_rig);
    return fmt_checked(v.x(), o, what) + " " + fmt_checked(v.y(), o, what) + " " +
           fmt_checked(v.z(), o, what);
  };
  auto indent = [](int depth) { return std::string(2 * std::min(depth, 32), ' '); };
  out << "HIERARCHY\n";
  // (bone, depth) to open; a negative bone closes joint -bone-1
  std::vector<std::pair<int, int>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [b, depth] = stack.back();
    stack.pop_back();
    const std::string ind = indent(depth);
    if (b < 0) {
      out << ind << "}\n";
      continue;
    }
    const int p = rig.bone_parent[b];
    const Vec3 off = p < 0 ? rig.bone_rest_head_world[b]
                           : Vec3(rig.bone_rest_head_world[b] - rig.bone_rest_head_world[p]);
    const std::string el = "bone '" + names[b] + "'";
    out << ind << (p < 0 ? "ROOT " : "JOINT ") << names[b] << "\n" << ind << "{\n";
    out << ind << "  OFFSET " << triple(off, el) << "\n";
    if (p < 0) {
      out << ind << "  CHANNELS " << 3 + nrot << " Xposition Yposition Zposition " << rot_channels
          << "\n";
    } else {
      out << ind << "  CHANNELS " << nrot << " " << rot_channels << "\n";
    }
    if (rig.bone_children[b].empty()) {
      const Vec3 e = rig.bone_rest_tail_world[b] - rig.bone_rest_head_world[b];
      out << ind << "  End Site\n" << ind << "  {\n" << ind << "    OFFSET " << triple(e, el)
          << "\n" << ind << "  }\n";
    }
    stack.push_back({-b - 1, depth});
    const auto& kids = rig.bone_children[b];
    for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back({*it, depth + 1});
  }
}

// per-bone continuity across frames: Euler branch and quaternion hemisphere
struct FrameMemory {
  std::vector<Quat> rw;          // (nbone) world rotation from rest, this frame
  std::vector<Vec3> prev_euler;  // (nbone) rad
  std::vector<Quat> prev_quat;   // (nbone)
};

// stage 3: one frame row: the root's head, then every bone's rotation relative to its parent's
void write_frame(const Rig& rig, const Pose& pose, std::size_t f, const std::string& order,
                 const BvhExportOptions& o, BoneFrames& fk, FrameMemory& mem, std::ostream& out) {
  const Quat a = bvh_axes_to_rig(o.axes);
  const Quat ainv = a.conjugate();
  const std::string el = "frame " + std::to_string(f);
  forward_kinematics(rig, pose, fk);
  const Vec3 root = o.scale * (ainv * fk.head_world[0]);
  out << fmt_checked(root.x(), o, el) << " " << fmt_checked(root.y(), o, el) << " "
      << fmt_checked(root.z(), o, el);
  for (int b = 0; b < rig.nbone; ++b) {
    // world rotation from rest, then relative to the parent's, in file axes
    mem.rw[b] = (fk.orient_world[b] * rig.bone_rest_orient_world[b].conjugate()).normalized();
    const int p = rig.bone_parent[b];
    const Quat local = p < 0 ? mem.rw[b] : Quat(mem.rw[p].conjugate() * mem.rw[b]);
    Quat lf = (ainv * local * a).normalized();
    if (!lf.coeffs().allFinite()) {
      throw_input_error(target_name(o), el, "pose", "bone " + std::to_string(b) +
                                                        ": the rotation is not finite");
    }
    if (o.quaternion) {
      if (lf.coeffs().dot(mem.prev_quat[b].coeffs()) < 0.0) lf.coeffs() *= -1.0;
      mem.prev_quat[b] = lf;
      out << " " << fmt(lf.w()) << " " << fmt(lf.x()) << " " << fmt(lf.y()) << " "
          << fmt(lf.z());
    } else {
      Vec3 e = euler_from_rotation(lf, order);
      if (f > 0) e = closest_euler(e, mem.prev_euler[b]);
      mem.prev_euler[b] = e;
      out << " " << fmt(rad2deg(e[0])) << " " << fmt(rad2deg(e[1])) << " "
          << fmt(rad2deg(e[2]));
    }
  }
  out << "\n";
}

}  // namespace

void write_bvh(const Rig& rig, const std::vector<Pose>& poses_in, const BvhExportOptions& options,
               std::ostream& out) {
  check_export_options(options);
  const std::string order = upper(options.euler_order);
  const std::vector<Pose> rest{rest_pose(rig)};
  const std::vector<Pose>& poses = poses_in.empty() ? rest : poses_in;

  UniqueNames used;
  std::vector<std::string> names(rig.nbone);
  for (int b = 0; b < rig.nbone; ++b) names[b] = bvh_name(rig.bone_name[b], used);

  std::string rot_channels;
  if (options.quaternion) {
    rot_channels = "Wquaternion Xquaternion Yquaternion Zquaternion";
  } else {
    for (char c : order) rot_channels += std::string(rot_channels.empty() ? "" : " ") + c + "rotation";
  }
  write_hierarchy(rig, names, rot_channels, options.quaternion ? 4 : 3, options, out);

  out << "MOTION\nFrames: " << poses.size() << "\nFrame Time: " << fmt(options.frame_time)
      << "\n";
  BoneFrames fk;
  FrameMemory mem{std::vector<Quat>(rig.nbone), std::vector<Vec3>(rig.nbone, Vec3::Zero()),
                  std::vector<Quat>(rig.nbone, Quat::Identity())};
  for (std::size_t f = 0; f < poses.size(); ++f) {
    write_frame(rig, poses[f], f, order, options, fk, mem, out);
  }
}

void save_bvh(const std::string& path, const Rig& rig, const std::vector<Pose>& poses,
              const BvhExportOptions& options) {
  BvhExportOptions o = options;
  o.target = path;
  check_export_options(o);  // before a file is created
  std::ofstream out = open_output_file(path, "");
  write_bvh(rig, poses, o, out);
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
