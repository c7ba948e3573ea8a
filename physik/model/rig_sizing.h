// The sizes a converter gives a skeleton's bones (`rig from-bvh`, `rig from-mjcf`): a radius
// and a collision radius that fit the skeleton, and masses that follow them.
//
// Radius (rig units, after the converter's --scale): a source's own thickness where it has one
// (MuJoCo's capsule or sphere geoms, reference/mjcf_import.h), else
//   r = kRadiusPerLength x L                         (L the bone's length)
// kRadiusPerLength = 0.14 is the median radius over length of the limb capsules of MuJoCo's
// humanoid (humanoid.xml: thigh 0.06 / 0.34 = 0.18, shin 0.049 / 0.30 = 0.16, upper arm
// 0.04 / 0.28 = 0.14, foot 0.027 / 0.21 = 0.13, lower arm 0.031 / 0.28 = 0.11), so a bone
// is as thick as the limb it stands for in MuJoCo's own model of a human. The collision capsule
// takes the same radius: the body's thickness is what touches.
// Mass (kg): a solid cylinder of that radius at kBodyDensity,
//   m = rho pi r^2 L,   rho = 1000 kg / m^3 (water: MuJoCo's default geom density, and within
//                       10% of every body segment's, Winter, Biomechanics and Motor Control of
//                       Human Movement, 4th ed., Table 4.1)
// with rig units read as metres (the rig format's convention), so a file in centimetres
// converted without --scale 0.01 is a giant, not a 1.7 m figure, and the converter says so.
// Options replace these: a radius for every bone (--radius), mass_per_length x L instead of the
// rod (--mass-per-length, kg per rig unit), and every mass scaled so the rig weighs total_mass
// (--total-mass, kg; explicit inertias scale with their masses).
#pragma once

#include <vector>

#include "physik/model/rig.h"

namespace physik {

constexpr double kRadiusPerLength = 0.14;  // 1, radius over length of a bone without geometry
constexpr double kBodyDensity = 1000.0;    // kg per cubic rig unit (rig units read as metres)

struct SizingOptions {
  double radius = 0.0;           // rig units, every bone's radius and collision radius; 0: each
                                 //   bone's own (the source's, else kRadiusPerLength x L)
  double mass_per_length = 0.0;  // kg per rig unit; 0: the rod of density kBodyDensity
  double total_mass = 0.0;       // kg, the rig's mass after scaling; 0: no scaling
};

// Throws InputError naming the option (--radius, --mass-per-length, --total-mass) for a value
// that is not a finite number, is negative, or (when given, > 0) lies outside
// [kMinScale, kMaxScale] (rig.h). Both mass options may be given: mass_per_length sets the
// ratios between the bones, total_mass their sum.
void check_sizing_options(const SizingOptions& options);

// The radius of a bone of length L with no source thickness: options.radius when given, else
// kRadiusPerLength x L.
double fitted_radius(const SizingOptions& options, double length);

// Sets the masses of `specs`: mass_per_length x L when given, else (when `keep_mass` is false
// for the bone) the rod of density kBodyDensity with the bone's radius; then, with total_mass,
// scales every mass (and every explicit inertia) by total_mass / sum. `keep_mass` (nspec, or
// empty: all false) marks bones whose mass came from the source (MuJoCo's bodies), which only
// mass_per_length and total_mass change; a bone that mass_per_length re-masses loses its
// explicit inertia (the cylinder of its radius then).
void fit_masses(std::vector<BoneSpec>& specs, const SizingOptions& options,
                const std::vector<bool>& keep_mass = {});

}  // namespace physik
