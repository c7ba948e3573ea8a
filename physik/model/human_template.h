// The human template: the segments a human skeleton is made of, with the published tables that
// give each its mass, inertia, joint kind and range of motion (human_body.h fits them to a
// converted skeleton; models/human/joint_names.json maps the joint names of the common motion
// capture conventions onto these segments; models/README.md "A human body").
//
// Segments (".L" / ".R" the body's left and right side):
//   pelvis, lumbar, thorax, neck, head, clavicle, upper_arm, forearm, hand, fingers, thigh,
//   shank, foot, toes
//
// Masses and inertias: de Leva, P. (1996). Adjustments to Zatsiorsky-Seluyanov's segment inertia
// parameters. J. Biomech. 29(9), 1223-1230, Table 4 (males). Per segment of the table (between
// its endpoints): its mass as a share of the body's, its centre of mass as a fraction of its
// length from the first endpoint, and its radii of gyration about the sagittal (antero-
// posterior), transverse (medio-lateral) and longitudinal axes as fractions of its length:
//                                   mass %   CM %    r_sag %  r_trans %  r_long %
//   head, vertex to C7 (cervicale)   6.94    50.02   30.3     31.5       26.1
//   upper trunk, C7 to xiphoid      15.96    50.66   50.5     32.0       46.5
//   middle trunk, xiphoid to navel  16.33    45.02   48.2     38.3       46.8
//   lower trunk, navel to hips      11.17    61.15   61.5     55.1       58.7
//   upper arm, shoulder to elbow     2.71    57.72   28.5     26.9       15.8
//   forearm, elbow to wrist          1.62    45.74   27.6     26.5       12.1
//   hand, wrist to 3rd knuckle       0.61    79.00   62.8     51.3       40.1
//   thigh, hip to knee              14.16    40.95   32.9     32.9       14.9
//   shank, knee to ankle             4.33    43.95   25.1     24.6       10.2
//   foot, heel to toe tip            1.37    44.15   25.7     24.5       12.4
// (the head and trunk rows measure their centre of mass from the upper endpoint.) The template's
// segments take them as: pelvis the lower trunk, lumbar the middle trunk, thorax and clavicles
// the upper trunk, neck and head the head, fingers the hand, toes the foot.
//
// Joint kinds and ranges: the normal ranges of motion of the American Academy of Orthopaedic
// Surgeons (Joint Motion: Method of Measuring and Recording, 1965; reprinted in Greene &
// Heckman, The Clinical Measurement of Joint Motion, AAOS 1994), in degrees:
//   thoracolumbar spine  flexion 80, extension 25, lateral bending 35, rotation 45
//   cervical spine       flexion 45, extension 45, lateral bending 45, rotation 60
//   shoulder             flexion 180, extension 60, abduction 180, internal rotation 70,
//                        external rotation 90 (adduction: 30, our choice; the table gives none)
//   elbow and forearm    flexion 150; pronation and supination 80 each (two axes: a skeleton's
//                        forearm bone carries the radius's turn about the ulna, along its own
//                        length, y; a hinge there held motion capture's forearms off their pose)
//   wrist                flexion 80, extension 70, radial deviation 20, ulnar deviation 30 (two
//                        axes)
//   fingers (MCP)        flexion 90, hyperextension 45 (abduction 20 each way, our choice)
//   hip                  flexion 120, extension 30, abduction 45, adduction 30, internal and
//                        external rotation 45
//   knee                 flexion 135 (a hinge)
//   ankle and hindfoot   plantar flexion 50, dorsiflexion 20, inversion 35, eversion 15 (two
//                        axes)
//   great toe (MTP)      flexion 45, extension 70 (a hinge)
//   clavicle             15 each way on every axis (our choice: "a small range")
// Spine and neck ranges belong to the whole region: its bones share them (each gets the range
// divided by the region's bone count).
//
// Frames (body axes F forward, L left, U up, found from the skeleton: human_body.h): every segment
// has an anatomical direction d0 (its bone's direction standing in the anatomical position: arms
// down, palms forward, feet forward) and a reference axis x0 across it; its bone frame in that
// position is x = x0, y = d0, z = x0 x d0. Left-side and central segments are tabled; a right
// one is the mirror image (d0, x0 reflected through the sagittal plane), under which a rotation
// vector's x and y components change sign and z keeps it, so its ranges are the left's with x
// and y negated. With x0 = L on the limbs, a positive turn about x moves a downward bone's tail
// backward (knee flexion, hip and shoulder extension) and a forward bone's tail down (plantar
// flexion); about z (= -F for a downward bone) it moves the tail toward the body's right.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "physik/model/types.h"

namespace physik {

// de Leva's segments (the rows of the table above)
enum class LevaSegment {
  kHead,
  kUpperTrunk,
  kMiddleTrunk,
  kLowerTrunk,
  kUpperArm,
  kForearm,
  kHand,
  kThigh,
  kShank,
  kFoot,
  kCount
};

struct LevaRow {
  const char* name;
  double mass_share;    // 1, of the body's mass
  double com;           // 1, of the segment's length from its lower (proximal) end
  double r_sagittal;    // 1, radius of gyration about the sagittal (lateral) axis, of the length
  double r_transverse;  // 1, about the transverse (antero-posterior) axis
  double r_long;        // 1, about the longitudinal axis
};
const LevaRow& leva_row(LevaSegment s);

// How a segment's joint to its parent moves
enum class JointKind {
  kRoot,    // the pelvis: the rig's root or welded to it
  kBall,    // three axes, each with its range
  kHinge,   // one axis (x), the other two locked
  kTwoAxis  // two axes (x and z, or x and y for the forearm and ankle), the third locked
};

// A body axis in the anatomical position, as a signed unit vector in (F, L, U) coordinates
using BodyDir = Vec3;

struct TemplateSegment {
  std::string name;  // "thigh.L", "pelvis"
  int side = 0;      // +1 left, -1 right, 0 central
  LevaSegment leva;  // the table row whose mass it shares
  JointKind kind;
  BodyDir d0;  // the bone's direction in the anatomical position
  BodyDir x0;  // the frame's x axis there, across d0
  std::array<std::array<double, 2>, 3> range_deg;  // per local x, y, z: [min, max], deg
  // the region whose range its bones share: "spine", "cervical" (empty: each bone its own)
  std::string shared_region;
  // the rest pose is not the anatomical one at this joint (a T-pose's shoulders, an A-pose's
  // hips): the ranges are offset by the rest's turn from the anatomical direction
  bool offset_by_rest = false;
};

// Every segment of the template: the central ones, then each left segment followed by its
// right mirror image.
const std::vector<TemplateSegment>& human_segments();
// Index into human_segments(), or -1.
int human_segment_index(const std::string& name);
// The segment names, in table order.
std::vector<std::string> human_segment_names();
// The segments a skeleton must have to be taken as human: the pelvis, both thighs, shanks, upper
// arms and forearms, and one of lumbar, thorax, neck or head.
bool human_core_complete(const std::vector<bool>& present, std::vector<std::string>& missing);

// A reference adult (ICRP Publication 89, 2002, the reference adult male): the default total mass
// of a human rig, and the height the unit rule aims at when no unit of length fits.
constexpr double kReferenceMass = 73.0;    // kg
constexpr double kReferenceHeight = 1.76;  // m
// The height band a human figure in metres falls in (rig units are read as metres).
constexpr double kHumanHeightMin = 1.2;  // m
constexpr double kHumanHeightMax = 2.2;  // m

// Segment lengths as fractions of the body's height (Drillis & Contini 1966, as drawn in Winter,
// Biomechanics and Motor Control of Human Movement, 4th ed., Fig. 4.1): a leg (hip to ankle)
// 0.491 H, an arm (shoulder to wrist) 0.332 H. A limb shorter than half or longer than 1.5 times
// its share is implausible for a figure of that height (a leg of 0.74 H leaves 0.26 H for the
// trunk, neck and head, whose share is 0.48 H).
constexpr double kLegShare = 0.491;  // 1, of the height
constexpr double kArmShare = 0.332;  // 1, of the height

}  // namespace physik
