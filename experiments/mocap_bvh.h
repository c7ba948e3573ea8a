// A motion-capture skeleton of the kind users bring: a BVH written here, not taken from
// anywhere (the outside_rigs experiment converts it, the tests of the BVH converter read it). A
// standing figure 183 cm tall (centimetres, Y up), whose root (Hips) has three children (Spine,
// LeftUpLeg, RightUpLeg) and whose Chest has three (Neck, LeftShoulder, RightShoulder), 19 joints,
// one frame at rest.
#pragma once

#include <string>

namespace physik::experiments {

inline std::string mocap_bvh() {
  const std::string rot = "CHANNELS 3 Zrotation Xrotation Yrotation\n";
  auto joint = [&](const std::string& name, const std::string& offset, const std::string& inner) {
    return "JOINT " + name + "\n{\nOFFSET " + offset + "\n" + rot + inner + "}\n";
  };
  auto end = [](const std::string& offset) { return "End Site\n{\nOFFSET " + offset + "\n}\n"; };
  auto arm = [&](const std::string& side, double sx) {
    const std::string s = sx > 0 ? "" : "-";
    return joint(side + "Shoulder", s + "4 20 0",
                 joint(side + "Arm", s + "14 0 0",
                       joint(side + "ForeArm", s + "28 0 0",
                             joint(side + "Hand", s + "26 0 0", end(s + "18 0 0")))));
  };
  auto leg = [&](const std::string& side, double sx) {
    const std::string s = sx > 0 ? "" : "-";
    return joint(side + "UpLeg", s + "9 -5 0",
                 joint(side + "Leg", "0 -42 0", joint(side + "Foot", "0 -42 0", end("0 -6 14"))));
  };
  const std::string spine =
      joint("Spine", "0 10 0",
            joint("Chest", "0 25 0",
                  joint("Neck", "0 25 0", joint("Head", "0 10 0", end("0 18 0"))) + arm("Left", 1) +
                      arm("Right", -1)));
  // the root's position channels hold it where its OFFSET puts it (95 cm up); every rotation 0
  std::string frame = "0 95 0";
  for (int c = 3; c < 6 + 18 * 3; ++c) frame += " 0";
  return "HIERARCHY\nROOT Hips\n{\nOFFSET 0 95 0\n"
         "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n" +
         spine + leg("Left", 1) + leg("Right", -1) +
         "}\nMOTION\nFrames: 1\nFrame Time: 0.0333333\n" + frame + "\n";
}

}  // namespace physik::experiments
