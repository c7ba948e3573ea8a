// What the BVH files share inside physik/io (bvh_parse, bvh_rig, bvh_euler, bvh_write): text and
// Euler-order helpers. Not part of the interface (bvh.h).
#pragma once

#include <algorithm>
#include <cctype>
#include <string>
#include <utility>

#include "physik/io/bvh.h"
#include "physik/model/errors.h"
#include "physik/model/types.h"

namespace physik::bvh_detail {

inline std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// channel names as BVH writes them, and read back in any case
inline const std::pair<const char*, BvhChannel>* channel_names(std::size_t& n) {
  static const std::pair<const char*, BvhChannel> kNames[] = {
      {"Xposition", BvhChannel::kXpos},    {"Yposition", BvhChannel::kYpos},
      {"Zposition", BvhChannel::kZpos},    {"Xrotation", BvhChannel::kXrot},
      {"Yrotation", BvhChannel::kYrot},    {"Zrotation", BvhChannel::kZrot},
      {"Wquaternion", BvhChannel::kWquat}, {"Xquaternion", BvhChannel::kXquat},
      {"Yquaternion", BvhChannel::kYquat}, {"Zquaternion", BvhChannel::kZquat}};
  n = sizeof(kNames) / sizeof(kNames[0]);
  return kNames;
}

inline bool channel_from_name(const std::string& name, BvhChannel& out) {
  std::size_t n = 0;
  const auto* names = channel_names(n);
  const std::string u = upper(name);
  for (std::size_t i = 0; i < n; ++i) {
    if (u == upper(names[i].first)) {
      out = names[i].second;
      return true;
    }
  }
  return false;
}

inline const char* channel_name(BvhChannel c) {
  std::size_t n = 0;
  const auto* names = channel_names(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (names[i].second == c) return names[i].first;
  }
  return "";
}

inline bool is_rotation(BvhChannel c) {
  return c == BvhChannel::kXrot || c == BvhChannel::kYrot || c == BvhChannel::kZrot;
}
inline bool is_quaternion(BvhChannel c) {
  return c == BvhChannel::kWquat || c == BvhChannel::kXquat || c == BvhChannel::kYquat ||
         c == BvhChannel::kZquat;
}
inline bool is_position(BvhChannel c) {
  return c == BvhChannel::kXpos || c == BvhChannel::kYpos || c == BvhChannel::kZpos;
}

inline int axis_index(char c) {
  return c == 'X' ? 0 : c == 'Y' ? 1 : 2;
}

// `where` names the file in the message
inline void check_order(const std::string& order, const std::string& where = "") {
  std::string s = upper(order);
  std::sort(s.begin(), s.end());
  if (order.size() != 3 || s != "XYZ") {
    throw_input_error(where, "", "euler order", "'" + order + "' is not a permutation of XYZ");
  }
}

// the Euler triple equivalent to `e` closest to `prev` (bvh_euler.cpp)
Vec3 closest_euler(const Vec3& e, const Vec3& prev);

// write_bvh for a rig with a source skeleton: that skeleton and its channels (bvh_source.cpp)
BvhWriteReport write_source_bvh(const Rig& rig, const std::vector<Pose>& poses,
                                const BvhExportOptions& options, const SourceFrames& source,
                                std::ostream& out);

// refuses (InputError naming `target`) a file that physik's reader would refuse: an OFFSET, End
// Site or position channel beyond +-kMaxCoordinate, or a joint or End Site that the OFFSETs put
// beyond it at rest (bvh_to_rig at scale 1); each row holds every joint's channels in order
void check_readable(const BvhFile& bvh, const std::string& target);

}  // namespace physik::bvh_detail
