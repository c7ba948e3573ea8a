// The start check (physik/engine/start_contacts.h): a rod lying at height z over the floor, its
// collision radius r, overlaps it by d = r - z at both ends. Clear or just touching: nothing;
// past 5% of r: a warning naming the bone, depth and surface, the energy 2 k d^2 / 2 of its two
// ends; d = r (the rod's centre line on the floor): still a warning; past it: bad input. The same
// for a box; bones overlapping each other at the start are not checked.
#include "physik/engine/start_contacts.h"

#include <string>

#include <gtest/gtest.h>

#include "physik/model/errors.h"
#include "tests/contact_test_util.h"

namespace physik {
namespace {

constexpr double kRadius = 0.06;  // lying_rod's default collision radius, rig units

Scene rod_over_floor(double z) {
  return test::floor_scene(test::lying_rod(z), Scheme::kImplicit, 0.01);
}

TEST(StartContacts, ClearOrJustTouchingSaysNothing) {
  for (const double z : {1.0, kRadius, 0.99 * kRadius}) {
    const Scene s = rod_over_floor(z);
    EXPECT_EQ(check_start_contacts(s), "") << "z " << z;
  }
  EXPECT_EQ(deepest_start_contact(rod_over_floor(kRadius + 1e-3)).bone, -1);
}

TEST(StartContacts, IntoTheFloorWarnsWithTheDepthAndEnergy) {
  const Scene s = rod_over_floor(0.5 * kRadius);
  const StartContact c = deepest_start_contact(s);
  EXPECT_EQ(c.contacts, 2);  // both ends
  EXPECT_EQ(c.bone, 0);
  EXPECT_EQ(c.obstacle, -1);
  EXPECT_NEAR(c.depth, 0.5 * kRadius, 1e-12);
  EXPECT_NEAR(c.fraction, 0.5, 1e-12);
  EXPECT_NEAR(c.energy, 2 * 0.5 * s.params.contact_k * c.depth * c.depth, 1e-9);
  const std::string w = check_start_contacts(s);
  EXPECT_NE(w.find("bone 'rod' starts 0.03 rig units into the ground, 0.5 times its collision "
                   "radius 0.06"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("ground.height"), std::string::npos) << w;
}

TEST(StartContacts, CentreLineOnTheFloorWarnsAndPastItIsBadInput) {
  EXPECT_NE(check_start_contacts(rod_over_floor(0.0)), "");  // d = r: a warning
  try {
    check_start_contacts(rod_over_floor(-0.01));
    FAIL() << "a rod through the floor was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground: field 'height': bone 'rod' starts 0.07"),
              std::string::npos)
        << e.what();
  }
}

TEST(StartContacts, IntoABoxNamesTheBox) {
  Scene s = rod_over_floor(1.0);
  s.collision.ground.reset();
  BoxObstacle seat;
  seat.name = "seat";
  seat.center_world = Vec3(0.5, 0, 1.0 - 0.5 * kRadius - 0.5);  // its top 0.5 r above the axis
  seat.half_extents = Vec3(1, 1, 0.5);
  s.collision.obstacles.push_back(seat);
  const StartContact c = deepest_start_contact(s);
  EXPECT_EQ(c.obstacle, 0);
  EXPECT_NEAR(c.fraction, 0.5, 1e-9);
  EXPECT_NE(check_start_contacts(s).find("into obstacle 'seat'"), std::string::npos);
  s.collision.obstacles[0].center_world.z() = 1.0;  // the rod through the box
  EXPECT_THROW(check_start_contacts(s), InputError);
}

TEST(StartContacts, BonesOverlappingEachOtherAreNamedInAWarningNeverRefused) {
  // the U's post and leg 0.05 apart with radius 0.06: they overlap by 0.07, more than r
  Scene s = test::floor_scene(test::u_rig(0.05, 0.5, kRadius), Scheme::kImplicit, 0.01);
  s.collision.ground->height = -1.0;  // a ground, clear of the U
  s.collision.self_collision = true;
  EXPECT_EQ(deepest_start_contact(s).bone, -1);  // the surfaces' check: bones are not surfaces
  const std::string warning = check_start_contacts(s);
  EXPECT_EQ(warning.rfind("1 bone pair overlaps at the start under self_collision (depth in rig "
                          "units): [\"post\", \"leg\"] (0.07)",
                          0),
            0u)
      << warning;
  EXPECT_NE(warning.find("add the pairs to collision_exclude"), std::string::npos) << warning;
  // excluded by the scene (or the rig), or without self-collision: nothing to say
  s.collision.excluded_pairs = {{0, 2}};
  EXPECT_EQ(check_start_contacts(s), "");
  s.collision.excluded_pairs.clear();
  s.rig.collision_exclude = {{0, 2}};
  EXPECT_EQ(check_start_contacts(s), "");
  s.rig.collision_exclude.clear();
  s.collision.self_collision = false;
  EXPECT_EQ(check_start_contacts(s), "");
}

}  // namespace
}  // namespace physik
