// The human template's tables (human_template.h has their sources and conventions).
#include "physik/model/human_template.h"

#include <algorithm>
#include <utility>

namespace physik {

namespace {

// body axes in the anatomical position, (F, L, U) coordinates
const Vec3 kF(1, 0, 0), kL(0, 1, 0), kU(0, 0, 1);

// de Leva (1996) Table 4, males; the head and trunk rows' centres of mass turned to be measured
// from their lower end (the table measures them from the upper one)
const LevaRow kLeva[] = {
    {"head (with neck)", 0.0694, 1.0 - 0.5002, 0.303, 0.315, 0.261},
    {"upper trunk", 0.1596, 1.0 - 0.5066, 0.505, 0.320, 0.465},
    {"middle trunk", 0.1633, 1.0 - 0.4502, 0.482, 0.383, 0.468},
    {"lower trunk", 0.1117, 1.0 - 0.6115, 0.615, 0.551, 0.587},
    {"upper arm", 0.0271, 0.5772, 0.285, 0.269, 0.158},
    {"forearm", 0.0162, 0.4574, 0.276, 0.265, 0.121},
    {"hand", 0.0061, 0.7900, 0.628, 0.513, 0.401},
    {"thigh", 0.1416, 0.4095, 0.329, 0.329, 0.149},
    {"shank", 0.0433, 0.4395, 0.251, 0.246, 0.102},
    {"foot", 0.0137, 0.4415, 0.257, 0.245, 0.124},
};

using Range = std::array<std::array<double, 2>, 3>;
const Range kNoRange = {{{0, 0}, {0, 0}, {0, 0}}};

// a segment of the table: its name, side (+1 left, 0 central), row, kind, frame and ranges
TemplateSegment segment(std::string name, int side, LevaSegment leva, JointKind kind,
                        const Vec3& d0, const Vec3& x0, const Range& r) {
  TemplateSegment s;
  s.name = std::move(name);
  s.side = side;
  s.leva = leva;
  s.kind = kind;
  s.d0 = d0;
  s.x0 = x0;
  s.range_deg = r;
  return s;
}

TemplateSegment central(const char* name, LevaSegment leva, JointKind kind, const Range& r,
                        const char* region) {
  TemplateSegment s = segment(name, 0, leva, kind, kU, kL, r);
  s.shared_region = region;
  return s;
}

TemplateSegment left(const char* name, LevaSegment leva, JointKind kind, const Vec3& d0,
                     const Vec3& x0, const Range& r, bool offset_by_rest = false) {
  TemplateSegment s = segment(std::string(name) + ".L", 1, leva, kind, d0, x0, r);
  s.offset_by_rest = offset_by_rest;
  return s;
}

// the mirror image through the sagittal plane (L -> -L): directions reflect; a rotation vector's
// x and y components in the mirrored frame change sign, z keeps it (human_template.h "Frames")
TemplateSegment mirrored(const TemplateSegment& l) {
  TemplateSegment r = l;
  r.name = l.name.substr(0, l.name.size() - 2) + ".R";
  r.side = -1;
  r.d0.y() = -l.d0.y();
  r.x0.y() = -l.x0.y();
  for (int a = 0; a < 2; ++a)
    r.range_deg[a] = {0.0 - l.range_deg[a][1], 0.0 - l.range_deg[a][0]};  // 0 - x: no -0
  return r;
}

std::vector<TemplateSegment> make_segments() {
  using L = LevaSegment;
  using K = JointKind;
  // AAOS normal ranges (human_template.h), per local x, y, z of the left side
  const Range spine = {{{-25, 80}, {-45, 45}, {-35, 35}}};
  const Range cervical = {{{-45, 45}, {-60, 60}, {-45, 45}}};
  std::vector<TemplateSegment> out = {
      central("pelvis", L::kLowerTrunk, K::kRoot, kNoRange, ""),
      central("lumbar", L::kMiddleTrunk, K::kBall, spine, "spine"),
      central("thorax", L::kUpperTrunk, K::kBall, spine, "spine"),
      central("neck", L::kHead, K::kBall, cervical, "cervical"),
      central("head", L::kHead, K::kBall, cervical, "cervical"),
  };
  const std::vector<TemplateSegment> lefts = {
      left("clavicle", L::kUpperTrunk, K::kBall, kL, kU, {{{-15, 15}, {-15, 15}, {-15, 15}}}),
      left("upper_arm", L::kUpperArm, K::kBall, -kU, kL, {{{-180, 60}, {-90, 70}, {-180, 30}}},
           true),
      left("forearm", L::kForearm, K::kTwoAxis, -kU, kL, {{{-150, 0}, {-80, 80}, {0, 0}}}),
      left("hand", L::kHand, K::kTwoAxis, -kU, kL, {{{-80, 70}, {0, 0}, {-20, 30}}}),
      left("fingers", L::kHand, K::kTwoAxis, -kU, kL, {{{-90, 45}, {0, 0}, {-20, 20}}}),
      left("thigh", L::kThigh, K::kBall, -kU, kL, {{{-120, 30}, {-45, 45}, {-45, 30}}}, true),
      left("shank", L::kShank, K::kHinge, -kU, kL, {{{0, 135}, {0, 0}, {0, 0}}}),
      left("foot", L::kFoot, K::kTwoAxis, kF, kL, {{{-20, 50}, {-35, 15}, {0, 0}}}),
      left("toes", L::kFoot, K::kHinge, kF, kL, {{{-70, 45}, {0, 0}, {0, 0}}}),
  };
  for (const TemplateSegment& l : lefts) {
    out.push_back(l);
    out.push_back(mirrored(l));
  }
  return out;
}

}  // namespace

const LevaRow& leva_row(LevaSegment s) {
  return kLeva[static_cast<int>(s)];
}

const std::vector<TemplateSegment>& human_segments() {
  static const std::vector<TemplateSegment> segments = make_segments();
  return segments;
}

int human_segment_index(const std::string& name) {
  const auto& all = human_segments();
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<std::string> human_segment_names() {
  std::vector<std::string> names;
  for (const TemplateSegment& s : human_segments()) names.push_back(s.name);
  return names;
}

bool human_core_complete(const std::vector<bool>& present, std::vector<std::string>& missing) {
  missing.clear();
  const auto has = [&](const char* name) {
    const int i = human_segment_index(name);
    return i >= 0 && present[i];
  };
  for (const char* name : {"pelvis", "thigh.L", "thigh.R", "shank.L", "shank.R", "upper_arm.L",
                           "upper_arm.R", "forearm.L", "forearm.R"}) {
    if (!has(name)) missing.push_back(name);
  }
  if (!has("lumbar") && !has("thorax") && !has("neck") && !has("head")) {
    missing.push_back("lumbar, thorax, neck or head");
  }
  return missing.empty();
}

}  // namespace physik
