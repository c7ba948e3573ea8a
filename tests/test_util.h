// Shared test helpers: one tolerance helper, paths to shipped models, a file's text.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "physik/model/types.h"

namespace physik::test {

inline std::string model_path(const std::string& rel) {
  return std::string(PHYSIK_SOURCE_DIR) + "/models/" + rel;
}

// the whole text of a file ("" when it cannot be read: the caller's assertions then fail)
inline std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream buf;
  buf << in.rdbuf();
  return buf.str();
}

// |a - b| <= tol, element-wise max norm, with a readable failure message
inline ::testing::AssertionResult near(const Vec3& a, const Vec3& b, double tol) {
  const double err = (a - b).cwiseAbs().maxCoeff();
  if (err <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a.transpose() << ") vs (" << b.transpose()
                                       << "): max error " << err << " > " << tol;
}

// rotation angle between two orientations (rad)
inline double angle_between(const Quat& a, const Quat& b) {
  return a.angularDistance(b);
}

}  // namespace physik::test
