// Bone radii and masses for converted skeletons (rig_sizing.h).
#include "physik/model/rig_sizing.h"

#include <cmath>
#include <string>

#include "physik/model/errors.h"
#include "physik/model/message_number.h"

namespace physik {

namespace {

void check_option(double value, const char* option, const char* unit) {
  if (!std::isfinite(value) || value < 0.0) {
    throw_input_error(option, "", "",
                      "must be a positive finite number (" + std::string(unit) + "), got " +
                          message_number(value));
  }
  if (value > 0.0 && (value < kMinScale || value > kMaxScale)) {
    throw_input_error(option, "", "",
                      message_number(value) + " " + unit + " is outside [" +
                          message_number(kMinScale) + ", " + message_number(kMaxScale) +
                          "] (rig.h)");
  }
}

}  // namespace

void check_sizing_options(const SizingOptions& options) {
  check_option(options.radius, "--radius", "rig units");
  check_option(options.mass_per_length, "--mass-per-length", "kg per rig unit");
  check_option(options.total_mass, "--total-mass", "kg");
}

double fitted_radius(const SizingOptions& options, double length) {
  return options.radius > 0.0 ? options.radius : kRadiusPerLength * length;
}

void fit_masses(std::vector<BoneSpec>& specs, const SizingOptions& options,
                const std::vector<bool>& keep_mass) {
  double sum = 0.0;
  for (std::size_t s = 0; s < specs.size(); ++s) {
    BoneSpec& b = specs[s];
    const double length = (b.tail_world - b.head_world).norm();
    if (options.mass_per_length > 0.0) {
      b.mass = options.mass_per_length * length;
      b.inertia_local.setZero();
    } else if (keep_mass.empty() || !keep_mass[s]) {
      b.mass = kBodyDensity * kPi * b.radius * b.radius * length;
    }
    sum += b.mass;
  }
  if (!(options.total_mass > 0.0) || !(sum > 0.0)) return;
  const double factor = options.total_mass / sum;
  for (BoneSpec& b : specs) {
    b.mass *= factor;
    b.inertia_local *= factor;
  }
}

}  // namespace physik
