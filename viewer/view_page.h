// `physik view` and physik.view(): run folders into one self-contained HTML page that plays
// them in 3D (viewer/viewer.js on three.js), with no network access.
//
// The page holds, inline: three.js and its OrbitControls, read at generation time from
// Debian's libjs-three (r111, /usr/share/javascript/three; PHYSIK_THREE_DIR overrides the
// folder, and the revision must be 111, the one the viewer is written for); viewer/viewer.js
// and viewer/page.html, compiled into the program; and the runs as JSON in a non-executable
// <script type="application/json"> element. Names come from user files, so the JSON has every
// '<', '>' and '&' escaped (\u003c ...): no name can close the element, and the page sets
// names with textContent, never as markup.
//
// Frame arrays travel as base64 of little-endian typed arrays (Float32 positions, targets,
// readouts, excess, orientations and contact values; Float64 times; Int32 steps, indices and each
// frame's first contact, run_reader.h ViewRun): a 100-bone, 10,000-frame run is 24 MB of positions,
// where decimal JSON would be about twice that and slower to parse. Each run's bones carry their
// lengths, rest frames in their parents' (quaternion x y z w) and limits per local axis (rad, null
// where free) for the axes and limit ranges the page draws. A run whose scene has a ground has
// "ground" (height, normal), one with box obstacles has "boxes" (name, center, half_extents,
// quaternion x y z w: scene.h BoxObstacle), one with orientation targets, aims or pins has
// "bone_targets" (orientations: bone, quaternion x y z w world<-bone; aims: bone, point; pins:
// bone, alpha, point; world, rig units), one with contacts.csv has "contacts"; other runs have
// none of these keys.
#pragma once

#include <string>
#include <vector>

#include "viewer/run_reader.h"

namespace physik::viewer {

struct ViewOptions {
  std::string title;                // "" = the runs' labels
  std::vector<std::string> labels;  // one per run, or empty for default_labels
  int max_frames = 10000;           // per run (run_reader.h decimation)
};

// three.js and OrbitControls as the page inlines them.
struct ThreeJs {
  std::string folder, revision, three, orbit_controls;
};

// From PHYSIK_THREE_DIR or Debian's folder; InputError naming the file when it is missing,
// of another revision, or holds text that would end a <script> element.
ThreeJs load_three_js();

// The page's data element content: the runs as JSON, '<', '>' and '&' escaped.
std::string view_data_json(const std::vector<ViewRun>& runs, const std::string& title);

// The whole page.
std::string view_page_html(const std::vector<ViewRun>& runs, const std::string& title,
                           const ThreeJs& three);

// Reads the folders (bad input: InputError naming the folder), checks the overlay and writes
// the page to `out` (created with its parent folders; "--out" names it in errors). Returns the
// page's size in bytes.
std::size_t write_view_page(const std::vector<std::string>& folders, const ViewOptions& options,
                            const std::string& out);

}  // namespace physik::viewer
