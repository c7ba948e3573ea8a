// BVH and qBVH text into a BvhFile: tokens, the hierarchy and the motion, every error naming the
// file and the line (the format: bvh.h).
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

#include "physik/io/bvh_detail.h"
#include "physik/model/errors.h"
#include "physik/model/input_bounds.h"
#include "physik/model/names.h"

namespace physik {

using bvh_detail::channel_from_name;
using bvh_detail::is_quaternion;
using bvh_detail::is_rotation;
using bvh_detail::upper;

namespace {

// ---------------------------------------------------------------- parsing

struct Token {
  std::string text;
  int line;  // 1-based
};

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
    int index;  // into bvh_.joints
    int line;   // of its ROOT/JOINT keyword
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
      fail(t.line, field,
           "'" + t.text + "' is beyond +-" + fmt_limit(kMaxCoordinate) + " (rig.h kMaxCoordinate)");
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
      fail(t.line, "{",
           "unbalanced braces: expected '{' to open " + what + " (line " + std::to_string(kw.line) +
               "), got '" + t.text + "'");
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
          fail(t.line, "CHANNELS",
               "the count says " + std::to_string(n) + " but " + std::to_string(k) +
                   " channel names follow");
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
      fail(kw.line, kw.text,
           "more than " + std::to_string(kMaxBones) + " joints (rig.h kMaxBones)");
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
    if (upper(o.text) == "CHANNELS") {
      fail(o.line, "CHANNELS", "an End Site has no channels (it is a point, only an OFFSET)");
    }
    if (upper(o.text) != "OFFSET") fail(o.line, "End Site", "expected OFFSET");
    bvh_.joints[index].end_sites.push_back(offset());
    const Token& close = next("}");
    if (upper(close.text) == "CHANNELS") {
      fail(close.line, "CHANNELS", "an End Site has no channels (it is a point, only an OFFSET)");
    }
    if (close.text != "}") {
      fail(close.line, "}",
           "unbalanced braces: the End Site at line " + std::to_string(kw.line) +
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
             "unbalanced braces: joint '" + name + "' opened at line " + std::to_string(top.line) +
                 " is never closed");
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
      fail(line, "MOTION",
           "frame " + std::to_string(bvh_.frames.size()) + " has " + std::to_string(w.size()) +
               " values, the hierarchy has " + std::to_string(bvh_.nchannel) + " channels");
    }
    std::vector<double> row(w.size());
    for (const BvhJoint& j : bvh_.joints) {
      double n2 = 0.0;
      bool quat = false;
      for (std::size_t c = 0; c < j.channels.size(); ++c) {
        const std::size_t k = j.channel_start + c;
        const BvhChannel ch = j.channels[c];
        const bool position =
            ch == BvhChannel::kXpos || ch == BvhChannel::kYpos || ch == BvhChannel::kZpos;
        row[k] = position ? coordinate(Token{w[k], line}, "MOTION")
                          : number(Token{w[k], line}, "MOTION");
        if (!position && !is_quaternion(ch) && !(std::abs(row[k]) <= kMaxAngleDeg)) {
          static_assert(kMaxAngleDeg == 1e6, "the message below quotes it");
          fail(line, "MOTION",
               "frame " + std::to_string(bvh_.frames.size()) + ": joint '" + j.name +
                   "': " + bvh_channel_name(ch) + " '" + w[k] +
                   "' is beyond +-1e6 degrees (input_bounds.h kMaxAngleDeg)");
        }
        if (is_quaternion(ch)) {
          quat = true;
          n2 += row[k] * row[k];
        }
      }
      static_assert(kQuaternionNormTol == 1e-3, "bvh.h quotes it");
      if (quat && std::abs(std::sqrt(n2) - 1.0) > kQuaternionNormTol) {
        fail(line, "MOTION",
             "joint '" + j.name + "': quaternion norm " + std::to_string(std::sqrt(n2)) +
                 " is not 1");
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
        fail(line, "Frames",
             "more frames than 'Frames: " + std::to_string(nframe) + "' (line " +
                 std::to_string(frames_line) + ")");
      }
      bvh_.frames.push_back(frame_row(w, line));
    }
    if (static_cast<long>(bvh_.frames.size()) != nframe) {
      fail(frames_line, "Frames",
           "says " + std::to_string(nframe) + " frames but the file has " +
               std::to_string(bvh_.frames.size()));
    }
  }

  std::string source_;
  std::vector<std::string> lines_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  BvhFile bvh_;
};

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

void check_bvh_frames(BvhFile& bvh, const std::string& source) {
  int col = 0;
  for (BvhJoint& j : bvh.joints) {
    j.channel_start = col;
    col += static_cast<int>(j.channels.size());
  }
  bvh.nchannel = col;
  if (!(bvh.frame_time > 0.0) || !std::isfinite(bvh.frame_time)) {
    throw_input_error(source, "", "frame_time", "must be a positive finite number (s)");
  }
  for (std::size_t f = 0; f < bvh.frames.size(); ++f) {
    const std::vector<double>& row = bvh.frames[f];
    const std::string el = "frame " + std::to_string(f);
    if (static_cast<int>(row.size()) != col) {
      throw_input_error(source, el, "values",
                        std::to_string(row.size()) + " values, the hierarchy has " +
                            std::to_string(col) + " channels");
    }
    for (const BvhJoint& j : bvh.joints) {
      double n2 = 0.0;
      bool quat = false;
      for (std::size_t c = 0; c < j.channels.size(); ++c) {
        const double v = row[j.channel_start + c];
        const bool position = bvh_detail::is_position(j.channels[c]);
        if (!std::isfinite(v) || (position && std::abs(v) > kMaxCoordinate)) {
          throw_input_error(
              source, el, std::string("joint '") + j.name + "' " + bvh_channel_name(j.channels[c]),
              position ? "not a finite coordinate within +-1e9" : "not finite");
        }
        quat = quat || is_quaternion(j.channels[c]);
        if (is_quaternion(j.channels[c])) n2 += v * v;
      }
      if (quat && std::abs(std::sqrt(n2) - 1.0) > 1e-3) {
        throw_input_error(source, el, "joint '" + j.name + "' quaternion",
                          "norm " + std::to_string(std::sqrt(n2)) + " is not 1 (within 1e-3)");
      }
    }
  }
}

}  // namespace physik
