#!/usr/bin/env bash
# The CLI's contract through the real binary: --help on every command, exit codes, error lines.
# usage: cli_test.sh PHYSIK_BINARY SOURCE_DIR
set -u
bin=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
check() {  # check NAME EXPECTED_STATUS CMD...
  local name=$1 want=$2; shift 2
  "$@" >"$tmp/out" 2>"$tmp/err"; local got=$?
  if [ "$got" -eq "$want" ]; then pass=$((pass+1)); else
    fail=$((fail+1)); echo "FAIL $name: exit $got, want $want"; cat "$tmp/err"; fi
}
expect_in() {  # expect_in NAME FILE TEXT
  if grep -qF -- "$3" "$2"; then pass=$((pass+1)); else fail=$((fail+1)); echo "FAIL $1: '$3' not in:"; cat "$2"; fi
}

check "help" 0 "$bin" --help
check "rig help" 0 "$bin" rig --help
check "rig info help" 0 "$bin" rig info --help
check "rig chain help" 0 "$bin" rig chain --help
check "no command" 2 "$bin"
check "unknown option" 2 "$bin" rig info "$src/models/rigs/pinhead.json" --bogus
# every command's --help ends with the exit statuses, an unexpected failure (1) among them
for cmd in "" rig "rig info" "rig chain" "rig tree" "rig from-bvh" "rig to-bvh" "rig limits" \
    "rig from-mjcf" bvh "bvh convert" experiment "experiment list" "experiment run" simulate \
    export-mjcf tune equilibrium solve params view follow; do
  check "help: physik $cmd" 0 "$bin" $cmd --help
  expect_in "help: physik $cmd lists the exit statuses" "$tmp/out" "Exit status: 0 success, 1 an unexpected failure, 2 bad input, 3 a diverged run"
done

check "rig info" 0 "$bin" rig info "$src/models/rigs/pinhead.json"
expect_in "rig info text" "$tmp/out" "bones: 18"
check "rig info json" 0 "$bin" rig info --json "$src/models/rigs/pinhead.json"
expect_in "rig info json bones" "$tmp/out" '"bones": 18'
expect_in "rig info json joints" "$tmp/out" '"joints": 14'
expect_in "rig info json max" "$tmp/out" '"max_bones_per_joint": 4'

check "chain" 0 "$bin" rig chain 5 --out "$tmp/c5.json"
check "chain info" 0 "$bin" rig info --json "$tmp/c5.json"
expect_in "chain bones" "$tmp/out" '"bones": 5'
check "chain zero" 2 "$bin" rig chain 0
check "rig tree help" 0 "$bin" rig tree --help
expect_in "rig tree help text" "$tmp/out" "--branching"
check "tree" 0 "$bin" rig tree 15 --branching 2 --out "$tmp/t15.json"
check "tree info" 0 "$bin" rig info --json "$tmp/t15.json"
expect_in "tree bones" "$tmp/out" '"bones": 15'
expect_in "tree joints" "$tmp/out" '"joints": 7'
check "tree zero branching" 2 "$bin" rig tree 5 --branching 0
expect_in "tree branching message" "$tmp/err" "branching"

printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,0]}]}' > "$tmp/zero.json"
check "zero-length bone" 2 "$bin" rig info "$tmp/zero.json"
expect_in "zero-length message" "$tmp/err" "zero.json: bones[0] 'a': field 'tail': zero-length"
check "missing file" 2 "$bin" rig info "$tmp/none.json"
expect_in "missing file message" "$tmp/err" "none.json: cannot open"

# simulate: success, bad scenes (exit 2), a diverged run (exit 3)
check "simulate help" 0 "$bin" simulate --help
check "simulate" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/sim" --steps 50 --quiet
# a run that ends short of convergence says what to try, as a divergence does (and exits 0)
expect_in "simulate short of convergence" "$tmp/err" "physik: not converged: $src/models/scenes/pinhead_two_hands.json: the run ended after 50 steps short of convergence; try more steps (--steps 100, twice this run's)"
expect_in "simulate short of convergence: the preset" "$tmp/err" "or --set preset=robust"
check "simulate short of convergence, robust" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --set preset=robust --out "$tmp/sim_robust" --steps 5 --quiet
expect_in "simulate short of convergence, robust: damping" "$tmp/err" "or a fixed damping in place of damping auto's choice"
# an old key keeps its meaning: joint_solve exact without integration is the exact scheme
printf '{"rig": "%s", "steps": 5, "params": {"joint_solve": "exact"}, "control_points": [{"bone": "forearm", "target": [0, 1, 3]}]}' "$src/models/rigs/elbow.json" > "$tmp/old_keys.json"
check "old key joint_solve exact" 0 "$bin" simulate "$tmp/old_keys.json" --out "$tmp/old_keys" --quiet
expect_in "old key joint_solve exact runs the exact scheme" "$tmp/old_keys/scene.json" '"scheme": "exact"'
expect_in "simulate summary" "$tmp/sim/summary.json" '"mean_passes_per_step"'
expect_in "simulate csv" "$tmp/sim/trajectory.csv" 'step,time,kinetic_energy,passes,joint_mismatch,joint_separation,residual_hand.L,residual_hand.R'
expect_in "simulate csv step 0" "$tmp/sim/trajectory.csv" $'\n0,0,0,0,0,0,'
expect_in "simulate scene.json has the rig inline" "$tmp/sim/scene.json" '"bones"'
check "simulate paper damping diverges" 3 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/div" --set damping=20 --quiet
expect_in "diverged message" "$tmp/err" "diverged"
expect_in "diverged summary" "$tmp/div/summary.json" '"diverged": true'
printf '{"rig": "%s/models/rigs/elbow.json", "control_points": [{"bone": "wrist", "target": [0,0,1]}]}' "$src" > "$tmp/s1.json"
check "simulate unknown bone" 2 "$bin" simulate "$tmp/s1.json" --out "$tmp/x"
expect_in "unknown bone message" "$tmp/err" "s1.json: control_points[0]: field 'bone': unknown bone 'wrist'"
printf '{"rig": "%s/models/rigs/elbow.json", "params": {"dt": -1}}' "$src" > "$tmp/s2.json"
check "simulate negative dt" 2 "$bin" simulate "$tmp/s2.json" --out "$tmp/x"
expect_in "negative dt message" "$tmp/err" "s2.json: params: field 'dt'"
printf '{"rig": "nowhere.json"}' > "$tmp/s3.json"
check "simulate missing rig" 2 "$bin" simulate "$tmp/s3.json" --out "$tmp/x"
check "simulate bad override" 2 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/x" --set nonsense=1
expect_in "bad override lists the keys" "$tmp/err" "--set: unknown parameter 'nonsense' (known: preset, dt, damping,"
check "simulate typo override" 2 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/x" --set dampng=1
expect_in "typo override suggests" "$tmp/err" "--set: unknown parameter 'dampng' (did you mean 'damping'?)"
check "simulate bad override value" 2 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/x" --set dt=abc
expect_in "bad override value message" "$tmp/err" "--set: params: field 'dt': expected a number, got 'abc'"
check "simulate override out of range" 2 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/x" --set torsion_tolerance=0.5
expect_in "override range message" "$tmp/err" "--set: params: field 'torsion_tolerance': must lie in [0, 0.5)"
check "simulate override each kind" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/kinds" --steps 5 --quiet \
  --set preset=paper --set damping=2.5 --set max_passes=40 --set centripetal=true --set torsion_spring=capped
expect_in "override each kind: preset" "$tmp/kinds/summary.json" '"preset": "paper"'
expect_in "override each kind: damping" "$tmp/kinds/summary.json" '"damping": 2.5'
expect_in "override each kind: scene's control_k on top of the preset" "$tmp/kinds/summary.json" '"control_k": 30.0'
expect_in "override each kind: max_passes" "$tmp/kinds/summary.json" '"max_passes": 40'
expect_in "override each kind: centripetal" "$tmp/kinds/summary.json" '"centripetal": true'
expect_in "override each kind: torsion_spring" "$tmp/kinds/summary.json" '"torsion_spring": "capped"'

# bone targets on the command line (cli/bone_target_options.cpp): in the run's scene.json as given,
# a pin without a point where its bone's head starts, an option replacing the file's target of
# that bone; each bad value exits 2 naming the option, the value, the field and the reason
pinhead_scene="$src/models/scenes/pinhead_two_hands.json"
check "simulate bone targets help" 0 "$bin" simulate --help
expect_in "simulate help: --orientation-target" "$tmp/out" "--orientation-target BONE=W,X,Y,Z"
expect_in "simulate help: --aim" "$tmp/out" "--aim BONE=X,Y,Z"
expect_in "simulate help: --pin" "$tmp/out" "--pin BONE[=X,Y,Z]"
check "solve help: --pin" 0 "$bin" solve --help
expect_in "solve help: --pin" "$tmp/out" "--pin BONE[=X,Y,Z]"
check "simulate bone targets" 0 "$bin" simulate "$pinhead_scene" --out "$tmp/bt" --quiet --set preset=robust --steps 1000 \
  --orientation-target forearm.L=0.7071068,0.7071068,0,0 --aim head=2,-3,2.5 --pin foot.R --pin hand.R=-1,-0.9,1.2 --pin hand.R
check "bone targets in scene.json" 0 python3 -c "
import json
d = json.load(open('$tmp/bt/scene.json'))
(o,) = d['orientation_targets']
assert o['bone'] == 'forearm.L' and max(abs(a - b) for a, b in zip(o['quaternion'], [0.7071068, 0.7071068, 0, 0])) < 1e-6, o
assert d['aim_targets'] == [{'bone': 'head', 'point': [2.0, -3.0, 2.5], 'axis': [0.0, 1.0, 0.0]}], d['aim_targets']
pins = {p['bone']: p['point'] for p in d['pins']}
assert sorted(pins) == ['foot.R', 'hand.R'], pins  # the second --pin hand.R replaced the first
assert max(abs(a - b) for a, b in zip(pins['foot.R'], [-0.4347, 0, -2.1169])) < 1e-9, pins
assert max(abs(a - b) for a, b in zip(pins['hand.R'], [-1.267, 0, -0.0311])) < 1e-9, pins
s = json.load(open('$tmp/bt/summary.json'))
assert not s['diverged'], s  # hand.R is pinned short of its control point's target
"
check "solve with a pin" 0 "$bin" solve "$pinhead_scene" --solver physik --out "$tmp/bt_solve" --quiet --pin forearm.L
check "a classic solver without pins refuses one" 2 "$bin" solve "$pinhead_scene" --solver fabrik --out "$tmp/bt_fabrik" --quiet --pin forearm.L
expect_in "classic refusal names pins" "$tmp/err" "pins: the fabrik solver does not support pins"
for bad in "--orientation-target|hand.L=2,0,0,0|--orientation-target: 'hand.L=2,0,0,0': field 'quaternion': not a unit quaternion (norm 2, more than 1e-3 from 1)" \
    "--orientation-target|hand.L=1.0011,0,0,0|field 'quaternion': not a unit quaternion (norm 1.0011, more than 1e-3 from 1)" \
    "--orientation-target|hand.L=0,0,0,0|field 'quaternion': zero quaternion" \
    "--orientation-target|hand.L=1,0,0|field 'quaternion': expected 4 numbers w,x,y,z, got 3" \
    "--orientation-target|hand.L=1,0,x,0|field 'quaternion': expected 4 numbers w,x,y,z, got '1,0,x,0'" \
    "--orientation-target|hand.L|--orientation-target: 'hand.L': expected BONE=w,x,y,z" \
    "--orientation-target|hand.X=1,0,0,0|field 'bone': unknown bone 'hand.X' (did you mean 'hand.L'?) in rig" \
    "--aim|hadn.L=0,-5,1|--aim: 'hadn.L=0,-5,1': field 'bone': unknown bone 'hadn.L' (did you mean 'hand.L'?)" \
    "--look-at|haed=0,-5,1|field 'bone': unknown bone 'haed' (did you mean 'head'?)" \
    "--aim|hand.L=1,2|--aim: 'hand.L=1,2': field 'point': expected 3 numbers x,y,z, got 2" \
    "--aim|hand.L=1.2266,0,-0.0109|rig units from the head of bone 'hand.L': an aim's point must be at least 0.1 of its bone's length (0.0287)" \
    "--aim|hand.L=1.22661,0,-0.0109|--aim: 'hand.L=1.22661,0,-0.0109': field 'point': lies 1e-05 rig units from the head of bone 'hand.L'" \
    "--pin|nope|--pin: 'nope': field 'bone': unknown bone 'nope'" \
    "--pin|foot.r|--pin: 'foot.r': field 'bone': unknown bone 'foot.r' (did you mean 'foot.R'?)" \
    "--pin|hand.L=1,2,3,4|field 'point': expected 3 numbers x,y,z, got 4" \
    "--pin|=1,2,3|field 'bone': no bone named before '='" \
    "--pin|hand.L=1e10,0,0|--pin: 'hand.L=1e10,0,0': field 'point': a coordinate beyond +-1e9" \
    "--aim|head=1e300,0,1|--aim: 'head=1e300,0,1': field 'point': a coordinate beyond +-1e9"; do
  IFS='|' read -r opt value message <<< "$bad"
  check "bad $opt $value" 2 "$bin" simulate "$pinhead_scene" --out "$tmp/bt_bad" --quiet "$opt" "$value"
  expect_in "bad $opt $value message" "$tmp/err" "$message"
done
# a quaternion as a person types it (norm 0.99999) is normalised, and said once naming the
# option, the value, the field and the norm; the same in a scene file
check "typed quaternion normalised" 0 "$bin" simulate "$pinhead_scene" --out "$tmp/bt_typed" --quiet --steps 2 --orientation-target hand.L=0.7071,0.7071,0,0
expect_in "typed quaternion warning" "$tmp/err" "physik: warning: --orientation-target: 'hand.L=0.7071,0.7071,0,0': field 'quaternion': norm 0.99999041 (within 1e-3 of 1): normalised to unit"
check "typed quaternion said once" 0 test "$(grep -c 'normalised to unit' "$tmp/err")" -eq 1
python3 -c "
import json
d = json.load(open('$pinhead_scene'))
d['rig'] = '$src/models/rigs/pinhead.json'
d['orientation_targets'] = [{'bone': 'hand.R', 'quaternion': [0.7071, 0, 0.7071, 0]}]
json.dump(d, open('$tmp/typed_q.json', 'w'))
"
check "typed quaternion in a scene" 0 "$bin" simulate "$tmp/typed_q.json" --out "$tmp/bt_typed2" --quiet --steps 2
expect_in "typed quaternion in a scene: warning" "$tmp/err" "physik: warning: $tmp/typed_q.json: orientation_targets[0]: field 'quaternion': norm 0.99999041 (within 1e-3 of 1): normalised to unit"
check "typed quaternion in a scene: solve warns too" 0 "$bin" solve "$tmp/typed_q.json" --solver physik --out "$tmp/bt_typed3" --quiet
expect_in "typed quaternion in a scene: solve's warning" "$tmp/err" "orientation_targets[0]: field 'quaternion': norm 0.99999041"
# an aim axis whose squared norm overflows is a direction (+X here), not zero: the aim turns
python3 -c "
import json
d = json.load(open('$pinhead_scene'))
d['rig'] = '$src/models/rigs/pinhead.json'
d['aim_targets'] = [{'bone': 'head', 'point': [2, -3, 2.5], 'axis': [1e155, 0, 0]}]
json.dump(d, open('$tmp/big_axis.json', 'w'))
"
check "aim axis 1e155" 0 "$bin" simulate "$tmp/big_axis.json" --out "$tmp/bt_axis" --quiet --steps 2 --set preset=robust
check "aim axis 1e155: normalised in the run's scene" 0 python3 -c "
import json
a = json.load(open('$tmp/bt_axis/scene.json'))['aim_targets'][0]['axis']
assert a == [1.0, 0.0, 0.0], a
s = json.load(open('$tmp/bt_axis/summary.json'))
assert s['aim_residuals_rad'][0] > 0.1, s['aim_residuals_rad']  # it has a direction to turn
"
check "aim axis 1e155: view reads the run" 0 "$bin" view "$tmp/bt_axis" --out "$tmp/bt_axis.html"
# the pose-terms step reads the bone targets too (forces.h pose_forces)
check "bone targets under full linearisation" 0 "$bin" simulate "$pinhead_scene" --set scheme=implicit --set implicit_linearisation=full --out "$tmp/bt_full" --quiet --pin hand.L --orientation-target hand.R=1,0,0,0 --aim head=0,-5,1.5
expect_in "full linearisation's pin in its scene" "$tmp/bt_full/scene.json" '"pins"'

# contacts and gravity: each bad value exits 2 naming its field
rig="$src/models/rigs/elbow.json"
bad_contact() {  # bad_contact NAME JSON_FIELDS EXPECTED_TEXT
  printf '{"rig": "%s", %s}' "$rig" "$2" > "$tmp/c.json"
  check "contacts: $1" 2 "$bin" simulate "$tmp/c.json" --out "$tmp/x" --quiet
  expect_in "contacts: $1 message" "$tmp/err" "$3"
}
bad_contact "zero normal" '"ground": {"height": 0, "normal": [0, 0, 0]}' "c.json: ground: field 'normal': zero length"
bad_contact "gravity not a vector" '"gravity": [0, 0]' "c.json: field 'gravity': expected an array of 3 numbers"
bad_contact "gravity beyond range" '"gravity": [0, 0, 1e300]' "c.json: field 'gravity': a coordinate beyond +-1e9"
bad_contact "gravity not a number" '"gravity": [0, "x", 0]' "c.json: field 'gravity[1]': expected a number"
bad_contact "unknown bone excluded" '"self_collision": true, "collision_exclude": [["upper_arm", "wrist"]]' "c.json: field 'collision_exclude[0]': unknown bone 'wrist'"
bad_contact "negative stiffness" '"ground": {"height": 0}, "params": {"contact_k": -1}' "c.json: params: field 'contact_k'"
bad_contact "contact params without contacts" '"params": {"contact_k": 100}' "c.json: params: field 'contact_k': applies only to a scene with a ground"
bad_contact "obstacles not a list" '"obstacles": {"name": "seat"}' "c.json: field 'obstacles': expected an array"
bad_contact "obstacle without a name" '"obstacles": [{"box": {"center": [0, 0, 0], "half_extents": [1, 1, 1]}}]' "c.json: obstacles[0]: field 'name': missing required field"
bad_contact "obstacle of an unknown shape" '"obstacles": [{"name": "seat", "cone": {}}]' "c.json: obstacles[0]: field 'cone': unknown shape"
bad_contact "obstacle without extents" '"obstacles": [{"name": "seat", "box": {"center": [0, 0, 0]}}]' "c.json: obstacles[0] box: field 'half_extents': missing required field"
bad_contact "obstacle with a negative extent" '"obstacles": [{"name": "seat", "box": {"center": [0, 0, 0], "half_extents": [1, -0.5, 1]}}]' "c.json: obstacles[0] box: field 'half_extents': each must be positive"
bad_contact "obstacle with an extent beyond range" '"obstacles": [{"name": "seat", "box": {"center": [0, 0, 0], "half_extents": [1, 1e300, 1]}}]' "c.json: obstacles[0] box: field 'half_extents': a coordinate beyond"
bad_contact "duplicate obstacle" '"obstacles": [{"name": "seat", "box": {"center": [0, 0, 0], "half_extents": [1, 1, 1]}}, {"name": "seat", "box": {"center": [0, 3, 0], "half_extents": [1, 1, 1]}}]' "c.json: obstacles[1]: field 'name': duplicate obstacle name 'seat'"
# a control character in any name a file carries is refused before it reaches MuJoCo (whose parser
# rejected the MJCF: exit 1, "internal error"), naming the file and the field
bad_contact "obstacle name with a NUL" '"obstacles": [{"name": "o\u0000", "box": {"center": [0, 0, -1.5], "half_extents": [1, 1, 0.5]}}]' "c.json: obstacles[0]: field 'name': control character 0x00 at offset 1"
printf '{"rig": "%s", "obstacles": [{"name": "o\\u0000", "box": {"center": [0, 0, -1.5], "half_extents": [1, 1, 0.5]}}]}' "$rig" > "$tmp/nul_obstacle.json"
check "names: export-mjcf refuses a NUL obstacle" 2 "$bin" export-mjcf "$rig" --contacts "$tmp/nul_obstacle.json" --out "$tmp/nul.xml"
expect_in "names: export-mjcf names the field" "$tmp/err" "nul_obstacle.json: obstacles[0]: field 'name': control character 0x00"
check "names: simulate --reference refuses it first" 2 "$bin" simulate "$tmp/nul_obstacle.json" --reference mujoco --out "$tmp/nul_ref" --quiet
[ ! -e "$tmp/nul_ref/trajectory.csv" ] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL names: a run was written before the refusal"; }
printf '{"name": "r\\u0000", "bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]}]}' > "$tmp/nul_rig.json"
check "names: a rig name with a NUL" 2 "$bin" export-mjcf "$tmp/nul_rig.json"
expect_in "names: the rig's name field" "$tmp/err" "nul_rig.json: field 'name': control character 0x00 at offset 1"
# names the readers accept come back from MuJoCo's parser: its own "world", the ground's name,
# markup and an XML comment's end, in a rig and a scene with a ground and a box
printf '{"name": "r--><", "bones": [{"name": "world", "parent": null, "head": [0,0,0.5], "tail": [0,0,1.5]}, {"name": "ground", "parent": "world", "head": [0,0,1.5], "tail": [0,0,2.5]}, {"name": "a\\"<&>--", "parent": "ground", "head": [0,0,2.5], "tail": [0,0,3.5]}]}' > "$tmp/hostile_rig.json"
printf '{"rig": "hostile_rig.json", "ground": {}, "self_collision": true, "obstacles": [{"name": "ground", "box": {"center": [3, 0, 0.5], "half_extents": [0.5, 0.5, 0.5]}}]}' > "$tmp/hostile_scene.json"
check "names: hostile names export" 0 "$bin" export-mjcf "$tmp/hostile_rig.json" --contacts "$tmp/hostile_scene.json" --out "$tmp/hostile.xml"
expect_in "names: a bone named world is renamed" "$tmp/hostile.xml" '<body name="world_2"'
expect_in "names: the ground geom steps aside" "$tmp/hostile.xml" '<geom name="ground_2" type="plane"'
check "names: hostile names run in MuJoCo" 0 "$bin" simulate "$tmp/hostile_scene.json" --steps 3 --reference mujoco --out "$tmp/hostile_run" --quiet
printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1], "collision_radius": -0.1}]}' > "$tmp/negr.json"
printf '{"rig": "%s", "ground": {"height": 0}}' "$tmp/negr.json" > "$tmp/c.json"
check "contacts: negative radius" 2 "$bin" simulate "$tmp/c.json" --out "$tmp/x" --quiet
expect_in "contacts: negative radius message" "$tmp/err" "negr.json: bones[0] 'a': field 'collision_radius': must be positive"
printf '{"defaults": {"collision_radius": -1}, "bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]}]}' > "$tmp/negd.json"
check "contacts: negative default radius" 2 "$bin" rig info "$tmp/negd.json"
expect_in "contacts: negative default radius message" "$tmp/err" "negd.json: defaults: field 'collision_radius': must be positive"
printf '{"rig": "%s", "ground": {"height": -1}, "gravity": [0, 0, -9.81], "params": {"dt": 0.01}}' "$rig" > "$tmp/drop.json"
check "contacts: a drop runs" 0 "$bin" simulate "$tmp/drop.json" --out "$tmp/drop" --steps 20 --quiet
expect_in "contacts: the scene keeps its ground" "$tmp/drop/scene.json" '"ground"'
printf '{"rig": "%s", "obstacles": [{"name": "seat", "box": {"center": [0, 0, -1.5], "half_extents": [1, 1, 0.5]}}], "gravity": [0, 0, -9.81], "params": {"dt": 0.01}}' "$rig" > "$tmp/seat.json"
check "contacts: a drop on a box runs" 0 "$bin" simulate "$tmp/seat.json" --out "$tmp/seat" --steps 20 --quiet
expect_in "contacts: the scene keeps its obstacle" "$tmp/seat/scene.json" '"obstacles"'
expect_absent() {  # expect_absent NAME FILE TEXT
  if grep -qF -- "$3" "$2"; then fail=$((fail+1)); echo "FAIL $1: '$3' in:"; cat "$2"; else pass=$((pass+1)); fi
}
# a rig that starts into the ground or a box: a warning past 5% of the bone's collision radius,
# exit 2 past the whole radius (physik/engine/start_contacts.h); the elbow's upper_arm runs from
# z = 0 up, its collision radius 0.12 (0.06 of its length 2), so a ground at height h sinks its
# lower end by 0.12 + h
start_scene() {  # start_scene FILE JSON_FIELDS
  printf '{"rig": "%s", %s, "gravity": [0, 0, -9.81], "params": {"dt": 0.01}}' "$rig" "$2" > "$1"
}
start_scene "$tmp/touch.json" '"ground": {"height": -0.119}'
check "start: just touching runs" 0 "$bin" simulate "$tmp/touch.json" --out "$tmp/touch" --steps 5 --quiet
expect_absent "start: just touching does not warn" "$tmp/err" "warning"
start_scene "$tmp/sunk.json" '"ground": {"height": -0.06}'
check "start: into the ground runs" 0 "$bin" simulate "$tmp/sunk.json" --out "$tmp/sunk" --steps 5 --quiet
expect_in "start: into the ground warns" "$tmp/err" "physik: warning: $tmp/sunk.json: bone 'upper_arm' starts 0.06 rig units into the ground, 0.5 times its collision radius 0.12"
expect_in "start: the warning says what to change" "$tmp/err" "raise the rig (initial_pose.root_head) or lower the ground (ground.height)"
start_scene "$tmp/below.json" '"ground": {"height": 0}, "initial_pose": {"root_head": [0, 0, -100]}'
check "start: below the ground is bad input" 2 "$bin" simulate "$tmp/below.json" --out "$tmp/below" --quiet
expect_in "start: below the ground names the field" "$tmp/err" "below.json: ground: field 'height': bone 'upper_arm' starts 100 rig units into the ground, 834 times its collision radius 0.12: its centre line is past the surface"
[ ! -e "$tmp/below" ] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL start: below the ground wrote a run folder"; }
start_scene "$tmp/below_cp.json" '"ground": {"height": 0}, "initial_pose": {"root_head": [0, 0, -100]}, "control_points": [{"bone": "forearm", "alpha": 1, "target": [0, 1, -97]}]'
check "start: the solve mode refuses it too" 2 "$bin" solve "$tmp/below_cp.json" --solver physik --out "$tmp/below" --quiet
expect_in "start: the solve mode names the field" "$tmp/err" "below_cp.json: ground: field 'height'"
# tune runs the scene from its start too: the same warning, the same refusal before any run
start_scene "$tmp/sunk_cp.json" '"ground": {"height": -0.06}, "control_points": [{"bone": "forearm", "alpha": 1, "target": [0, 1, 3]}]'
# (5 steps cannot converge: exit 4, the tuned values written all the same)
check "start: tune into the ground runs" 4 "$bin" tune "$tmp/sunk_cp.json" --steps 5 --scan-points 0 --max-iterations 1 --quiet
expect_in "start: tune warns" "$tmp/err" "physik: warning: $tmp/sunk_cp.json: bone 'upper_arm' starts 0.06 rig units into the ground"
check "start: tune refuses a start below the ground" 2 "$bin" tune "$tmp/below_cp.json" --steps 5 --scan-points 0 --quiet
expect_in "start: tune names the field" "$tmp/err" "below_cp.json: ground: field 'height'"
start_scene "$tmp/inbox.json" '"obstacles": [{"name": "seat", "box": {"center": [0, 0, -0.56], "half_extents": [1, 1, 0.5]}}]'
check "start: into a box runs" 0 "$bin" simulate "$tmp/inbox.json" --out "$tmp/inbox" --steps 5 --quiet
expect_in "start: into a box warns" "$tmp/err" "bone 'upper_arm' starts 0.06 rig units into obstacle 'seat'"
start_scene "$tmp/thrubox.json" '"obstacles": [{"name": "seat", "box": {"center": [0, 0, 0], "half_extents": [1, 1, 0.5]}}]'
check "start: through a box is bad input" 2 "$bin" simulate "$tmp/thrubox.json" --out "$tmp/x" --quiet
expect_in "start: through a box names it" "$tmp/err" "thrubox.json: obstacles[0]: field 'box': bone 'upper_arm' starts"
# no shipped scene starts into anything
for scene in "$src"/models/scenes/*.json; do
  check "start: $(basename "$scene") runs" 0 "$bin" simulate "$scene" --out "$tmp/shipped" --steps 1 --quiet
  expect_absent "start: $(basename "$scene") does not warn of its start" "$tmp/err" "rig units into"
done
# a solver that knows only the rig refuses a scene with contacts or gravity rather than ignore them
printf '{"rig": "%s", "ground": {"height": -3}, "gravity": [0, 0, -9.81], "control_points": [{"bone": "hand.L", "alpha": 1, "target": [0, 0, 1]}]}' "$src/models/rigs/pinhead.json" > "$tmp/floor_cp.json"
check "contacts: dls refuses a ground" 2 "$bin" solve "$tmp/floor_cp.json" --solver dls --out "$tmp/x" --quiet
expect_in "contacts: dls refusal names the field" "$tmp/err" "floor_cp.json: ground: the dls solver does not read it"
check "contacts: a classic finish refuses a ground" 2 "$bin" solve "$tmp/floor_cp.json" --solver physik --finish dls --out "$tmp/x" --quiet
expect_in "contacts: finish refusal names the field" "$tmp/err" "the dls finish does not read it"
# ... and bone targets: dls and jt take an orientation and a pin (orientation rows, a position
# goal); an aim, and every bone target for the other classic solvers, is refused by name
for target in '"orientation_targets": [{"bone": "hand.L", "quaternion": [1, 0, 0, 0]}]' \
              '"aim_targets": [{"bone": "head", "point": [0, -3, 2]}]' \
              '"pins": [{"bone": "hand.R"}]'; do
  field=${target%%\":*}; field=${field#\"}
  words=$(echo "$field" | tr _ ' ')
  printf '{"rig": "%s", %s, "control_points": [{"bone": "hand.L", "alpha": 1, "target": [0, 0, 1]}]}' "$src/models/rigs/pinhead.json" "$target" > "$tmp/targets_cp.json"
  for solver in fabrik ccd mass-spring rotation; do
    check "targets: $solver refuses $field" 2 "$bin" solve "$tmp/targets_cp.json" --solver $solver --out "$tmp/x" --quiet
    expect_in "targets: $solver refusal names $field" "$tmp/err" "targets_cp.json: $field: the $solver solver does not support $words"
  done
  check "targets: a classic finish refuses $field" 2 "$bin" solve "$tmp/targets_cp.json" --solver physik --finish dls --out "$tmp/x" --quiet
  expect_in "targets: finish refusal names $field" "$tmp/err" "targets_cp.json: $field: the dls finish does not support $words"
  check "targets: the solve mode takes $field" 0 "$bin" simulate "$tmp/targets_cp.json" --out "$tmp/x" --steps 20 --quiet
done
printf '{"rig": "%s", "aim_targets": [{"bone": "head", "point": [0, -3, 2]}], "control_points": [{"bone": "hand.L", "alpha": 1, "target": [0, 0, 1]}]}' "$src/models/rigs/pinhead.json" > "$tmp/aim_cp.json"
check "targets: dls refuses aim_targets" 2 "$bin" solve "$tmp/aim_cp.json" --solver dls --out "$tmp/x" --quiet
expect_in "targets: dls refusal names aim_targets" "$tmp/err" "aim_cp.json: aim_targets: the dls solver does not support aim targets"
# dls and jt reach a control point, a pin and an orientation target together (the hand's frame
# turned a quarter turn about x: the quaternion (cos 45, sin 45, 0, 0))
printf '{"rig": "%s", "pins": [{"bone": "hand.R"}], "orientation_targets": [{"bone": "hand.L", "quaternion": [0.7071067811865476, 0.7071067811865476, 0, 0]}], "control_points": [{"bone": "hand.L", "alpha": 1, "target": [0.5, -0.3, 1.2]}]}' "$src/models/rigs/pinhead.json" > "$tmp/ori_cp.json"
for solver in dls jt; do
  check "targets: $solver takes an orientation and a pin" 0 "$bin" solve "$tmp/ori_cp.json" --solver $solver --max-iterations 5000 --out "$tmp/x" --quiet
  expect_in "targets: $solver reports the orientation residual" "$tmp/x/summary.json" '"orientation_residual_rad"'
  expect_in "targets: $solver reports the pin's residual" "$tmp/x/summary.json" '"pin_residuals"'
done
# (it runs: under gravity the hand stops short of its target, so it exits 4, not converged)
check "contacts: the solve mode takes a ground" 4 "$bin" solve "$tmp/floor_cp.json" --solver physik --out "$tmp/x" --quiet
expect_in "contacts: the solve mode ran" "$tmp/x/summary.json" '"solver": "physik"'
printf '{"rig": "%s", "gravity": [0, 0, -9.81], "control_points": [{"bone": "hand.L", "alpha": 1, "target": [0, 0, 1]}]}' "$src/models/rigs/pinhead.json" > "$tmp/grav_cp.json"
check "contacts: equilibrium refuses gravity" 2 "$bin" equilibrium "$tmp/grav_cp.json" --out "$tmp/eq.json"
expect_in "contacts: equilibrium refusal names the field" "$tmp/err" "grav_cp.json: gravity: the exact equilibrium has the control and torsion springs' potential only"

# params: the parameter table, for people and for the report
check "params help" 0 "$bin" params --help
check "params" 0 "$bin" params
expect_in "params text" "$tmp/out" "angular_velocity_factor"
check "params json" 0 "$bin" params --json
expect_in "params json damping" "$tmp/out" '"name": "damping"'
mkdir -p "$tmp/report" && cp "$tmp/out" "$tmp/report/params.json"
check "params paper" 0 "$bin" params --json --preset paper
expect_in "params paper damping" "$tmp/out" '"damping": 20.0'
check "params bad preset" 2 "$bin" params --preset fast
expect_in "params bad preset message" "$tmp/err" "unknown preset 'fast'"
check "report from the table" 0 /usr/bin/python3 "$src/analysis/report.py" "$tmp/report"
expect_in "report settings row" "$tmp/report/REPORT.md" "| \`damping\` | 20 N s/m | 3 N s/m (the original code's) |"

# MuJoCo reference: export-mjcf prints MJCF that MuJoCo's own tools load; simulate --reference
check "export-mjcf help" 0 "$bin" export-mjcf --help
check "export-mjcf" 0 "$bin" export-mjcf "$src/models/rigs/pinhead.json" --out "$tmp/pinhead.xml"
expect_in "export-mjcf free root" "$tmp/pinhead.xml" 'type="free"'
if command -v mujoco-compile >/dev/null; then
  check "mujoco-compile loads it" 0 mujoco-compile "$tmp/pinhead.xml" "$tmp/pinhead.mjb"
fi
# a 150-bone chain is too deep for one MJCF file: include files beside --out; stdout refuses
check "chain 150" 0 "$bin" rig chain 150 --out "$tmp/c150.json"
check "export-mjcf deep" 0 "$bin" export-mjcf "$tmp/c150.json" --joints ball --out "$tmp/c150.xml"
expect_in "export-mjcf include" "$tmp/c150.xml" '<include file="c150.part1.xml"/>'
expect_in "export-mjcf part" "$tmp/c150.part1.xml" '<mujocoinclude>'
expect_in "export-mjcf part2" "$tmp/c150.part2.xml" '<body name="b128"'
if command -v mujoco-compile >/dev/null; then
  check "mujoco-compile loads the deep chain" 0 mujoco-compile "$tmp/c150.xml" "$tmp/c150.mjb"
fi
check "export-mjcf deep to stdout" 2 "$bin" export-mjcf "$tmp/c150.json"
expect_in "export-mjcf deep message" "$tmp/err" "give --out FILE"
check "export-mjcf bad rig" 2 "$bin" export-mjcf "$tmp/zero.json"
check "export-mjcf bad joints" 2 "$bin" export-mjcf "$src/models/rigs/pinhead.json" --joints hinges
# the exact and implicit schemes' same-forces joints: pinhead's elbows and knees one hinge, its
# torso two (a universal joint), its hips and collarbones none (welds by locks)
check "export-mjcf hinge joints" 0 "$bin" export-mjcf "$src/models/rigs/pinhead.json" --joints hinge --out "$tmp/pinhead_hinge.xml"
expect_in "export-mjcf hinge elbow" "$tmp/pinhead_hinge.xml" '<joint name="forearm.L:z" type="hinge"'
expect_in "export-mjcf hinge torso" "$tmp/pinhead_hinge.xml" '<joint name="torso:z" type="hinge"'
check "simulate bad reference" 2 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --reference bullet --out "$tmp/ref"
check "simulate reference" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --steps 20 --quiet --reference mujoco:exact-constraints --out "$tmp/ref"
expect_in "comparison.json" "$tmp/ref/comparison.json" '"final_pose_gap"'
expect_in "mujoco csv header" "$tmp/ref/mujoco/trajectory.csv" "step,time,kinetic_energy,passes,joint_mismatch,joint_separation,residual_"
expect_in "mujoco run folder" "$tmp/ref/mujoco/summary.json" '"mode": "exact-constraints"'
expect_in "mujoco run folder scene" "$tmp/ref/mujoco/scene.json" '"bones"'
# a run into the folder of an earlier one leaves none of the earlier run's files; the user's stay
check "simulate reference into a folder" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --steps 20 --quiet --reference mujoco --out "$tmp/rerun"
echo "my notes" > "$tmp/rerun/notes.txt"
echo "mine" > "$tmp/rerun/mujoco/mine.txt"
check "rerun without a reference" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --steps 20 --quiet --out "$tmp/rerun"
[ ! -e "$tmp/rerun/comparison.json" ] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL rerun kept comparison.json"; }
[ ! -e "$tmp/rerun/mujoco/summary.json" ] && [ ! -e "$tmp/rerun/mujoco/trajectory.csv" ] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL rerun kept the mujoco run"; ls -R "$tmp/rerun"; }
expect_in "rerun keeps the user's file" "$tmp/rerun/notes.txt" "my notes"
expect_in "rerun keeps the user's file in mujoco/" "$tmp/rerun/mujoco/mine.txt" "mine"
expect_in "rerun writes its own run" "$tmp/rerun/summary.json" '"mean_passes_per_step"'
check "simulate reference again" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --steps 20 --quiet --reference mujoco --out "$tmp/ref2"
check "rerun without a reference (clean folder)" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --steps 20 --quiet --out "$tmp/ref2"
[ ! -e "$tmp/ref2/mujoco" ] && [ ! -e "$tmp/ref2/comparison.json" ] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL rerun kept mujoco/ or comparison.json"; ls -R "$tmp/ref2"; }
# a folder that is not a run folder (no summary.json) loses nothing
mkdir -p "$tmp/notrun" && echo '{"mine": 1}' > "$tmp/notrun/comparison.json"
check "run into a folder that is not a run folder" 0 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --steps 5 --quiet --out "$tmp/notrun"
expect_in "a foreign comparison.json stays" "$tmp/notrun/comparison.json" '"mine"'
expect_in "mujoco targets and limits" "$tmp/ref/mujoco/targets_and_limits.csv" "step,"
# MuJoCo's warnings make its run not comparable: a bundle of 40 bones zig-zagging over one
# segment, every pair that shares no joint overlapping, has more contacts than the export sizes
# MuJoCo's buffers for (mjcf_export.h mjcf_size): exit 3 naming the warning, no dt hint
python3 - "$tmp/bundle.json" <<'PY'
import json, sys
bones = [{"name": "b%d" % i, "parent": "b%d" % (i - 1) if i else None,
          "head": [i % 2, 0.002 * i, 0.06], "tail": [(i + 1) % 2, 0.002 * (i + 1), 0.06]}
         for i in range(40)]
json.dump({"rig": {"name": "bundle", "bones": bones}, "steps": 3, "ground": {},
           "self_collision": True}, open(sys.argv[1], "w"))
PY
check "reference: a full contact list" 3 "$bin" simulate "$tmp/bundle.json" --reference mujoco --out "$tmp/bundle" --quiet
expect_in "reference: the warning named" "$tmp/err" "MuJoCo raised mjWARN_CONTACTFULL (its contact list (nconmax "
expect_in "reference: the buffers, not the step" "$tmp/err" "compare a scene with fewer bones in contact"
expect_absent "reference: no dt hint for a full buffer" "$tmp/err" "--set dt="
# tune --objective mujoco refuses a reference that diverged (the README's humanoid reach at dt 0.2:
# MuJoCo's Euler step on its hinges diverges at step 19; at the scene's 0.05 it is stable since the
# export writes the engine's hinges), with the dt hint, where it tuned against those steps
if [ -f /usr/share/mujoco/model/humanoid/humanoid.xml ]; then
  check "humanoid rig" 0 "$bin" rig from-mjcf /usr/share/mujoco/model/humanoid/humanoid.xml --out "$tmp/humanoid.json"
  printf '{"rig": "humanoid.json", "steps": 400, "control_points": [{"bone": "right_hand", "target": [0.3, -0.5, 1.9]}, {"bone": "left_foot", "target": [0.16, 0.13, 0.24]}, {"bone": "right_foot", "target": [0.16, -0.13, 0.24]}], "params": {"dt": 0.2}}' > "$tmp/reach.json"
  check "tune against a diverged MuJoCo reference" 3 "$bin" tune "$tmp/reach.json" --objective mujoco --scan-points 3 --max-iterations 2 --quiet
  expect_in "tune names the reference" "$tmp/err" "physik: diverged: tune: MuJoCo's same-forces run of $tmp/reach.json, the objective's reference, ended after 19 of 400 steps"
  expect_in "tune gives the dt hint" "$tmp/err" "try a smaller step, e.g. --set dt=0.02"
fi

# interchange: BVH / qBVH, joint-limit files, MJCF
check "from-bvh help" 0 "$bin" rig from-bvh --help
check "to-bvh pinhead" 0 "$bin" rig to-bvh "$src/models/rigs/pinhead.json" --out "$tmp/p.bvh"
check "from-bvh pinhead" 0 "$bin" rig from-bvh "$tmp/p.bvh" --out "$tmp/p_back.json"
check "from-bvh info" 0 "$bin" rig info --json "$tmp/p_back.json"
expect_in "from-bvh bones" "$tmp/out" '"bones": 18'
check "bvh to qbvh" 0 "$bin" bvh convert "$tmp/p.bvh" "$tmp/p.qbvh"
expect_in "qbvh channels" "$tmp/p.qbvh" "Wquaternion Xquaternion Yquaternion Zquaternion"
check "from-bvh qbvh" 0 "$bin" rig from-bvh "$tmp/p.qbvh"
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n    OFFSET 0 1 0\n  }\n' > "$tmp/open.bvh"
check "bvh unbalanced braces" 2 "$bin" rig from-bvh "$tmp/open.bvh"
expect_in "bvh unbalanced message" "$tmp/err" "open.bvh: line 9: field '}': unbalanced braces"
# a rotation of 1e308 degrees (finite; infinite in radians): the input's line, frame, joint and
# channel are named, not the output (the fuzzer's seed 9001 case, a mutated hand.bvh)
python3 - "$tmp/p.bvh" "$tmp/huge_angle.bvh" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
last = max(i for i, l in enumerate(lines) if l.strip())
row = lines[last].split()
row[-1] = "1e308"
lines[last] = " ".join(row)
open(sys.argv[2], "w").write("\n".join(lines))
PY
check "bvh convert: a rotation beyond 1e6 degrees" 2 "$bin" bvh convert "$tmp/huge_angle.bvh" "$tmp/huge_angle.qbvh"
expect_in "bvh convert: the input is named" "$tmp/err" "huge_angle.bvh: line"
expect_in "bvh convert: frame, joint and channel" "$tmp/err" "field 'MOTION': frame 0: joint '"
expect_in "bvh convert: the bound" "$tmp/err" "rotation '1e308' is beyond +-1e6 degrees"
check "bvh convert: nothing written" 1 test -e "$tmp/huge_angle.qbvh"
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n1 2 3\n' > "$tmp/frames.bvh"
check "bvh frame count" 2 "$bin" rig from-bvh "$tmp/frames.bvh"
expect_in "bvh frame count message" "$tmp/err" "frames.bvh: line 8: field 'Frames'"
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n1 nan 3\n' > "$tmp/nan.bvh"
check "bvh nan" 2 "$bin" rig from-bvh "$tmp/nan.bvh"
expect_in "bvh nan message" "$tmp/err" "nan.bvh: line 10: field 'MOTION'"
check "bvh bad axes" 2 "$bin" rig from-bvh "$tmp/p.bvh" --axes x-up
printf '{"limits_deg": {"forearm.L": {"x": [-120, 0]}, "torso": "locked"}}' > "$tmp/lim.json"
check "rig limits" 0 "$bin" rig limits "$src/models/rigs/pinhead.json" "$tmp/lim.json" --out "$tmp/lim_rig.json"
check "rig limits info" 0 "$bin" rig info --json "$tmp/lim_rig.json"
# limits on a free root hold against nothing
printf '{"limits_deg": {"head": "locked"}}' > "$tmp/rootlim.json"
check "rig limits on a free root" 2 "$bin" rig limits "$src/models/rigs/pinhead.json" "$tmp/rootlim.json"
printf '{"limits_deg": {"no_such_bone": {"x": [-120, 0]}}}' > "$tmp/badlim.json"
check "rig limits unknown bone" 2 "$bin" rig limits "$src/models/rigs/pinhead.json" "$tmp/badlim.json"
expect_in "unknown bone message" "$tmp/err" "badlim.json: limits_deg 'no_such_bone': unknown bone"
printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1], "limits_deg": {"x": [-190, 0]}}]}' > "$tmp/rangelim.json"
check "rig limit outside 180" 2 "$bin" rig info "$tmp/rangelim.json"
expect_in "rig limit range message" "$tmp/err" "rangelim.json: bones[0] 'a': field 'limits_deg.x': limits must lie within [-180, 180]"
if [ -f /usr/share/mujoco/model/humanoid/humanoid.xml ]; then
  check "from-mjcf humanoid" 0 "$bin" rig from-mjcf /usr/share/mujoco/model/humanoid/humanoid.xml --out "$tmp/hum.json"
  check "from-mjcf info" 0 "$bin" rig info "$tmp/hum.json"
fi
printf '<mujoco><worldbody><body></worldbody></mujoco>' > "$tmp/bad.xml"
check "from-mjcf bad xml" 2 "$bin" rig from-mjcf "$tmp/bad.xml"
expect_in "from-mjcf message" "$tmp/err" "bad.xml: MuJoCo cannot load it"
# capsule radii -> each bone's radius and collision_radius; a body with only a sphere takes the
# sphere's; a body with neither (a box) keeps the defaults and is named
cat > "$tmp/capsules.xml" <<'XML'
<mujoco model="two_capsules">
  <worldbody>
    <body name="upper" pos="0 0 1">
      <freejoint/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.07"/>
      <body name="lower" pos="0 0 -0.4">
        <joint type="hinge" axis="0 1 0" limited="true" range="-2 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.03"/>
        <body name="tip" pos="0 0 -0.3">
          <geom type="sphere" size="0.05" pos="0 0 -0.05"/>
          <body name="toe" pos="0 0 -0.1">
            <geom type="box" size="0.02 0.02 0.02" pos="0 0 -0.02"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
XML
check "from-mjcf capsule radii" 0 "$bin" rig from-mjcf "$tmp/capsules.xml" --out "$tmp/capsules.json"
expect_in "from-mjcf names a bone without a capsule or sphere" "$tmp/err" "no capsule or sphere geom on their body: radius and collision radius 0.14 x length (1): toe"
expect_in "from-mjcf names a widened limit" "$tmp/err" "limits widened: the rest angle was inside the torsion band (torsion_tolerance 0.1), now at its edge (1): lower x: [-2, 0] -> [-2, 0.2222] deg"
check "from-mjcf collision radii are the capsules'" 0 python3 - "$tmp/capsules.json" <<'PY'
import json, math, sys
rig = json.load(open(sys.argv[1]))
bones = {b["name"]: b for b in rig["bones"]}
def radius(b, key):
    return b.get(key, rig["defaults"].get(key))
for name, r in (("upper", 0.07), ("lower", 0.03), ("tip", 0.05)):
    assert radius(bones[name], "collision_radius") == r and radius(bones[name], "radius") == r, name
toe = bones["toe"]
length = math.dist(toe["head"], toe["tail"])
assert abs(radius(toe, "radius") - 0.14 * length) < 1e-12 * length, toe
assert radius(toe, "collision_radius") == radius(toe, "radius"), toe
assert any("limits widened" in n for n in rig["source"]), rig["source"]
PY
check "from-mjcf bad radius" 2 "$bin" rig from-mjcf "$tmp/capsules.xml" --radius -0.1
expect_in "from-mjcf bad radius message" "$tmp/err" "physik: error: --radius: must be a positive finite number"
check "from-mjcf total mass" 0 "$bin" rig from-mjcf "$tmp/capsules.xml" --total-mass 7 --out "$tmp/caps7.json"
check "from-mjcf total mass sums" 0 python3 -c "import json,sys; r=json.load(open('$tmp/caps7.json')); assert abs(sum(b['mass'] for b in r['bones']) - 7) < 1e-9"

# a mocap skeleton in centimetres: its height, the unit warning, sizes that fit, options
printf 'HIERARCHY\nROOT Hips\n{\n OFFSET 0 95 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n JOINT Spine\n {\n  OFFSET 0 10 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 80 0\n  }\n }\n JOINT LeftLeg\n {\n  OFFSET 9 -5 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 -90 0\n  }\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 95 0 0 0 0 0 0 0 0 0 0\n' > "$tmp/cm.bvh"
check "from-bvh cm" 0 "$bin" rig from-bvh "$tmp/cm.bvh" --out "$tmp/cm.json"
expect_in "from-bvh prints the height" "$tmp/err" "from-bvh: height 185 rig units"
expect_in "from-bvh names the scale" "$tmp/err" "looks like a file in centimetres (rig units are read as metres): convert it with --scale 0.01"
check "from-bvh cm scaled" 0 "$bin" rig from-bvh "$tmp/cm.bvh" --scale 0.01 --radius 0.05 --out "$tmp/m.json"
check "from-bvh radius once in the defaults" 0 python3 -c "import json; r=json.load(open('$tmp/m.json')); assert r['defaults']['radius'] == 0.05 and not any('radius' in b for b in r['bones']), r"
check "from-bvh no warning in metres" 1 grep -q "looks like" "$tmp/err"
# the source skeleton: kept in the rig file, written back by to-bvh, simulate --bvh, solve --bvh
check "from-bvh keeps the source skeleton" 0 python3 -c "import json; s=json.load(open('$tmp/m.json'))['source_skeleton']; assert s['format'] == 'bvh' and s['scale'] == 0.01 and [j['name'] for j in s['joints']] == ['Hips', 'Spine', 'LeftLeg'], s"
check "to-bvh source skeleton" 0 "$bin" rig to-bvh "$tmp/m.json"
expect_in "to-bvh writes the file's root" "$tmp/out" "ROOT Hips"
expect_in "to-bvh writes the file's units" "$tmp/out" "OFFSET 0 95 0"
expect_in "to-bvh writes the file's channels" "$tmp/out" "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
check "to-bvh own skeleton" 0 "$bin" rig to-bvh "$tmp/m.json" --own-skeleton
expect_in "to-bvh own skeleton: a joint per bone" "$tmp/out" "JOINT Hips>LeftLeg"
expect_in "to-bvh own skeleton in rig units" "$tmp/out" "OFFSET 0.09 -0.05 0"
head -n -3 "$tmp/cm.bvh" > "$tmp/clip.bvh"
printf 'Frames: 3\nFrame Time: 0.1\n0 95 0 0 0 0 0 0 0 0 0 0\n0 96 0 10 0 0 0 20 0 0 0 -30\n0 97 0 0 0 0 0 0 0 0 0 0\n' >> "$tmp/clip.bvh"
clip_scene() {  # clip_scene FILE INITIAL_POSE_JSON
  printf '{"rig": "m.json", "steps": 5, "control_points": [{"bone": "Spine", "target": [0, 0.1, 1.8]}], "initial_pose": %s}\n' "$2" > "$1"
}
clip_scene "$tmp/clip_scene.json" '{"bvh": "clip.bvh", "frame": 1}'
check "initial_pose from a clip" 0 "$bin" simulate "$tmp/clip_scene.json" --out "$tmp/clip_run" --bvh "$tmp/clip_run.bvh" --quiet
expect_in "simulate --bvh on the source skeleton" "$tmp/clip_run.bvh" "JOINT LeftLeg"
check "solve --bvh" 0 "$bin" solve "$tmp/clip_scene.json" --solver dls --out "$tmp/clip_solve" --bvh "$tmp/clip_solve.bvh" --quiet
expect_in "solve --bvh on the source skeleton" "$tmp/clip_solve.bvh" "ROOT Hips"
expect_in "solve --bvh one frame" "$tmp/clip_solve.bvh" "Frames: 1"
clip_scene "$tmp/clip_past.json" '{"bvh": "clip.bvh", "frame": 3}'
check "initial_pose frame past the clip" 2 "$bin" simulate "$tmp/clip_past.json" --out "$tmp/clip_run" --quiet
expect_in "initial_pose frame past the clip message" "$tmp/err" "clip_past.json: initial_pose: field 'frame': frame 3 is past the end of"
expect_in "initial_pose frame past the clip count" "$tmp/err" "(3 frames, 0 to 2)"
clip_scene "$tmp/clip_other.json" "{\"bvh\": \"$tmp/p.bvh\", \"frame\": 0}"
check "initial_pose from another skeleton" 2 "$bin" simulate "$tmp/clip_other.json" --out "$tmp/clip_run" --quiet
expect_in "initial_pose from another skeleton message" "$tmp/err" "clip_other.json: initial_pose: field 'bvh': '$tmp/p.bvh' is not a clip of the rig's source skeleton"
clip_scene "$tmp/clip_missing.json" '{"bvh": "nowhere.bvh", "frame": 0}'
check "initial_pose bad path" 2 "$bin" simulate "$tmp/clip_missing.json" --out "$tmp/clip_run" --quiet
expect_in "initial_pose bad path message" "$tmp/err" "clip_missing.json: initial_pose: field 'bvh': cannot read '$tmp/nowhere.bvh': no such file"
# following a clip: a run folder, the clip's frames at its speed
check "follow" 0 "$bin" follow "$tmp/clip.bvh" --rig "$tmp/m.json" --out "$tmp/follow" --ground -0.5 --bvh "$tmp/follow.bvh" --quiet
check "follow run folder" 0 test -f "$tmp/follow/trajectory.csv"
expect_in "follow --bvh on the source skeleton" "$tmp/follow.bvh" "JOINT Spine"
check "follow frames past the clip" 2 "$bin" follow "$tmp/clip.bvh" --rig "$tmp/m.json" --out "$tmp/follow" --frames 0:5
expect_in "follow frames message" "$tmp/err" "clip.bvh: field 'last frame': 5 is outside frames 0 to 2"
check "follow another skeleton" 2 "$bin" follow "$tmp/p.bvh" --rig "$tmp/m.json" --out "$tmp/follow"
expect_in "follow another skeleton message" "$tmp/err" "not a clip of the rig's source skeleton"
check "follow unknown bone" 2 "$bin" follow "$tmp/clip.bvh" --rig "$tmp/m.json" --out "$tmp/follow" --point Nose:tail
expect_in "follow unknown bone message" "$tmp/err" "points[0]: field 'bone': unknown bone 'Nose'"
# the clip's frame time: 61 frames of 1/120 s run at dt 1/120 and write a BVH of 61 frames of
# 1/120 s (it was 61 steps of the engine's 0.05 s, Frame Time 0.05: six times slow)
{ head -n -3 "$tmp/cm.bvh"; printf 'Frames: 61\nFrame Time: 0.00833333333333\n'
  for k in $(seq 0 60); do printf '0 95 0 0 0 0 0 0 0 0 0 0\n'; done; } > "$tmp/clip120.bvh"
check "follow a 120 fps clip" 0 "$bin" follow "$tmp/clip120.bvh" --rig "$tmp/m.json" --out "$tmp/follow120" --gravity --ground -0.5 --bvh "$tmp/follow120.bvh"
expect_in "follow at the clip's dt" "$tmp/err" "follow: 3 points over 61 clip frames, 61 steps of 0.00833333"
expect_in "follow --bvh at the clip's frame time" "$tmp/follow120.bvh" "Frame Time: 0.00833333333333"
expect_in "follow --bvh one frame per clip frame" "$tmp/follow120.bvh" "Frames: 61"
check "follow --set dt off the frame time" 0 "$bin" follow "$tmp/clip120.bvh" --rig "$tmp/m.json" --out "$tmp/follow120" --set dt=0.05 --bvh "$tmp/follow120.bvh" --quiet
expect_in "follow says the clip plays faster" "$tmp/err" "physik: warning: follow: a clip frame takes 0.05 s (1 step of dt 0.05 s) against the clip's 0.00833333 s: the run (and --bvh) plays the clip at 0.166667 times its speed"
# a floor height that is not a finite coordinate, a frame time whose run no int counts, a source
# skeleton whose scale puts the clip's root past +-1e9: each exit 2 naming what
for g in nan -inf -1e10; do
  check "follow --ground $g" 2 "$bin" follow "$tmp/clip.bvh" --rig "$tmp/m.json" --out "$tmp/follow" --ground="$g"
  expect_in "follow --ground $g message" "$tmp/err" "physik: error: --ground: the floor's height must be a finite number within +-1e9 rig units"
done
sed 's/^Frame Time: 0.1$/Frame Time: 5e7/' "$tmp/clip.bvh" > "$tmp/clip_slow.bvh"
check "follow Frame Time 5e7" 2 "$bin" follow "$tmp/clip_slow.bvh" --rig "$tmp/m.json" --out "$tmp/follow"
expect_in "follow Frame Time 5e7 message" "$tmp/err" "clip_slow.bvh: field 'Frame Time': 5e+07 s a frame at dt 0.00833333 s is 6e+09 steps a frame"
python3 -c "import json; r=json.load(open('$tmp/m.json')); r['source_skeleton']['scale'] = 1e12; json.dump(r, open('$tmp/m12.json', 'w'))"
check "follow a root past 1e9" 2 "$bin" follow "$tmp/clip.bvh" --rig "$tmp/m12.json" --out "$tmp/follow"
expect_in "follow a root past 1e9 message" "$tmp/err" "clip.bvh: field 'frame': frame 1 puts the rig's root 1.64966e+13 rig units out along an axis, past +-1e+09"
sed 's/"m.json"/"m12.json"/' "$tmp/clip_scene.json" > "$tmp/clip_scene12.json"
check "initial_pose a root past 1e9" 2 "$bin" simulate "$tmp/clip_scene12.json" --out "$tmp/clip_run" --quiet
expect_in "initial_pose a root past 1e9 message" "$tmp/err" "clip_scene12.json: initial_pose: field 'frame': frame 1 puts the rig's root 1.64966e+13 rig units out"
for opt in --radius --mass-per-length --total-mass; do
  check "from-bvh bad $opt" 2 "$bin" rig from-bvh "$tmp/cm.bvh" $opt nan
  expect_in "from-bvh bad $opt message" "$tmp/err" "physik: error: $opt: must be a positive finite number"
done
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n    OFFSET 0 1 0\n    CHANNELS 1 Zrotation\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n' > "$tmp/endch.bvh"
check "bvh channels on an End Site" 2 "$bin" rig from-bvh "$tmp/endch.bvh"
expect_in "bvh End Site channels message" "$tmp/err" "endch.bvh: line 9: field 'CHANNELS': an End Site has no channels"
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  JOINT B\n  {\n    OFFSET 0 0 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 1 0\n    }\n  }\n  JOINT C\n  {\n    OFFSET 0 0 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 1 0 0\n    }\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0 10 20 30 0 0 0\n' > "$tmp/zero.bvh"
check "bvh zero offsets to several children" 0 "$bin" rig from-bvh "$tmp/zero.bvh" --out "$tmp/zero.json"
expect_in "bvh a joint with no bone named" "$tmp/err" "from-bvh: warning: joint 'A' (line 2) has no bone of its own (its children B, C sit at its position)"
expect_in "bvh a root without position channels is pinned" "$tmp/err" "from-bvh: note: root joint 'A' (line 2) has no position channels, so it never moves: its joint is pinned where it is"
check "bvh zero offsets no nan" 1 grep -qi nan "$tmp/zero.json"
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  JOINT B\n  {\n    OFFSET 0 1 0\n    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 1 0\n    }\n  }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n0 0 0 0 1 0 0 0 0\n0 0 0 0 1.5 0 0 0 0\n' > "$tmp/slide.bvh"
check "bvh position channels off the offset" 0 "$bin" rig from-bvh "$tmp/slide.bvh" --out "$tmp/slide.json"
expect_in "bvh position channels named by joint, bone and size" "$tmp/err" "from-bvh: warning: joint 'B' (line 6, bone 'A'): its position channels move it up to 0.5 file units off its OFFSET"

# the write-back (issue 56): a CMU-like clip (Spine1 and the hand: children at their origin; a
# joint with no child), angles on either branch, a stretch; every channel comes back
cat > "$tmp/cmu.bvh" <<'BVH'
HIERARCHY
ROOT Hips
{
  OFFSET 0 17 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT LowerBack
  {
    OFFSET 0 0 0
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT Spine1
    {
      OFFSET 0 2 0
      CHANNELS 3 Zrotation Yrotation Xrotation
      JOINT Neck
      {
        OFFSET 0 0 0
        CHANNELS 3 Zrotation Yrotation Xrotation
        JOINT Head
        {
          OFFSET 0 1.6 0
          CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
          JOINT HeadTop
          {
            OFFSET 0 1.8 0
            CHANNELS 3 Zrotation Yrotation Xrotation
          }
        }
      }
      JOINT LeftShoulder
      {
        OFFSET 0 0 0
        CHANNELS 3 Zrotation Yrotation Xrotation
        JOINT LeftHand
        {
          OFFSET 3.5 0 0
          CHANNELS 3 Zrotation Yrotation Xrotation
          JOINT LThumb
          {
            OFFSET 0 0 0
            CHANNELS 3 Zrotation Yrotation Xrotation
            End Site
            {
              OFFSET 0.6 0 0.6
            }
          }
          JOINT LeftFingerBase
          {
            OFFSET 0 0 0
            CHANNELS 3 Zrotation Yrotation Xrotation
            End Site
            {
              OFFSET 1.2 0 0
            }
          }
        }
      }
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.0083333
0 17 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1.6 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0
1.5 16.5 -2 154.4 -36.8 -111.4 12 -150 40 -5 3 170 20 10 -30 0.1 1.7 -0.05 90 -45 10 -120 60 100 30 -20 10 -10 160 -100 25 35 -15 -60 -80 120
BVH
check "bvh convert cmu-like" 0 "$bin" bvh convert "$tmp/cmu.bvh" "$tmp/cmu_back.bvh"
check "bvh convert: no warnings" 1 grep -q "warning" "$tmp/err"
check "bvh convert: every channel as it was" 0 python3 - "$tmp/cmu.bvh" "$tmp/cmu_back.bvh" <<'PY'
import sys
def rows(path):
    lines = open(path).read().split("MOTION")[1].strip().splitlines()[2:]
    return [[float(v) for v in l.split()] for l in lines]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
worst = max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb))
assert len(a) == len(b) and worst < 1e-6, worst
PY
check "bvh convert cmu-like to qbvh and back" 0 "$bin" bvh convert "$tmp/cmu_back.bvh" "$tmp/cmu.qbvh"
check "qbvh back to bvh" 0 "$bin" bvh convert "$tmp/cmu.qbvh" "$tmp/cmu_q.qbvh"
check "qbvh convert: every quaternion as it was" 0 python3 - "$tmp/cmu.qbvh" "$tmp/cmu_q.qbvh" <<'PY'
import sys
def rows(path):
    lines = open(path).read().split("MOTION")[1].strip().splitlines()[2:]
    return [[float(v) for v in l.split()] for l in lines]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
assert max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb)) < 1e-9
PY
# a solve from a frame of the clip: the held joints keep that frame's rotation, one frame at the
# source's frame time
check "from-bvh cmu-like" 0 "$bin" rig from-bvh "$tmp/cmu.bvh" --scale 0.056 --out "$tmp/cmu.json"
expect_in "from-bvh names the joints with no bone" "$tmp/err" "joint 'Spine1' (line 10) has no bone of its own (its children Neck, LeftShoulder sit at its position)"
expect_in "from-bvh names the joint with no child" "$tmp/err" "joint 'HeadTop' (line 22) has no bone of its own (no child, no End Site)"
expect_in "from-bvh names the stretch and its size" "$tmp/err" "joint 'Head' (line 18, bone 'Neck'): its position channels move it up to 0.15 file units off its OFFSET"
printf '{"rig": "cmu.json", "steps": 5, "control_points": [{"bone": "LeftFingerBase", "target": [0.2, -0.1, 1.1]}], "initial_pose": {"bvh": "cmu.bvh", "frame": 1}}\n' > "$tmp/cmu_scene.json"
check "solve --bvh from a clip frame" 0 "$bin" solve "$tmp/cmu_scene.json" --solver dls --out "$tmp/cmu_solve" --bvh "$tmp/cmu_solve.bvh" --quiet
expect_in "solve --bvh at the source's frame time" "$tmp/cmu_solve.bvh" "Frame Time: 0.0083333"
check "solve --bvh: Spine1 and the stretch as the frame had them" 0 python3 - "$tmp/cmu.bvh" "$tmp/cmu_solve.bvh" <<'PY'
import sys
def last(path):
    return [float(v) for v in open(path).read().split("MOTION")[1].strip().splitlines()[-1].split()]
a, b = last(sys.argv[1]), last(sys.argv[2])
# Spine1's channels (columns 9-11) and Head's position channels (18-20)
assert max(abs(a[k] - b[k]) for k in list(range(9, 12)) + list(range(18, 21))) < 1e-6, (a, b)
PY
# a root with no position channels (three.js's pirouette) is pinned: a solve cannot move it
printf 'HIERARCHY\nROOT hip\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Yrotation Xrotation\n  JOINT abdomen\n  {\n    OFFSET 0 20 -1\n    CHANNELS 3 Zrotation Yrotation Xrotation\n    End Site\n    {\n      OFFSET 0 30 0\n    }\n  }\n  JOINT lthigh\n  {\n    OFFSET 9 -2 0\n    CHANNELS 3 Zrotation Yrotation Xrotation\n    End Site\n    {\n      OFFSET 0 -80 0\n    }\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.0083333\n0 0 0 0 0 0 0 0 0\n' > "$tmp/pirouette.bvh"
check "from-bvh pirouette-like" 0 "$bin" rig from-bvh "$tmp/pirouette.bvh" --scale 0.01 --out "$tmp/pir.json"
check "pirouette-like root held" 0 python3 -c "import json; r=json.load(open('$tmp/pir.json')); assert r['root'] in ('pinned', 'fixed'), r.get('root')"
printf '{"rig": "pir.json", "steps": 200, "control_points": [{"bone": "abdomen", "target": [0.2, 0.2, 0.3]}]}\n' > "$tmp/pir_scene.json"
check "solve pirouette-like" 0 "$bin" solve "$tmp/pir_scene.json" --solver physik --out "$tmp/pir_solve" --bvh "$tmp/pir_solve.bvh" --quiet
check "pirouette-like: no root move to leave out" 1 grep -q "has no .position channel" "$tmp/err"
check "from-bvh --root free" 0 "$bin" rig from-bvh "$tmp/pirouette.bvh" --scale 0.01 --root free --out "$tmp/pir_free.json"
check "from-bvh --root bad" 2 "$bin" rig from-bvh "$tmp/pirouette.bvh" --root hovering
expect_in "from-bvh --root message" "$tmp/err" "physik: error: --root: expected free or pinned, got 'hovering'"
# whatever physik writes, physik reads: a scale that puts the rig past +-1e9 is refused
check "to-bvh past 1e9" 2 "$bin" rig to-bvh "$src/models/rigs/pinhead.json" --own-skeleton --scale 1e9 --out "$tmp/big.bvh"
expect_in "to-bvh past 1e9 message" "$tmp/err" "beyond +-1e9 file units"
check "to-bvh past 1e9 writes nothing" 1 test -e "$tmp/big.bvh"
# a joint with 10,000 siblings converts in linear memory (it took 2.3 GB and minutes: the rest
# overlaps' broad phase over bones piled at one joint, which bvh convert never reads)
python3 - "$tmp/wide.bvh" <<'PY'
import random, sys
random.seed(1)
n = 10000
s = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n"
for i in range(n):
    s += "JOINT s%d\n{\nOFFSET %g %g %g\nCHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n" % (
        i, random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1))
s += "}\nMOTION\nFrames: 1\nFrame Time: 0.1\n" + " ".join(["0"] * (6 + 3 * n)) + "\n"
open(sys.argv[1], "w").write(s)
PY
# (a sanitized binary cannot run under an address-space cap: its shadow memory reserves terabytes)
if [ "${PHYSIK_SANITIZED:-0}" = 1 ]; then
  echo "skipped in the sanitizer build: bvh convert of 10,000 siblings within 400 MB"
  check "bvh convert of 10,000 siblings" 0 "$bin" bvh convert "$tmp/wide.bvh" "$tmp/wide_back.bvh"
else
  check "bvh convert of 10,000 siblings within 400 MB" 0 bash -c "ulimit -v 400000; '$bin' bvh convert '$tmp/wide.bvh' '$tmp/wide_back.bvh'"
fi
# a source skeleton listed parents first but not depth first: refused, naming the field
check "source skeleton not depth-first" 0 python3 - "$tmp/cmu.json" "$tmp/cmu_bfs.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
j = r["source_skeleton"]["joints"]
names = [x["name"] for x in j]
j[names.index("LeftHand")]["parent"] = names.index("Neck")  # Neck's subtree closed before it
json.dump(r, open(sys.argv[2], "w"))
PY
check "rig with a skeleton not depth-first" 2 "$bin" rig to-bvh "$tmp/cmu_bfs.json"
expect_in "rig with a skeleton not depth-first message" "$tmp/err" "source_skeleton.joints[7]: field 'parent': joint 3 is not the joint before nor one of its ancestors"

# rig info tells the rig's story (issue 56 part 4, issue 58): welds, pinned and fixed roots
printf '{"root": "pinned", "bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1], "limits_deg": {"x": [0, 0], "y": [-30, 60]}}, {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2]}, {"name": "c", "parent": "a", "head": [0,0,1], "tail": [1,0,1], "weld": "b"}]}' > "$tmp/pinned.json"
check "rig info pinned root" 0 "$bin" rig info "$tmp/pinned.json"
expect_in "rig info pinned root says so" "$tmp/out" "root 'a': pinned: a universal at its head, held in place, 2 DOF; limits against its rest frame in the world: x locked at 0  y [-30, 60]  z free"
expect_in "rig info the world's joint" "$tmp/out" "[0] world -> a(2)"
expect_in "rig info welded bone" "$tmp/out" "welded to b (0 DOF)"
check "rig info pinned root json" 0 "$bin" rig info --json "$tmp/pinned.json"
cp "$tmp/out" "$tmp/pinned_info.json"
check "rig info json dof agrees with the joint list" 0 python3 - "$tmp/pinned_info.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
bones = {b["name"]: b for b in r["bone_list"]}
assert r["root"] == "pinned" and bones["a"]["dof"] == 2 and bones["a"]["joint"] == "pinned"
assert bones["c"]["dof"] == 0 and bones["c"]["welded_to"] == "b", bones["c"]
assert bones["b"]["joint"] == "ball" and bones["c"]["joint"] == "weld", bones
assert sum(j["dof"] for j in r["joint_list"]) == sum(b["dof"] for b in r["bone_list"]) == r["dof"] == 5
assert r["joint_list"][0]["parent"] is None and r["joint_list"][0]["world"]
PY
printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]}, {"name": "knee", "parent": "a", "head": [0,0,1], "tail": [0,0,2], "limits_deg": {"x": [0, 135], "y": [0, 0], "z": [0, 0]}}, {"name": "wrist", "parent": "a", "head": [0,0,1], "tail": [1,0,1], "limits_deg": {"x": [-70, 80], "y": [0, 0], "z": [-20, 30]}}]}' > "$tmp/hinged.json"
check "rig info hinges" 0 "$bin" rig info "$tmp/hinged.json"
expect_in "rig info names a hinge" "$tmp/out" "hinge, 1 DOF: x [0, 135]  y locked at 0  z locked at 0"
expect_in "rig info names a universal joint" "$tmp/out" "universal (two hinges), 2 DOF: x [-70, 80]  y locked at 0  z [-20, 30]"
check "rig info hinges json" 0 "$bin" rig info --json "$tmp/hinged.json"
expect_in "rig info json hinge" "$tmp/out" '"joint": "hinge"'
expect_in "rig info json universal" "$tmp/out" '"joint": "universal"'
# a start pose off a hinge is put on it by the exact and implicit schemes, and one warning says so
printf '{"rig": "hinged.json", "steps": 2, "initial_pose": {"rotation_deg": {"knee": [30, 20, 0]}}}' > "$tmp/offhinge.json"
check "a start off its hinge" 0 "$bin" simulate "$tmp/offhinge.json" --quiet --out "$tmp/offhinge"
expect_in "a start off its hinge is said" "$tmp/err" "initial_pose: 1 joint(s) start off their locked axes' set, which the implicit scheme keeps; the start is the nearest pose on it: knee 19.8 deg off its hinge"
check "the paper's scheme keeps it" 0 "$bin" simulate "$tmp/offhinge.json" --quiet --set preset=original --out "$tmp/offhinge_gs"
expect_absent "the paper's scheme says nothing" "$tmp/err" "locked axes' set"
sed 's/"pinned"/"fixed"/; s/, "limits_deg": {"x": \[0, 0\], "y": \[-30, 60\]}//' "$tmp/pinned.json" > "$tmp/fixed.json"
check "rig info fixed root" 0 "$bin" rig info "$tmp/fixed.json"
expect_in "rig info fixed root says so" "$tmp/out" "root 'a': fixed to the world: 0 DOF"
if [ -f /usr/share/mujoco/model/adhesion/active_adhesion.xml ]; then
  check "from-mjcf adhesion" 0 "$bin" rig from-mjcf /usr/share/mujoco/model/adhesion/active_adhesion.xml --out "$tmp/adhesion.json"
  check "rig info --json adhesion" 0 "$bin" rig info --json "$tmp/adhesion.json"
  check "rig info adhesion" 0 "$bin" rig info "$tmp/adhesion.json"
fi
if [ -f /usr/share/mujoco/model/tendon_arm/arm26.xml ]; then
  check "from-mjcf arm26" 0 "$bin" rig from-mjcf /usr/share/mujoco/model/tendon_arm/arm26.xml --out "$tmp/arm26.json"
  check "rig info arm26" 0 "$bin" rig info "$tmp/arm26.json"
  expect_in "rig info arm26 pinned root" "$tmp/out" "(pinned: a hinge at its head"
fi

# a human skeleton (Mixamo's names, centimetres): a human body, the unit rule, --height, --body,
# --mapping, --weld-constant, --look-at; each bad value exits 2 naming the option
human_joint() {  # human_joint NAME "X Y Z" INNER
  printf 'JOINT %s\n{\nOFFSET %s\nCHANNELS 3 Zrotation Xrotation Yrotation\n%s}\n' "$1" "$2" "$3"
}
human_end() { printf 'End Site\n{\nOFFSET %s\n}\n' "$1"; }
human_arm() {  # human_arm SIDE SIGN
  human_joint "$1Shoulder" "${2}6 11 0" "$(human_joint "$1Arm" "${2}11 0 0" "$(human_joint "$1ForeArm" "${2}28 0 0" "$(human_joint "$1Hand" "${2}25 0 0" "$(human_end "${2}18 0 0")")")")"
}
human_leg() {  # human_leg SIDE SIGN
  human_joint "$1UpLeg" "${2}9 -6 0" "$(human_joint "$1Leg" "0 -42 0" "$(human_joint "$1Foot" "0 -42 0" "$(human_end "0 -6 14")")")"
}
{
  printf 'HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n'
  human_joint Spine "0 10 0" "$(human_joint Spine1 "0 25 0" "$(human_joint Neck "0 22 0" "$(human_joint Head "0 9 2" "$(human_end "0 20 0")")"; human_arm Left ""; human_arm Right "-")")"
  human_leg Left ""; human_leg Right "-"
  printf '}\nMOTION\nFrames: 2\nFrame Time: 0.0333333\n'
  for f in 0 1; do printf '0 100 %s' "$f"; for j in $(seq 1 19); do printf ' 0 %s 0' "$f"; done; printf '\n'; done
} > "$tmp/human.bvh"
check "from-bvh human" 0 "$bin" rig from-bvh "$tmp/human.bvh" --out "$tmp/human_cm.json"
expect_in "from-bvh human: the body" "$tmp/err" "from-bvh: body: human (joint names of the Mixamo / HumanIK convention, 19 of 19 joints named)"
expect_in "from-bvh human: the unit rule" "$tmp/err" "looks like a file in centimetres: --scale 0.01 makes it"
check "from-bvh human in metres" 0 "$bin" rig from-bvh "$tmp/human.bvh" --scale 0.01 --total-mass 80 --out "$tmp/human.json"
check "from-bvh human in metres: no unit warning" 1 grep -q "looks like a file" "$tmp/err"
check "from-bvh human: 80 kg, segments, a knee hinge" 0 python3 -c "
import json
r = json.load(open('$tmp/human.json'))
bones = {b['name']: b for b in r['bones']}
assert abs(sum(b['mass'] for b in r['bones']) - 80) < 1e-9
assert bones['LeftUpLeg']['segment'] == 'thigh.L' and bones['Head']['forward'] == [0.0, 0.0, 1.0], bones['Head']
knee = bones['LeftLeg']['limits_deg']
assert knee['y'] == [0, 0] and knee['z'] == [0, 0] and knee['x'][1] == 135, knee
"
check "rig info human" 0 "$bin" rig info "$tmp/human.json"
expect_in "rig info: the body line" "$tmp/out" "body: human template"
expect_in "rig info: a bone's segment" "$tmp/out" "segment thigh.L"
check "from-bvh --height" 0 "$bin" rig from-bvh "$tmp/human.bvh" --height 1.8 --out "$tmp/human18.json"
expect_in "from-bvh --height: 1.8 m" "$tmp/err" "height 1.8 rig units"
for bad in "--height|0|--height: must be a positive finite number (metres), got 0" \
    "--height|-1|--height: must be a positive finite number (metres), got -1" \
    "--height|inf|--height: must be a positive finite number (metres), got inf" \
    "--total-mass|0|--total-mass: must be a positive finite number (kg), got 0 (leave the option out for the default)" \
    "--total-mass|-0|--total-mass: must be a positive finite number (kg), got -0" \
    "--radius|0|--radius: must be a positive finite number (rig units), got 0" \
    "--mass-per-length|-0|--mass-per-length: must be a positive finite number (kg per rig unit), got -0" \
    "--body|robot|--body: expected auto, human or generic, got 'robot'"; do
  IFS='|' read -r opt value text <<< "$bad"
  check "from-bvh $opt $value" 2 "$bin" rig from-bvh "$tmp/human.bvh" $opt "$value"
  expect_in "from-bvh $opt $value message" "$tmp/err" "physik: error: $text"
done
check "from-mjcf --total-mass 0" 2 "$bin" rig from-mjcf "$tmp/capsules.xml" --total-mass 0
expect_in "from-mjcf --total-mass 0 message" "$tmp/err" "physik: error: --total-mass: must be a positive finite number (kg), got 0"
check "from-bvh --height with --scale" 2 "$bin" rig from-bvh "$tmp/human.bvh" --height 1.8 --scale 0.01
expect_in "from-bvh --height with --scale message" "$tmp/err" "--height: give --height (the figure's height in metres) or --scale"
check "from-bvh --mass-per-length on a human" 2 "$bin" rig from-bvh "$tmp/human.bvh" --mass-per-length 2
expect_in "from-bvh --mass-per-length on a human message" "$tmp/err" "--mass-per-length: a human body's masses come from de Leva's table"
check "from-bvh --body generic" 0 "$bin" rig from-bvh "$tmp/human.bvh" --body generic --mass-per-length 2 --out "$tmp/human_generic.json"
check "from-bvh --body human on another skeleton" 2 "$bin" rig from-bvh "$tmp/cm.bvh" --body human
expect_in "from-bvh --body human message" "$tmp/err" "--body: human: $tmp/cm.bvh is not a human skeleton by its joint names"
printf '{"joints": {"Hips": "pelvis", "LeftUpLeg": "thigh.l"}}' > "$tmp/badmap.json"
check "from-bvh --mapping unknown segment" 2 "$bin" rig from-bvh "$tmp/human.bvh" --mapping "$tmp/badmap.json"
expect_in "from-bvh --mapping unknown segment message" "$tmp/err" "badmap.json: joints 'LeftUpLeg': unknown segment 'thigh.l' (did you mean 'thigh.L'?)"
printf '{"joints": {"Hips": "pelvis", "LeftUpLg": "thigh.L"}}' > "$tmp/badjoint.json"
check "from-bvh --mapping unknown joint" 2 "$bin" rig from-bvh "$tmp/human.bvh" --mapping "$tmp/badjoint.json"
expect_in "from-bvh --mapping unknown joint message" "$tmp/err" "badjoint.json: joints 'LeftUpLg': no joint of the skeleton has this name (did you mean 'LeftUpLeg'?)"
check "from-bvh --mapping with --body generic" 2 "$bin" rig from-bvh "$tmp/human.bvh" --body generic --mapping "$tmp/badmap.json"
check "from-bvh --weld-constant" 0 "$bin" rig from-bvh "$tmp/human.bvh" --scale 0.01 --weld-constant --out "$tmp/human_wc.json"
printf '{"rig": "human.json", "steps": 5, "pins": [{"bone": "LeftFoot"}, {"bone": "RightFoot"}]}\n' > "$tmp/look.json"
check "simulate --look-at" 0 "$bin" simulate "$tmp/look.json" --out "$tmp/look" --quiet --look-at Head=1,-2,1.7
check "simulate --look-at: the face's axis" 0 python3 -c "
import json
(a,) = json.load(open('$tmp/look/scene.json'))['aim_targets']
assert a['bone'] == 'Head' and a['axis'] == [0.0, 0.0, 1.0], a
"
check "--look-at a bone without a forward axis" 2 "$bin" simulate "$pinhead_scene" --out "$tmp/x" --quiet --look-at head=0,-3,2
expect_in "--look-at message" "$tmp/err" "--look-at: 'head=0,-3,2': field 'bone': 'head' has no forward axis"

# the rig's collision_exclude, and what rig info says about the rest pose
printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1]}, {"name": "b", "parent": "a", "head": [0,0,1], "tail": [0,0,2]}], "collision_exclude": [["a", "b"], ["b", "b"]]}' > "$tmp/twice.json"
check "rig exclusion naming one bone twice" 2 "$bin" rig info "$tmp/twice.json"
expect_in "rig exclusion message" "$tmp/err" "twice.json: field 'collision_exclude[1]': bone 'b' is paired with itself"
check "rig info pinhead" 0 "$bin" rig info "$src/models/rigs/pinhead.json"
expect_in "rig info axes" "$tmp/out" "forearm.L:  x ("
expect_in "rig info limits per axis" "$tmp/out" "z [-160, 0]"
expect_in "rig info rest band" "$tmp/out" "limits whose torsion band holds the rest angle (torsion_tolerance 0.1; they push at rest): 4"
# a scene that starts with overlapping capsules under self-collision is warned about, by pair
printf '{"bones": [{"name": "r", "parent": null, "head": [0,0,0], "tail": [0,0,1], "collision_radius": 0.1}, {"name": "b", "parent": "r", "head": [0,0,1], "tail": [1,0,1], "collision_radius": 0.1}, {"name": "b1", "parent": "b", "head": [1,0,1], "tail": [0.5,0,1.5], "collision_radius": 0.1}, {"name": "c", "parent": "r", "head": [0,0,1], "tail": [0.5,0,1.6], "collision_radius": 0.1}]}' > "$tmp/cross.json"
printf '{"rig": "cross.json", "steps": 3, "self_collision": true}' > "$tmp/cross_scene.json"
check "simulate overlapping start" 0 "$bin" simulate "$tmp/cross_scene.json" --out "$tmp/cross_run" --quiet
expect_in "simulate names the overlapping pair" "$tmp/err" '1 bone pair overlaps at the start under self_collision (depth in rig units): ["b1", "c"]'
expect_in "simulate says what to change" "$tmp/err" "add the pairs to collision_exclude"

# physik solve: classic IK solvers and the engine on a scene's control points
check "solve help" 0 "$bin" solve --help
# numeric options name their type (the solve options are read as text, then checked by their row)
expect_in "solve help: a real option is FLOAT" "$tmp/out" "--tol FLOAT"
expect_in "solve help: an integer option is INT" "$tmp/out" "--max-iterations INT"
expect_in "solve help: three numbers" "$tmp/out" "--gravity FLOAT x 3"
check "solve bad solver" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver newton --out "$tmp/solve"
expect_in "solve bad solver message" "$tmp/err" "--solver: unknown value 'newton' (expected fabrik|ccd"
check "solve missing scene" 2 "$bin" solve "$tmp/none.json" --solver dls --out "$tmp/solve"
check "solve negative tol" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver dls --tol -1 --out "$tmp/solve"
check "solve dls" 0 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver dls --out "$tmp/solve" --quiet
expect_in "solve summary converged" "$tmp/solve/summary.json" '"converged": true'
expect_in "solve summary residuals" "$tmp/solve/summary.json" '"final_residuals"'
expect_in "solve summary solver" "$tmp/solve/summary.json" '"solver": "dls"'
expect_in "solve final pose" "$tmp/solve/final_pose.csv" "hand.L"
# a diverging engine solve (the paper's damping on pinhead): exit 3 after writing both files
printf '{"rig": "%s/models/rigs/pinhead.json", "params": {"preset": "original", "control_k": 30, "damping": 20}, "control_points": [{"bone": "hand.L", "target": [1.5, -0.5, 1.2], "spring": "capped"}, {"bone": "hand.R", "target": [-1.0, -0.9, 1.0], "spring": "capped"}], "steps": 400}' "$src" > "$tmp/s4.json"
check "solve diverges" 3 "$bin" solve "$tmp/s4.json" --solver physik-explicit --out "$tmp/solve_div" --quiet
expect_in "solve diverged message" "$tmp/err" "diverged"
expect_in "solve diverged summary" "$tmp/solve_div/summary.json" '"diverged": true'
rows=$(( $(wc -l < "$tmp/solve_div/final_pose.csv") - 1 ))
if [ "$rows" -eq 18 ]; then pass=$((pass+1)); else
  fail=$((fail+1)); echo "FAIL solve diverged final pose: $rows rows, want 18 (one per pinhead bone)"; fi
# the same scene in the solve mode (the implicit step): the paper's damping poses it
check "solve mode at the paper's damping" 0 "$bin" solve "$tmp/s4.json" --solver physik --out "$tmp/solve_mode" --quiet
expect_in "solve mode converged" "$tmp/solve_mode/summary.json" '"converged": true'
expect_in "solve mode is the equilibrium solve" "$tmp/solve_mode/summary.json" '"method": "equilibrium"'
expect_in "solve mode goals" "$tmp/solve_mode/summary.json" '"short_goals": []'
# the time-stepping solve mode keeps its name and its growing step
check "physik-steps at the paper's damping" 0 "$bin" solve "$tmp/s4.json" --solver physik-steps --out "$tmp/solve_steps" --quiet
expect_in "physik-steps growth" "$tmp/solve_steps/summary.json" '"dt_growth"'
expect_in "physik-steps method" "$tmp/solve_steps/summary.json" '"method": "steps"'
# --tol-angle: an angle, positive and finite
for bad in 0 -1e-3 nan inf; do
  check "solve --tol-angle $bad" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver physik --tol-angle "$bad" --out "$tmp/x" --quiet
  expect_in "solve --tol-angle $bad message" "$tmp/err" "--tol-angle: must be a positive finite number"
done
# a goal out of reach: the equilibrium solve exits 4 naming it and by how much (never 3)
# (the upper arm's head held at the origin: the elbow's root is free, and would follow the pull)
printf '{"rig": "%s/models/rigs/elbow.json", "control_points": [{"bone": "forearm", "alpha": 1, "target": [0, 0, 40]}, {"bone": "upper_arm", "alpha": 0, "target": [0, 0, 0]}]}' "$src" > "$tmp/far_eq.json"
check "equilibrium out of reach" 4 "$bin" solve "$tmp/far_eq.json" --solver physik --out "$tmp/solve_far_eq" --quiet
expect_in "equilibrium out of reach names the goal" "$tmp/err" "short: control point 0 on 'forearm'"
expect_in "equilibrium out of reach in the summary" "$tmp/solve_far_eq/summary.json" '"met": false'
# an aim the elbow's limit keeps short (the forearm aimed to bend the way it cannot, the upper
# arm held by two springs, which give way a little to the aim's pull): named by its angle (rad)
printf '{"rig": "%s/models/rigs/elbow.json", "aim_targets": [{"bone": "forearm", "point": [0, -3, 2]}], "control_points": [{"bone": "upper_arm", "alpha": 0, "target": [0, 0, 0]}, {"bone": "upper_arm", "alpha": 1, "target": [0, 0, 2]}]}' "$src" > "$tmp/aim_back.json"
check "equilibrium aim short" 4 "$bin" solve "$tmp/aim_back.json" --solver physik --out "$tmp/solve_aim" --quiet
expect_in "equilibrium aim short names the aim" "$tmp/err" "aim of 'forearm' 0."
expect_in "equilibrium aim short in rad" "$tmp/solve_aim/summary.json" '"unit": "rad"'
# KDL from the command line: one chain with orientation rows; what it cannot take exits 2
printf '{"rig": "%s/models/rigs/pinhead.json", "orientation_targets": [{"bone": "hand.L", "quaternion": [0.7071067811865476, 0.7071067811865476, 0, 0]}], "control_points": [{"bone": "hand.L", "alpha": 1, "target": [0.5, -0.3, 1.2]}]}' "$src" > "$tmp/kdl_cp.json"
for solver in kdl kdl-nr; do
  check "solve $solver" 0 "$bin" solve "$tmp/kdl_cp.json" --solver $solver --out "$tmp/solve_$solver" --quiet
  expect_in "solve $solver summary" "$tmp/solve_$solver/summary.json" "\"solver\": \"$solver\""
  expect_in "solve $solver orientation" "$tmp/solve_$solver/summary.json" '"orientation_residual_rad"'
  check "$solver refuses an aim" 2 "$bin" solve "$tmp/aim_cp.json" --solver $solver --out "$tmp/x" --quiet
  expect_in "$solver aim refusal" "$tmp/err" "aim_cp.json: aim_targets: --solver kdl and kdl-nr take no aims"
  check "$solver refuses two goal bones" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver $solver --out "$tmp/x" --quiet
  expect_in "$solver two bones refusal" "$tmp/err" "solve one chain: their goals must be on one bone"
  check "$solver refuses a ground" 2 "$bin" solve "$tmp/floor_cp.json" --solver $solver --out "$tmp/x" --quiet
  expect_in "$solver ground refusal" "$tmp/err" "floor_cp.json: ground: --solver kdl and kdl-nr solve the rig's geometry"
done
# a goal on the torso: a chain of 5 axes, below what KDL's wdls solver takes (it aborted)
check "kdl-nr refuses a 5-axis chain" 2 "$bin" solve "$src/models/scenes/fig7_cannon_capped.json" --solver kdl-nr --out "$tmp/x" --quiet
expect_in "kdl-nr 5-axis refusal" "$tmp/err" "fig7_cannon_capped.json: solver: --solver kdl-nr needs at least 6 joint axes"
# the solve mode's step with the pose terms: an implicit-only --set is the run's on a scene of
# another scheme, the summary counts the Gauss-Newton retakes; a solver that runs the scene's
# scheme refuses it
check "solve mode full" 0 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver physik --set implicit_linearisation=full --out "$tmp/solve_full" --quiet
expect_in "solve mode full converged" "$tmp/solve_full/summary.json" '"converged": true'
expect_in "solve mode full retakes" "$tmp/solve_full/summary.json" '"implicit_gauss_newton_steps"'
check "solve explicit refuses full" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver physik-explicit --set implicit_linearisation=full --out "$tmp/solve_full2" --quiet
expect_in "solve explicit refuses full message" "$tmp/err" "applies to the implicit scheme only"
check "solve hybrid" 0 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver physik-explicit --finish dls --out "$tmp/solve_hyb" --quiet
expect_in "solve hybrid finish" "$tmp/solve_hyb/summary.json" '"finish": "dls"'
# the finish takes the classic solvers' flags: 15 physics steps, then DLS held to 2 iterations
printf '{"rig": "%s/models/rigs/pinhead.json", "control_points": [{"bone": "hand.L", "target": [0.6, -0.3, 1.0]}, {"bone": "hand.R", "target": [-0.6, -0.3, 1.0]}], "steps": 15}' "$src" > "$tmp/s15.json"
check "solve hybrid capped" 4 "$bin" solve "$tmp/s15.json" --solver physik-explicit --finish dls --max-iterations 2 --out "$tmp/solve_hyb2" --quiet
expect_in "solve hybrid capped says it fell short" "$tmp/err" "physik: not converged: the physics used the scene's steps after 15 steps, then the dls finish 2 iterations, at residual"
expect_in "solve hybrid out of steps" "$tmp/solve_hyb2/summary.json" '"out_of_steps": true'
expect_in "solve hybrid --max-iterations" "$tmp/solve_hyb2/summary.json" '"finish_iterations": 2'
# a solve short of its tolerance says so and exits 4, after writing its last pose and summary:
# DLS held to 2 iterations, and FABRIK after a target out of the elbow's reach (it stalls)
check "solve dls out of iterations" 4 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver dls --max-iterations 2 --out "$tmp/solve_short" --quiet
expect_in "solve dls out of iterations message" "$tmp/err" "physik: not converged: dls used its iterations (max_iterations) after 2 iterations at residual"
expect_in "solve dls out of iterations summary" "$tmp/solve_short/summary.json" '"not_converged_reason": "dls used its iterations'
expect_in "solve dls out of iterations pose" "$tmp/solve_short/final_pose.csv" "hand.L"
printf '{"rig": "%s/models/rigs/elbow.json", "control_points": [{"bone": "forearm", "alpha": 1, "target": [0, 0, 40]}]}' "$src" > "$tmp/far.json"
check "solve fabrik stalls" 4 "$bin" solve "$tmp/far.json" --solver fabrik --out "$tmp/solve_far" --quiet
expect_in "solve fabrik stalls message" "$tmp/err" "physik: not converged: fabrik stalled (the residual stopped improving)"
expect_in "solve converged has no reason" "$tmp/solve/summary.json" '"not_converged_reason": ""'
check "solve bad growth" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver physik --dt-growth 0.5 --out "$tmp/solve" --quiet
expect_in "solve bad growth message" "$tmp/err" "--dt-growth"
check "solve bad finish" 2 "$bin" solve "$src/models/scenes/pinhead_two_hands.json" --solver physik --finish newton --out "$tmp/solve" --quiet
expect_in "solve bad finish message" "$tmp/err" "--finish: unknown value 'newton' (expected none|"

# physik tune / equilibrium: Ceres tuning and exact equilibria
check "tune help" 0 "$bin" tune --help
check "equilibrium help" 0 "$bin" equilibrium --help
check "tune unknown param" 2 "$bin" tune "$src/models/scenes/pinhead_two_hands.json" --params damping,bogus --quiet
expect_in "tune unknown param message" "$tmp/err" "field 'bogus': unknown tunable parameter"
check "tune missing scene" 2 "$bin" tune "$tmp/none.json" --quiet
check "tune bad objective" 2 "$bin" tune "$src/models/scenes/pinhead_two_hands.json" --objective fast --quiet
check "tune bad bounds" 2 "$bin" tune "$src/models/scenes/pinhead_two_hands.json" --bounds damping=5:1 --quiet
# pinhead's own damping (3) settles at its step 89: the tuned one (0.77) has the lower objective
# (a faster approach) and settles later; both measures are said, and the exit is 4, the tuned
# scene written all the same, its rig path relative as the scene's was
check "tune" 4 "$bin" tune "$src/models/scenes/pinhead_two_hands.json" --scan-points 5 --max-iterations 5 --out "$tmp/tuned.json" --report "$tmp/tune_report.json" --quiet
expect_in "tune says both measures" "$tmp/out" "objective lower, convergence later: step "
# the tuned run did converge, later: stderr says so and never calls it "not converged"
expect_in "tune exits 4 saying why" "$tmp/err" "physik: converged later: tune: $src/models/scenes/pinhead_two_hands.json: the tuned run converges at step "
expect_in "tune names the scene's step" "$tmp/err" "later than the scene's (step 89); its objective is lower (J "
expect_absent "tune: a run that converged is not called not converged" "$tmp/err" "not converged"
expect_in "tune --quiet prints Ceres's brief" "$tmp/out" "ceres: Ceres Solver Report"
expect_absent "tune --quiet is quiet" "$tmp/out" "Solver Summary"
expect_in "tuned scene's rig stays relative" "$tmp/tuned.json" '"rig": "../'
# an underdamped pinhead (0.5) tunes to a damping that settles earlier: exit 0; Ceres's full
# report without --quiet
check "tune improving both" 0 "$bin" tune "$src/models/scenes/pinhead_two_hands.json" --set damping=0.5 --scan-points 5 --max-iterations 5
expect_in "tune prints Ceres's report" "$tmp/out" "Solver Summary"
expect_absent "tune improving both: no disagreement" "$tmp/out" "convergence later"
expect_in "tuned scene params" "$tmp/tuned.json" '"damping"'
expect_in "tune report values" "$tmp/tune_report.json" '"values"'
check "tuned scene runs" 0 "$bin" simulate "$tmp/tuned.json" --out "$tmp/tuned_run" --quiet
# damping auto: the baseline is the scene as simulate runs it (auto's choice), not damping 3
elbow="$src/models/scenes/fig6_elbow_linear.json"
check "tune a damping auto scene" 4 "$bin" tune "$elbow" --set damping=auto --scan-points 3 --max-iterations 2 --report "$tmp/tune_auto.json" --quiet
expect_in "tune names damping auto" "$tmp/out" "scene's damping: auto, resolved to"
expect_in "tune labels the auto baseline" "$tmp/out" "(scene, damping auto)"
check "simulate the damping auto scene" 0 "$bin" simulate "$elbow" --set damping=auto --out "$tmp/auto_run" --quiet
check "tune's baseline is simulate's run" 0 python3 - "$tmp/tune_auto.json" "$tmp/auto_run/summary.json" <<'PY'
import json, sys
rep, run = (json.load(open(f)) for f in sys.argv[1:3])
c = run["damping_auto_value"]
assert abs(rep["damping_auto"]["value_at_start"] - c) <= 1e-12 * c, (rep["damping_auto"], c)
assert abs(rep["initial_values"][0] - c) <= 1e-12 * c, (rep["initial_values"], c)
assert abs(c - 3.0) > 0.1, c  # auto is not the numeric default
assert rep["scene_run"]["steps_to_converge"] == run["steps_to_converge"], (rep["scene_run"], run)
# one choice (no target change): the fixed start runs the same scene as auto
assert abs(rep["start_cost"] - rep["initial_cost"]) <= 1e-9 * rep["initial_cost"], rep
assert rep["improved"] == (rep["final_cost"] < rep["initial_cost"]), rep
PY
check "equilibrium missing scene" 2 "$bin" equilibrium "$tmp/none.json"
check "equilibrium bad start" 2 "$bin" equilibrium "$src/models/scenes/pinhead_two_hands.json" --start middle
check "equilibrium" 0 "$bin" equilibrium "$src/models/scenes/pinhead_two_hands.json" --compare --start physik --out "$tmp/eq.json" --bones "$tmp/eq.csv"
expect_in "equilibrium converged" "$tmp/eq.json" '"converged": true'
expect_in "equilibrium physik gap" "$tmp/eq.json" '"max_pose_distance"'
expect_in "equilibrium bones" "$tmp/eq.csv" "hand.L"
# a minimisation that Ceres stops short of convergence is not a result: exit 4, its last iterate
# written and marked
check "equilibrium out of iterations" 4 "$bin" equilibrium "$src/models/scenes/pinhead_two_hands.json" --max-iterations 1 --out "$tmp/eq1.json"
expect_in "equilibrium out of iterations says so" "$tmp/err" "physik: not converged:"
expect_in "equilibrium out of iterations marks its output" "$tmp/eq1.json" '"converged": false'
check "equilibrium bad max-iterations" 2 "$bin" equilibrium "$src/models/scenes/pinhead_two_hands.json" --max-iterations 0
expect_in "equilibrium bad max-iterations names it" "$tmp/err" "--max-iterations"
check "equilibrium help lists exit 4" 0 "$bin" equilibrium --help
expect_in "equilibrium help lists exit 4" "$tmp/out" "4 not converged"

# robustness: absurd sizes, overflowing values, bad names, deep nesting, blow-ups
check "chain absurd size" 2 "$bin" rig chain 2147483647
expect_in "chain absurd message" "$tmp/err" "field 'N'"
printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [0,0,1], "radius": 1e200}]}' > "$tmp/r200.json"
check "radius 1e200" 2 "$bin" rig info --json "$tmp/r200.json"
expect_in "radius message" "$tmp/err" "r200.json: bones[0] 'a': field 'radius'"
check "to-bvh scale inf" 2 "$bin" rig to-bvh "$src/models/rigs/pinhead.json" --scale inf --out "$tmp/inf.bvh"
expect_in "to-bvh scale message" "$tmp/err" "--scale: must be a positive finite number"
printf 'HIERARCHY\nROOT A\xff\n{\n  OFFSET 0 0 0\n}\nMOTION\nFrames: 0\nFrame Time: 0.1\n' > "$tmp/utf.bvh"
check "bvh non-utf8 name" 2 "$bin" rig from-bvh "$tmp/utf.bvh"
expect_in "bvh name message" "$tmp/err" "utf.bvh: line 2: field 'joint name'"
printf 'HIERARCHY\nROOT A\n{\n  OFFSET 0 1e308 0\n}\n' > "$tmp/far.bvh"
check "bvh huge offset" 2 "$bin" rig from-bvh "$tmp/far.bvh"
expect_in "bvh offset message" "$tmp/err" "far.bvh: line 4: field 'OFFSET'"
python3 -c "print('{\"rig\": \"x.json\", \"params\": ' + '['*5000 + ']'*5000 + '}')" > "$tmp/deep.json"
check "deep json" 2 "$bin" simulate "$tmp/deep.json" --out "$tmp/x" --quiet
expect_in "deep json message" "$tmp/err" "deep.json: line 1: JSON nested deeper than 256"
check "pinhead damping 5 diverges" 3 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --set damping=5 --steps 300 --out "$tmp/d5" --quiet
expect_in "damping 5 reason" "$tmp/d5/summary.json" 'the rig was given'
check "hand_tight diverges" 3 "$bin" simulate "$src/models/scenes/hand_tight.json" --out "$tmp/ht" --quiet
printf '{"bones": [{"name": "a", "parent": null, "head": [0,0,0], "tail": [1,0,0]}, {"name": "b", "parent": "a", "head": [1,0,0], "tail": [2,0,0]}]}' > "$tmp/flat.json"
printf '{"rig": "flat.json", "control_points": [{"bone": "b", "target": [2,0,0]}], "steps": 30}' > "$tmp/flat_scene.json"
check "flat rig, target met" 0 "$bin" simulate "$tmp/flat_scene.json" --out "$tmp/flat" --quiet
expect_in "flat rig converged" "$tmp/flat/summary.json" '"converged": true'
"$bin" rig chain 1000 --out "$tmp/c1000.json"
printf '{"rig": "c1000.json", "params": {"preset": "original"}, "control_points": [{"bone": "b999", "target": [1,0,999.5]}], "steps": 2}' > "$tmp/c1000_scene.json"
check "chain joint solve warning" 0 "$bin" simulate "$tmp/c1000_scene.json" --out "$tmp/c1000" --quiet
expect_in "chain warning in summary" "$tmp/c1000/summary.json" '"joint_unpropagated_steps": 2'
expect_in "chain warning on stderr" "$tmp/err" "c1000_scene.json: the joint solve stopped before"
printf '{"bones": [{"name": "a\\"<b", "parent": null, "head": [0,0,0], "tail": [0,0,1]}, {"name": "c,d", "parent": "a\\"<b", "head": [0,0,1], "tail": [0,0,2]}]}' > "$tmp/names.json"
printf '{"rig": "names.json", "control_points": [{"bone": "c,d", "target": [0.5,0,1.5]}], "steps": 5}' > "$tmp/names_scene.json"
check "names with quote and comma" 0 "$bin" simulate "$tmp/names_scene.json" --out "$tmp/names" --quiet
expect_in "csv quotes a comma" "$tmp/names/final_pose.csv" '"c,d"'
check "mjcf escapes names" 0 "$bin" export-mjcf "$tmp/names.json" --out "$tmp/names.xml"
expect_in "mjcf quote entity" "$tmp/names.xml" 'name="a&quot;&lt;b"'
check "mjcf names load back" 0 "$bin" rig from-mjcf "$tmp/names.xml" --out "$tmp/names_back.json"
expect_in "mjcf name round trip" "$tmp/names_back.json" 'a\"<b'
"$bin" rig chain 6000 --out "$tmp/c6000.json"
check "mjcf too deep" 2 "$bin" export-mjcf "$tmp/c6000.json" --out "$tmp/c6000.xml"
expect_in "mjcf depth message" "$tmp/err" "c6000.json: field 'bones': the rig is 6000 bones deep"
check "to-bvh bad order" 2 "$bin" rig to-bvh "$src/models/rigs/pinhead.json" --order XXY
expect_in "bad order names the option" "$tmp/err" "--order: 'XXY' is not a permutation of XYZ"
check "convert bad order" 2 "$bin" bvh convert "$src/tests/fuzz/corpus/vtab_after_motion.bvh" "$tmp/o.bvh" --order ABC
expect_in "convert order names the option" "$tmp/err" "--order"
printf '{"rig": "%s.json", "steps": 2}' "$(printf 'a%.0s' $(seq 300))" > "$tmp/longpath.json"
check "rig path past NAME_MAX" 2 "$bin" simulate "$tmp/longpath.json" --out "$tmp/lp" --quiet
expect_in "long path names the scene" "$tmp/err" "longpath.json: field 'rig'"
printf '{"rig": "flat.json", "control_points": [{"bone": "b", "target": [1e155,0,0], "k": 10}], "steps": 5}' > "$tmp/far_target.json"
check "target 1e155 refused" 2 "$bin" simulate "$tmp/far_target.json" --out "$tmp/ft" --quiet
expect_in "far target message" "$tmp/err" "far_target.json: control_points[0]: field 'target'"

# defaults and honest tools: a scene that names no preset runs the robust preset; explicit
# values are the ones used; failures exit non-zero and print no result
printf '{"rig": "%s/models/rigs/pinhead.json", "control_points": [{"name": "reach", "bone": "hand.L", "target": [1.2, -0.6, 1.4]}], "steps": 300}' "$src" > "$tmp/plain.json"
check "no preset: robust converges" 0 "$bin" simulate "$tmp/plain.json" --out "$tmp/plain" --quiet
expect_in "no preset is robust" "$tmp/plain/summary.json" '"preset": "robust"'
expect_in "robust damping is auto" "$tmp/plain/summary.json" '"damping": "auto"'
expect_in "robust reports its choice" "$tmp/plain/summary.json" '"damping_auto_value"'
expect_in "progress shows substeps" "$tmp/plain/trajectory.csv" 'residual_reach'
check "explicit damping turns auto off" 0 "$bin" simulate "$tmp/plain.json" --out "$tmp/plain1" --quiet --set damping=1
expect_in "explicit damping is the used one" "$tmp/plain1/summary.json" '"damping": 1.0'
check "gauss-seidel setting under implicit" 2 "$bin" simulate "$tmp/plain.json" --out "$tmp/x" --set max_passes=10
expect_in "inapplicable setting message" "$tmp/err" "--set: field 'max_passes': applies to the gauss-seidel scheme only (this run: scheme implicit)"
check "unknown preset" 2 "$bin" simulate "$tmp/plain.json" --out "$tmp/x" --set preset=fast
expect_in "unknown preset message" "$tmp/err" "unknown preset 'fast' (original|paper|robust)"
check "damping of a wrong kind" 2 "$bin" simulate "$tmp/plain.json" --out "$tmp/x" --set damping=lots
expect_in "damping kind message" "$tmp/err" "--set: params: field 'damping': expected a number, got 'lots'"
expect_in "diverged message hints" "$tmp/div/summary.json" '"divergence_hint": "try --set preset=robust'
check "diverged hint on stderr" 3 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --out "$tmp/div2" --set damping=20 --quiet
expect_in "diverged hint names less damping" "$tmp/err" "or damping below"
touch "$tmp/afile"
check "unwritable --out" 2 "$bin" simulate "$tmp/plain.json" --out "$tmp/afile/run" --quiet
expect_in "unwritable --out names the path" "$tmp/err" "afile/run: field '--out': cannot create the folder"
check "unwritable solve --out" 2 "$bin" solve "$tmp/plain.json" --solver dls --out "$tmp/afile/solve" --quiet
check "unwritable tune --out" 2 "$bin" tune "$tmp/plain.json" --out "$tmp/afile/t.json" --quiet
expect_in "tune --out checked first" "$tmp/err" "afile: field '--out': cannot create the folder"
check "export-mjcf --dt 1e999" 2 "$bin" export-mjcf "$src/models/rigs/chain3.json" --dt 1e999
expect_in "non-finite dt message" "$tmp/err" "--dt: must be a positive finite number"
check "solve --tol 1e999" 2 "$bin" solve "$tmp/plain.json" --solver dls --tol 1e999 --out "$tmp/x"
expect_in "non-finite tol message" "$tmp/err" "--tol: must be a finite number >= 0"
check "solve --set" 0 "$bin" solve "$tmp/plain.json" --solver physik --set torsion_k=20 --out "$tmp/solve_set" --quiet
expect_in "solve --set reaches the params" "$tmp/solve_set/summary.json" '"torsion_k": 20.0'
check "solve mode refuses an explicit explicit scheme" 2 "$bin" solve "$tmp/plain.json" --solver physik --set scheme=gauss-seidel --out "$tmp/x"
expect_in "solve mode integration message" "$tmp/err" "the solve mode is the implicit step"
check "equilibrium --set" 0 "$bin" equilibrium "$tmp/plain.json" --set torsion_k=20 --out "$tmp/eq.json"
check "equilibrium --compare on a diverging run" 3 "$bin" equilibrium "$src/models/scenes/pinhead_two_hands.json" --compare --set damping=20 --out "$tmp/eqd.json"
expect_in "compare says it diverged" "$tmp/err" "PhysIK's run diverged"
expect_in "compare prints no distance" "$tmp/eqd.json" '"max_pose_distance": null'
check "reference with a diverging run" 3 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --set damping=20 --reference mujoco --out "$tmp/refd" --quiet
expect_in "reference says which diverged" "$tmp/err" "no gap to report"
expect_in "reference gap is null" "$tmp/refd/comparison.json" '"final_pose_gap": null'
check "tune where every candidate diverges" 3 "$bin" tune "$src/models/scenes/pinhead_two_hands.json" --bounds damping=20:100 --scan-points 3 --max-iterations 2 --steps 60 --out "$tmp/tuned_diverging.json" --quiet
expect_in "tune says nothing tuned" "$tmp/err" "nothing tuned"
[ ! -e "$tmp/tuned_diverging.json" ] && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL tune wrote a diverging scene"; }
check "tune a setting the scheme ignores" 2 "$bin" tune "$tmp/plain.json" --params torsion_cap --quiet
expect_in "tune ignored setting message" "$tmp/err" "--params: field 'torsion_cap': applies to capped torsion springs only"
check "params fits 100 columns" 0 "$bin" params
awk 'length > 100 { bad = 1 } END { exit bad }' "$tmp/out" && pass=$((pass+1)) || { fail=$((fail+1)); echo "FAIL params wider than 100 columns"; }
expect_in "params shows robust" "$tmp/out" "robust"
# a state that goes non-finite at step 1 leaves the initial one as its final pose, never NaN
for scheme in preset=original preset=robust joint_solve=exact integration=free-rods; do
  check "control_k 1e308 ($scheme)" 3 "$bin" simulate "$src/models/scenes/pinhead_two_hands.json" --set control_k=1e308 --set "$scheme" --out "$tmp/k308" --quiet
  if grep -qiE 'nan|inf' "$tmp/k308/final_pose.csv" "$tmp/k308/trajectory.csv"; then
    fail=$((fail+1)); echo "FAIL control_k 1e308 ($scheme): non-finite output"; else pass=$((pass+1)); fi
  expect_in "control_k 1e308 ($scheme) final pose" "$tmp/k308/summary.json" '"final_pose_step": 0'
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
