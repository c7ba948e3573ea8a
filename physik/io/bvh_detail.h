// What the BVH files share inside physik/io (bvh_parse, bvh_rig, bvh_euler, bvh_write): text and
// Euler-order helpers. Not part of the interface (bvh.h).
#pragma once

#include <algorithm>
#include <cctype>
#include <string>

#include "physik/model/errors.h"
#include "physik/model/types.h"

namespace physik::bvh_detail {

inline std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
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

}  // namespace physik::bvh_detail
