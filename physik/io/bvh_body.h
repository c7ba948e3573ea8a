// The body inside a converted BVH skeleton (`rig from-bvh --body`, bvh.h bvh_to_rig): a human's
// (physik/model/human_body.h) when the joint names say it is one (skeleton_names.h), else the
// generic rods of rig_sizing.h; and the welds a clip asks for (--weld-constant).
//
// Units of a human figure: its height H (file units, along the body's up axis, human_body.h)
// times the scale should be a human height in metres, 1.2 to 2.2. When it is not, the file's unit
// is guessed: the first of these whose H x unit lies in that band, the nearest to 1.76 m when two
// do (their bands overlap only between 21.3 and 22 file units):
//   metres 1, decimetres 0.1, CMU's unit 0.0564444 (1/0.45 inch: the CMU database's ASF files
//   say "length 0.45", inches per unit, and cgspeed's BVH conversion keeps the unit),
//   inches 0.0254, centimetres 0.01, millimetres 0.001
// and the warning names that --scale; where none fits, the --scale that makes the figure the
// reference adult's 1.76 m (human_template.h kReferenceHeight). --height H scales the figure to H
// metres instead (scale = H / height in file units; for a figure not recognised as human, its
// extent along the rig's Z).
// Axes: a human whose up axis after conversion is more than 45 deg from the rig's +Z lies down or
// stands on its head: the hint names the --axes that stands it up (the file axis nearest its up:
// Y -> y-up, Z -> z-up), or says that none does.
//
// --weld-constant: a joint (not the root) whose channels hold one value over the whole clip, at
// its rest (every rotation 0 within 1e-9 deg, every position its OFFSET), has its bone welded to
// the bone it hangs from (rig.h "Welds"): it can never turn, and the solvers get fewer
// coordinates. A joint constant away from its rest is not welded (a weld holds the rest shape,
// which the clip never shows): it is listed with its angle; so is a joint whose parent joint has
// no bone of its own (CMU's LThumb below LeftHand: the bone it would be welded to turns with
// another joint).
#pragma once

#include <string>
#include <vector>

#include "physik/io/skeleton_names.h"
#include "physik/model/human_body.h"
#include "physik/model/pivot_rig.h"

namespace physik {

struct BvhFile;
struct BvhImportOptions;

// Which body a converted skeleton gets.
enum class BodyKind {
  kGeneric,  // rods of rig_sizing.h, no limits (the library's default)
  kHuman,    // the human template; a skeleton whose names do not make a human is an InputError
  kAuto      // human when the names make one, else generic (`rig from-bvh`'s default)
};
const char* to_string(BodyKind body);

struct BvhBody {
  bool human = false;
  SkeletonMatch match;       // the joint names against the table (kGeneric: not matched)
  HumanBodyFit fit;          // the template as fitted (human only)
  double scale = 1.0;        // rig units per file unit, as used (--scale, or from --height)
  double height_file = 0.0;  // file units: along the body's up (human), else the rig's Z extent
  // the human unit rule's warning and the --scale it names (0: none), and the axes hint (empty:
  // the figure stands)
  std::string unit_warning;
  double suggested_scale = 0.0;
  std::string axes_hint;
  std::vector<std::string> welded_constant;      // --weld-constant: "LeftToeBase to LeftFoot"
  std::vector<std::string> constant_not_welded;  // constant away from rest, with its angles
};

// The names matched (or not), the scale (from --height), the human decision; InputError naming
// the option for --body human on a skeleton that is not one, --height not positive and finite,
// --height with --scale, --mass-per-length with a human body.
BvhBody plan_bvh_body(const BvhFile& bvh, const std::string& source,
                      const BvhImportOptions& options);

// --weld-constant's welds on `bones` (before the body is fitted, so welded bones get no limits).
void weld_constant_joints(const BvhFile& bvh, PivotBones& bones, BvhBody& body);

// The human template on `bones` (masses, inertias, limits, frames, welds, forward axes), its
// unit warning and axes hint. `nodes` at the final scale.
void fit_bvh_human(const std::vector<PivotNode>& nodes, const BvhImportOptions& options,
                   PivotBones& bones, BvhBody& body);

// A welded bone whose joint turns against the joint of the bone it is welded to in the clip (a
// welded pelvis joint that the file turns after all): one warning each, with the largest turn.
void weld_turn_warnings(const BvhFile& bvh, const PivotRig& pr, std::vector<std::string>& out);

// What the body is, as the rig's source notes say it (one line each).
std::vector<std::string> bvh_body_notes(const BvhBody& body);

}  // namespace physik
