// A run folder (physik/io/run_folder.h) read for the viewer: the scene as run, the recorded
// frames (every bone's head and tail), the per-frame readouts, and, from
// targets_and_limits.csv, the control points' targets and each bone's joint-limit excess, and,
// from contacts.csv (physik/io/contacts_table.h) where the folder has one, each kept frame's
// contacts.
//
// Runs longer than `max_frames` rows are decimated to exactly max_frames rows, evenly spread:
//   kept row k = round(k (rows - 1) / (max_frames - 1)),  k = 0 .. max_frames - 1
// (the first and the last row among them); the page says so.
// The page holds floats: a kept frame whose value lies past the viewer's bounds (a coordinate of
// a bone, a target or a contact point beyond the rig's bound, rig.h kMaxCoordinate = 1e9; any
// other value beyond a float's range) would draw or read as Infinity. That frame and every later
// one are left out, and the page says where (file, line, column, value): a diverged run shows up
// to where it left the bounds. Where no frame comes before it, the folder is refused, naming the
// same. The page's arrays never hold a non-finite number.
// Bad input is an InputError naming the folder or the file and what is wrong: not a folder,
// no scene.json or trajectory.csv (not a run folder), an empty trajectory, a header that is not
// the scene's columns, a row with the wrong number of fields, a value that is not a finite
// number, a first frame past the bounds above, a contact of a bone the rig does not have, a kept
// step with no row in targets_and_limits.csv (a run folder's tables hold the same steps); and,
// for an overlay, runs whose rigs differ in their bones.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physik/model/scene.h"

namespace physik::viewer {

struct ViewRun {
  std::string folder;      // as given
  std::string label;       // the legend's name
  Scene scene;             // scene.json
  nlohmann::json summary;  // summary.json; null when the folder has none
  int rows_recorded = 0;   // rows of trajectory.csv (all kept unless more than max_frames)
  // per kept frame
  std::vector<int> steps;               // (nframe)
  std::vector<double> times;            // (nframe) s
  std::vector<float> kinetic_energy;    // (nframe) J
  std::vector<float> max_residual;      // (nframe) rig units, 0 without control points
  std::vector<int> max_residual_point;  // (nframe) its control point, -1 without any
  std::vector<float> positions;         // (nframe x nbone x 6) head x y z, tail x y z, world
  std::vector<float> targets;           // (nframe x ncontrol x 3) world, rig units
  std::vector<float> limit_excess;      // (nframe x nbone) largest |excess| over the axes,
                                        //   rad; empty when the folder has no table
  std::vector<float> orientations;      // (nframe x nbone x 4) world <- bone, quaternion x y z
                                        //   w; empty when the table has no orientations
  // contacts.csv's rows of the kept frames, frame by frame; all empty without the file
  bool has_contacts = false;          // the folder has contacts.csv
  std::vector<int> contact_start;     // (nframe + 1) frame f's contacts are [start[f], start[f+1])
  std::vector<int> contact_bones;     // (ncontact x 2) bone, other bone (-1: the ground)
  std::vector<float> contact_values;  // (ncontact x 8) point x y z (world, rig units), normal
                                      //   x y z (world, unit), depth (rig units), normal force (N)
  std::vector<std::string> notes;     // what the page should say about this run
};

// Reads one run folder; max_frames >= 2.
ViewRun read_run_folder(const std::string& folder, int max_frames);

// An overlay draws every run in one scene, frame against frame: the runs must have the same
// bones (names and parents, in order). InputError naming the first run that differs.
void check_overlay(const std::vector<ViewRun>& runs);

// Legend names: each folder's last path component, the whole folder where two would repeat.
std::vector<std::string> default_labels(const std::vector<std::string>& folders);

}  // namespace physik::viewer
