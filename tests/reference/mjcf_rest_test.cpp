// MuJoCo's sample models, converted as `rig from-mjcf` and the outside_rigs experiment convert
// them, rest where they are put: no target, no gravity, 100 steps, in every scheme, with and
// without self-collision, and the converter says by bone what it changed to make it so.
#include <gtest/gtest.h>

#include <filesystem>

#include "experiments/at_rest.h"
#include "experiments/outside_rigs.h"
#include "physik/engine/bone_overlaps.h"
#include "physik/model/params.h"
#include "physik/model/rest_limits.h"
#include "reference/mjcf_import.h"

namespace physik {
namespace {

namespace outside = experiments::outside_rigs;

TEST(MjcfRest, EverySampleModelStaysAtRest) {
  if (!std::filesystem::is_directory(outside::kSamplesDir)) {
    GTEST_SKIP() << outside::kSamplesDir << " missing (Debian's libmujoco-samples)";
  }
  const outside::Collection c = outside::collect_rigs(outside::sample_files(outside::kSamplesDir));
  ASSERT_GE(c.rigs.size(), 5u);
  const double t = preset_params("robust").torsion_tolerance;
  for (const outside::OutsideRig& r : c.rigs) {
    // nothing left for the engine to push at rest: no band, no open overlap
    EXPECT_TRUE(rest_band_problems(r.rig, t).empty()) << r.name;
    for (const BoneOverlap& o : rest_overlaps(r.rig)) EXPECT_TRUE(o.excluded) << r.name;
    // with no force acting, every scheme's accelerations are sums of exact zeros
    for (auto scheme : {experiments::RestScheme::kGaussSeidel, experiments::RestScheme::kExact,
                        experiments::RestScheme::kImplicit}) {
      for (bool self : {false, true}) {
        EXPECT_EQ(experiments::rest_kinetic_energy(r.rig, scheme, self), 0.0)
            << r.name << ", " << to_string(scheme) << (self ? ", self_collision" : "");
      }
    }
  }
}

TEST(MjcfRest, TheHumanoidsChangesAreNamedByBone) {
  const std::string path = std::string(outside::kSamplesDir) + "/humanoid/humanoid.xml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " missing";
  const MjcfRig mr = load_mjcf(path);
  const MjcfImportReport& rep = mr.report;
  // the knees' range leaves the rest angle outside it (2 deg past its end, on the shin's local
  // x): widened so that the torsion band (0.1 of the range) ends at rest, 160 x 0.1 / 0.9 deg
  EXPECT_EQ(rep.widened_limits,
            (std::vector<std::string>{"right_shin x: [-160, 2] -> [-160, 17.78] deg",
                                      "left_shin x: [-160, 2] -> [-160, 17.78] deg"}));
  // the feet's ankles are freed, and the report names them
  ASSERT_EQ(rep.freed_bones.size(), static_cast<std::size_t>(rep.unaligned_hinges));
  for (const std::string& f : rep.freed_bones) EXPECT_NE(f.find("_foot'"), std::string::npos) << f;
  // the capsules that overlap at rest are excluded, and listed in the rig's notes
  EXPECT_FALSE(rep.rest_overlaps.empty());
  EXPECT_EQ(mr.rig().collision_exclude.size(), rep.rest_overlaps.size());
  bool noted = false;
  for (const std::string& n : mr.rig().source) {
    noted =
        noted || n.rfind("collision_exclude: bone pairs whose capsules overlap at rest", 0) == 0;
  }
  EXPECT_TRUE(noted);
}

}  // namespace
}  // namespace physik
