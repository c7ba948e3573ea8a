// Unique names in linear time: "base", then "base_2", "base_3", ... (the first free suffix), with
// a counter per base so that n equal names cost O(n), not O(n^2) (20,000 BVH siblings of one
// name).
#pragma once

#include <string>
#include <unordered_map>
#include <unordered_set>

namespace physik {

class UniqueNames {
 public:
  // marks `name` as taken; false if it already was
  bool take(const std::string& name) { return used_.insert(name).second; }
  bool taken(const std::string& name) const { return used_.count(name) > 0; }

  // `base` if free, else base_k for the smallest free k >= 2; the result is taken
  std::string make(const std::string& base) {
    if (take(base)) return base;
    // every suffix below next_[base] is taken already (names are never released)
    int& k = next_[base];
    if (k < 2) k = 2;
    for (;; ++k) {
      std::string n = base + "_" + std::to_string(k);
      if (take(n)) {
        ++k;
        return n;
      }
    }
  }

 private:
  std::unordered_set<std::string> used_;
  std::unordered_map<std::string, int> next_;
};

}  // namespace physik
