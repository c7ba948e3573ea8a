// The PhysIK run viewer: plays one or more run folders (physik/io/run_folder.h) in 3D with
// three.js r111 (Debian's libjs-three) and its OrbitControls. `physik view` inlines this file
// into viewer/page.html beside the runs' data (viewer/view_page.h gives the data's layout).
//
// - each bone is a capsule of the bone's radius (a cylinder from head to tail and a sphere at
//   each end), drawn with instanced meshes: four draw calls per run whatever its size;
// - the runs share one timeline, the union of their recorded times: at time t each run shows
//   its last frame at or before t (a run that stopped early holds its last pose; a pose folder,
//   one frame, shows at every time);
// - a bone whose joint angle is past a limit by more than LIMIT_SHOWN_RAD keeps its run's
//   colour and gets an outline in HIGHLIGHT (a larger capsule drawn from its back faces), so an
//   overlay still tells the runs apart (the excess comes from targets_and_limits.csv: a bone's
//   twist cannot be seen in its head and tail);
// - the "axes and limits" toggle (off at first) draws each bone's local axes at its head (x, y,
//   z in AXIS_COLORS, 0.3 of its length; from the bone orientations of targets_and_limits.csv)
//   and, for each limited axis, the limit's range as a fan at the head: the bone's direction
//   (for the y axis, its twist: the x axis) turned about that axis of the frame its parent
//   carries from min to max, the range of a turn about that axis alone (limits are intervals on
//   the rotation vector's components, rig.h);
// - targets are drawn in TARGET_COLOR, whatever their run (the spring to each is the run's);
// - a scene's bone targets (scene.h; they hold still through a run) are drawn with the targets
//   and hidden with them: an orientation target as a triad at its bone's head in the target
//   frame (x, y, z in AXIS_COLORS, TARGET_AXES_LENGTH of the bone's length, dashed: the bone's
//   own axes are the solid ones), an aim as a line from its bone's head to the point, in the
//   run's colour, with a TARGET_COLOR marker at the point, a pin as a TARGET_COLOR cube at its
//   point; the camera frames the aims' and pins' points;
// - a floor grid only where a run's scene has a ground, in the ground's plane;
// - a run folder with contacts.csv gets its contacts drawn at each frame: a sphere at the
//   contact point and a line along the normal, of a fixed length (a tenth of the scene's size:
//   an impact's force and a resting one differ by orders of magnitude, so a line scaled by the
//   force hides the resting contacts), in CONTACT_COLOR, over the bodies; the readout gives the
//   count and the largest normal force;
// - a scene's box obstacles (scene.h BoxObstacle: centre, half extents along the box's own axes,
//   the rotation turning those axes into the world) are translucent lit boxes in BOX_COLOR with
//   opaque edges, each in its own frame; a box several runs' scenes share is drawn once. The
//   camera frames them with the rig and its targets;
// - names come from user files: they are only ever set as text (textContent), never as markup;
// - the page's URL may choose how it opens, so that a screenshot can show a result: ?frame=N
//   opens at frame N (from 1, as the label counts; past the last: the last), ?frame=last at the
//   last frame, ?play=1 plays on load (both together: plays from frame N).
// World Z is up (the rigs' convention); the camera starts in front of the rig (-Y).
(function () {
  'use strict';

  var PALETTE = ['#1f77b4', '#ff7f0e', '#2ca02c', '#9467bd', '#8c564b', '#17becf', '#7f7f7f',
                 '#bcbd22'];
  var HIGHLIGHT = '#e6194b';
  var OUTLINE_SCALE = 1.45;  // the limit outline's radius, of the bone's
  var TARGET_COLOR = '#000000';
  var AXIS_COLORS = ['#ff2a2a', '#1fbf1f', '#2a5cff'];  // local x, y, z
  var AXES_LENGTH = 0.3;  // of the bone's length
  var TARGET_AXES_LENGTH = 0.6;  // an orientation target's triad, of its bone's length
  var ARC_SEGMENTS = 16;
  var CONTACT_COLOR = '#ff00ff';
  var BOX_COLOR = '#d4a017', BOX_EDGE_COLOR = '#8a6a0f', BOX_OPACITY = 0.5;
  var LIMIT_SHOWN_RAD = 0.1 * Math.PI / 180;  // 0.1 deg: round-off never lights a bone
  var SPEEDS = [0.1, 0.25, 0.5, 1, 2, 5, 10, 20, 50, 100];
  var Y_AXIS = new THREE.Vector3(0, 1, 0);

  // --- data ---------------------------------------------------------------------------------

  function decode(text, Type) {
    var bin = atob(text);
    var bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  function prepareRun(raw, index) {
    var run = {
      raw: raw, index: index, color: PALETTE[index % PALETTE.length],
      nbone: raw.bones.names.length, ncontrol: raw.control_points.names.length,
      steps: decode(raw.steps, Int32Array), times: decode(raw.times, Float64Array),
      ke: decode(raw.kinetic_energy, Float32Array),
      maxResidual: decode(raw.max_residual, Float32Array),
      maxResidualPoint: decode(raw.max_residual_point, Int32Array),
      positions: decode(raw.positions, Float32Array),
      targets: decode(raw.targets, Float32Array),
      excess: raw.limit_excess === null ? null : decode(raw.limit_excess, Float32Array),
      orient: raw.orientations ? decode(raw.orientations, Float32Array) : null,
      contacts: null
    };
    run.nframe = run.steps.length;
    if (raw.contacts) {
      run.contacts = { start: decode(raw.contacts.start, Int32Array),
                       bones: decode(raw.contacts.bones, Int32Array),
                       values: decode(raw.contacts.values, Float32Array) };
    }
    return run;
  }

  // The union of the runs' times, and for each run its frame at each timeline entry.
  function buildTimeline(runs) {
    var all = [];
    runs.forEach(function (r) { for (var i = 0; i < r.nframe; i++) all.push(r.times[i]); });
    all.sort(function (a, b) { return a - b; });
    var times = [];
    all.forEach(function (t) {
      var last = times.length ? times[times.length - 1] : null;
      if (last === null || t - last > 1e-9 * Math.max(1, Math.abs(t))) times.push(t);
    });
    runs.forEach(function (r) {
      r.frameAt = new Int32Array(times.length);
      var j = 0;
      for (var i = 0; i < times.length; i++) {
        var eps = 1e-9 * Math.max(1, Math.abs(times[i]));
        while (j + 1 < r.nframe && r.times[j + 1] <= times[i] + eps) j++;
        r.frameAt[i] = j;
      }
    });
    return times;
  }

  // --- page elements (text only) ------------------------------------------------------------

  function el(tag, className, text) {
    var e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== undefined) e.textContent = String(text);
    return e;
  }

  function swatch(color) {
    var s = el('span', 'swatch');
    s.style.background = color;
    return s;
  }

  function runDetail(run) {
    var raw = run.raw, sum = raw.summary, parts = [];
    if (raw.rig) parts.push('rig ' + raw.rig);
    if (sum.engine) parts.push(sum.engine + (sum.mode ? ' ' + sum.mode : ''));
    if (sum.kind === 'pose') {
      parts.push('one pose' + (sum.solver ? ' (' + sum.solver + ')' : ''));
      if (sum.converged === false && !sum.diverged) parts.push('not converged');
      // a solve's goals short of their tolerance, each by how much (its summary's short_goals)
      (sum.short_goals || []).forEach(function (g) {
        parts.push('short: ' + g.goal + ' ' + Number(g.residual).toPrecision(3) + ' ' + g.unit +
                   ' (tolerance ' + Number(g.tolerance).toPrecision(3) + ')');
      });
    } else {
      parts.push(run.nframe + ' frames');
      if (sum.diverged) parts.push('diverged');
      else if (sum.converged === true) parts.push('converged at step ' + sum.steps_to_converge);
      else if (sum.converged === false) parts.push('not converged');
    }
    return parts.join(', ');
  }

  function buildLegend(v) {
    var legend = el('div', 'legend');
    v.runs.forEach(function (run) {
      var item = el('span', 'run');
      item.appendChild(swatch(run.color));
      item.appendChild(el('span', 'label', run.raw.label));
      item.appendChild(el('span', 'detail', runDetail(run)));
      legend.appendChild(item);
    });
    var hi = el('span', 'run');
    hi.appendChild(swatch(HIGHLIGHT));
    hi.appendChild(el('span', 'label', 'outline: past a joint limit (by more than 0.1 deg)'));
    legend.appendChild(hi);
    if (v.runs.some(function (r) { return r.ncontrol > 0; })) {
      var tg = el('span', 'run');
      tg.appendChild(swatch(TARGET_COLOR));
      tg.appendChild(el('span', 'label', 'target'));
      legend.appendChild(tg);
    }
    if (anyContacts(v)) {
      var ct = el('span', 'run');
      ct.appendChild(swatch(CONTACT_COLOR));
      ct.appendChild(el('span', 'label', 'contact: the point and its normal'));
      legend.appendChild(ct);
    }
    var boxes = sceneBoxes(v);
    if (boxes.length) {
      var bx = el('span', 'run');
      bx.appendChild(swatch(BOX_COLOR));
      bx.appendChild(el('span', 'label', (boxes.length === 1 ? 'obstacle: ' : 'obstacles: ') +
          boxes.map(function (b) { return b.name; }).join(', ')));
      legend.appendChild(bx);
    }
    return legend;
  }

  function buildControls(v) {
    var c = el('div', 'controls');
    v.playButton = el('button', 'play', 'Play');
    v.playButton.type = 'button';
    v.playButton.addEventListener('click', function () { v.playing ? v.pause() : v.play(); });
    v.slider = el('input', 'frame');
    v.slider.type = 'range';
    v.slider.min = 0;
    v.slider.max = Math.max(0, v.times.length - 1);
    v.slider.step = 1;
    v.slider.value = 0;
    v.slider.disabled = v.times.length < 2;
    v.slider.setAttribute('aria-label', 'frame');
    v.slider.addEventListener('input', function () {
      v.pause();
      v.setFrame(parseInt(v.slider.value, 10));
    });
    v.timeLabel = el('span', 'time');
    c.appendChild(v.playButton);
    c.appendChild(v.slider);
    c.appendChild(v.timeLabel);
    c.appendChild(buildSpeed(v));
    c.appendChild(buildThickness(v));
    c.appendChild(checkbox('targets', true, function (on) { v.setTargetsShown(on); }));
    if (anyOrientations(v)) {
      c.appendChild(checkbox('axes and limits', false, function (on) { v.setAxesShown(on); }));
    }
    c.appendChild(checkbox('target paths', true, function (on) { v.setPathsShown(on); }));
    if (anyContacts(v)) {
      c.appendChild(checkbox('contacts', true, function (on) { v.setContactsShown(on); }));
    }
    if (sceneBoxes(v).length) {
      c.appendChild(checkbox('obstacles', true, function (on) { v.setBoxesShown(on); }));
    }
    return c;
  }

  function buildSpeed(v) {
    var label = el('label', 'speed', 'speed ');
    var select = el('select');
    var duration = v.times.length ? v.times[v.times.length - 1] - v.times[0] : 0;
    // the slowest speed that plays the whole timeline within 20 s (real time when it can)
    v.speed = SPEEDS[SPEEDS.length - 1];
    for (var i = 0; i < SPEEDS.length; i++) {
      if (SPEEDS[i] >= 1 && duration / SPEEDS[i] <= 20) { v.speed = SPEEDS[i]; break; }
    }
    SPEEDS.forEach(function (s) {
      var o = el('option', null, s + '\u00d7');
      o.value = s;
      o.selected = s === v.speed;
      select.appendChild(o);
    });
    select.addEventListener('change', function () { v.speed = parseFloat(select.value); });
    label.appendChild(select);
    return label;
  }

  // capsules at the bones' radii (the radius the inertias use), or thinner to see through
  function buildThickness(v) {
    var label = el('label', 'thickness', 'radius ');
    var select = el('select');
    v.radiusScale = 1;
    [1, 0.5, 0.25, 0.1].forEach(function (s) {
      var o = el('option', null, s === 1 ? 'the bones\u2019 radii' : s + '\u00d7 the radii');
      o.value = s;
      select.appendChild(o);
    });
    select.addEventListener('change', function () {
      v.radiusScale = parseFloat(select.value);
      v.setFrame(v.frame);
    });
    label.appendChild(select);
    return label;
  }

  function checkbox(text, checked, onChange) {
    var label = el('label', 'toggle');
    var box = el('input');
    box.type = 'checkbox';
    box.checked = checked;
    box.addEventListener('change', function () { onChange(box.checked); });
    label.appendChild(box);
    label.appendChild(document.createTextNode(' ' + text));
    return label;
  }

  function anyOrientations(v) {
    return v.runs.some(function (r) { return r.orient !== null; });
  }

  function anyContacts(v) {
    return v.runs.some(function (r) { return r.contacts !== null; });
  }

  // every run's box obstacles, a box that several runs give (the same numbers) once
  function sceneBoxes(v) {
    var seen = {}, out = [];
    v.runs.forEach(function (r) {
      (r.raw.boxes || []).forEach(function (b) {
        var key = JSON.stringify([b.center, b.half_extents, b.quaternion]);
        if (!seen[key]) {
          seen[key] = true;
          out.push(b);
        }
      });
    });
    return out;
  }

  var READOUT_COLUMNS = ['run', 'step', 'time (s)', 'kinetic energy (J)',
                         'largest residual (rig units)', 'past a joint limit', 'contacts'];

  function buildReadout(v) {
    var table = el('table', 'readout');
    var head = el('tr');
    READOUT_COLUMNS.forEach(function (c) { head.appendChild(el('th', null, c)); });
    table.appendChild(el('thead')).appendChild(head);
    var body = el('tbody');
    v.runs.forEach(function (run) {
      var tr = el('tr');
      var name = el('td');
      name.appendChild(swatch(run.color));
      name.appendChild(el('span', null, run.raw.label));
      tr.appendChild(name);
      run.cells = [];
      for (var k = 1; k < READOUT_COLUMNS.length; k++) run.cells.push(tr.appendChild(el('td')));
      body.appendChild(tr);
    });
    table.appendChild(body);
    return table;
  }

  function buildNotes(v, data) {
    var ul = el('ul', 'notes');
    v.runs.forEach(function (run) {
      run.raw.notes.forEach(function (n) {
        ul.appendChild(el('li', null, run.raw.label + ': ' + n));
      });
    });
    ul.appendChild(el('li', null, 'Drag to orbit, wheel to zoom, right-drag to pan. World Z up, ' +
        'rig units; capsules have the bones\u2019 radii. Each run shows its last frame at or ' +
        'before the time on the slider. ' + data.generator + ', three.js r' +
        data.three_revision + ' inlined.'));
    return ul;
  }

  // --- 3D -------------------------------------------------------------------------------------

  function instanced(geometry, material, count) {
    var m = new THREE.InstancedMesh(geometry, material, Math.max(1, count));
    m.frustumCulled = false;  // the geometry's bounds are not the instances'
    m.count = 0;
    return m;
  }

  function buildRunMeshes(v, run) {
    var mat = new THREE.MeshLambertMaterial({ color: run.color });
    // the outline: the back faces of a larger capsule, a rim around the bone's own colour
    var rim = new THREE.MeshBasicMaterial({ color: HIGHLIGHT, side: THREE.BackSide });
    run.meshes = {
      cyl: instanced(v.cylinder, mat, run.nbone), sph: instanced(v.sphere, mat, 2 * run.nbone),
      cylRim: instanced(v.cylinder, rim, run.nbone), sphRim: instanced(v.sphere, rim, 2 * run.nbone)
    };
    Object.keys(run.meshes).forEach(function (k) { v.scene.add(run.meshes[k]); });
    buildTargets(v, run);
    buildContacts(v, run);
    buildAxes(v, run);
  }

  // each bone's local axes (3 segments) and its limits' fans (an arc and its two end radii per
  // limited axis that is not locked), coloured per axis; hidden until the toggle shows them
  function buildAxes(v, run) {
    if (run.orient === null) return;
    var limits = run.raw.bones.limits, narc = 0;
    run.fans = [];
    for (var b = 0; b < run.nbone; b++) {
      for (var k = 0; k < 3; k++) {
        var l = limits[b][k];
        if (l && l[1] > l[0]) run.fans.push({ bone: b, axis: k, min: l[0], max: l[1] });
      }
    }
    narc = run.fans.length;
    var nseg = 3 * run.nbone + narc * (ARC_SEGMENTS + 2);
    var geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * nseg), 3));
    var colors = new Float32Array(6 * nseg), c = new THREE.Color(), at = 0;
    function paint(color, segments) {
      c.set(color);
      for (var i = 0; i < 2 * segments; i++, at += 3) c.toArray(colors, at);
    }
    for (var b2 = 0; b2 < run.nbone; b2++) {
      for (var k2 = 0; k2 < 3; k2++) paint(AXIS_COLORS[k2], 1);
    }
    run.fans.forEach(function (f) { paint(AXIS_COLORS[f.axis], ARC_SEGMENTS + 2); });
    geo.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    run.axes = new THREE.LineSegments(
        geo, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors, depthTest: false }));
    run.axes.renderOrder = 3;  // over the bodies: an axis inside a capsule is still seen
    run.axes.frustumCulled = false;
    run.axes.visible = false;
    v.scene.add(run.axes);
  }

  // a sphere per contact and a line along its normal, as many as the busiest frame has; drawn
  // over the bodies (the point lies inside a capsule or under the floor)
  function buildContacts(v, run) {
    var c = run.contacts;
    if (c === null) return;
    var most = 0;
    for (var f = 0; f < run.nframe; f++) most = Math.max(most, c.start[f + 1] - c.start[f]);
    run.contactSize = 0.02 * v.extent;
    run.contactLength = 0.1 * v.extent;
    var mat = new THREE.MeshBasicMaterial({ color: CONTACT_COLOR, depthTest: false });
    run.contactGroup = new THREE.Group();
    run.contactDots = instanced(v.sphere, mat, most);
    run.contactDots.renderOrder = 2;
    var geo = new THREE.BufferGeometry();
    var ends = new Float32Array(6 * Math.max(1, most));  // the point and the normal's end
    geo.setAttribute('position', new THREE.BufferAttribute(ends, 3));
    run.contactLines = new THREE.LineSegments(
        geo, new THREE.LineBasicMaterial({ color: CONTACT_COLOR, depthTest: false }));
    run.contactLines.renderOrder = 2;
    run.contactLines.frustumCulled = false;
    run.contactGroup.add(run.contactDots);
    run.contactGroup.add(run.contactLines);
    v.scene.add(run.contactGroup);
  }

  function buildTargets(v, run) {
    var size = 0.025 * v.extent;
    // drawn over the bodies (no depth test): a target inside a capsule is still seen
    var basic = new THREE.MeshBasicMaterial({ color: TARGET_COLOR, depthTest: false });
    run.targetGroup = new THREE.Group();
    run.targetMarks = [];
    for (var c = 0; c < run.ncontrol; c++) {
      var mark = new THREE.Mesh(new THREE.OctahedronBufferGeometry(size), basic);
      mark.renderOrder = 1;
      run.targetMarks.push(mark);
      run.targetGroup.add(mark);
    }
    var springGeo = new THREE.BufferGeometry();
    var ends = new Float32Array(6 * run.ncontrol);  // attachment point and target per point
    springGeo.setAttribute('position', new THREE.BufferAttribute(ends, 3));
    run.springs = new THREE.LineSegments(
        springGeo, new THREE.LineBasicMaterial({ color: run.color, depthTest: false }));
    run.springs.renderOrder = 1;
    run.springs.frustumCulled = false;
    run.targetGroup.add(run.springs);
    v.scene.add(run.targetGroup);
    run.pathGroup = buildPaths(v, run);
    v.scene.add(run.pathGroup);
    buildBoneTargets(v, run);
  }

  // the scene's bone targets, in the target group (the "targets" toggle hides them): the triads
  // (3 segments each, coloured per axis, dashed) and the aims' lines (1 segment each) move with
  // their bones' heads (placeBoneTargets); the aims' points and the pins are fixed markers
  function buildBoneTargets(v, run) {
    var bt = run.raw.bone_targets;
    if (!bt) return;
    var size = 0.02 * v.extent;
    var basic = new THREE.MeshBasicMaterial({ color: TARGET_COLOR, depthTest: false });
    function marker(geometry, point) {
      var m = new THREE.Mesh(geometry, basic);
      m.position.fromArray(point);
      m.renderOrder = 1;
      run.targetGroup.add(m);
    }
    bt.pins.forEach(function (p) { marker(new THREE.BoxBufferGeometry(size, size, size), p.point); });
    bt.aims.forEach(function (a) { marker(new THREE.SphereBufferGeometry(0.5 * size, 8, 6), a.point); });
    var ntriad = 3 * bt.orientations.length;
    if (ntriad > 0) {
      var geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * ntriad), 3));
      var colors = new Float32Array(6 * ntriad), c = new THREE.Color();
      for (var i = 0; i < ntriad; i++) {
        c.set(AXIS_COLORS[i % 3]);
        c.toArray(colors, 6 * i);
        c.toArray(colors, 6 * i + 3);
      }
      geo.setAttribute('color', new THREE.BufferAttribute(colors, 3));
      run.triads = new THREE.LineSegments(geo, new THREE.LineDashedMaterial({
        vertexColors: THREE.VertexColors, depthTest: false, dashSize: 0.01 * v.extent,
        gapSize: 0.006 * v.extent }));
      run.triads.renderOrder = 3;
      run.triads.frustumCulled = false;
      run.targetGroup.add(run.triads);
    }
    if (bt.aims.length > 0) {
      var aimGeo = new THREE.BufferGeometry();
      aimGeo.setAttribute('position',
                          new THREE.BufferAttribute(new Float32Array(6 * bt.aims.length), 3));
      run.aimLines = new THREE.LineSegments(
          aimGeo, new THREE.LineBasicMaterial({ color: run.color, depthTest: false }));
      run.aimLines.renderOrder = 1;
      run.aimLines.frustumCulled = false;
      run.targetGroup.add(run.aimLines);
    }
  }

  // each control point's target over the whole run, where it moves
  function buildPaths(v, run) {
    var group = new THREE.Group();
    var mat = new THREE.LineDashedMaterial(
        { color: run.color, dashSize: 0.012 * v.extent, gapSize: 0.008 * v.extent });
    for (var c = 0; c < run.ncontrol; c++) {
      var pts = [], moved = false;
      for (var f = 0; f < run.nframe; f++) {
        var o = (f * run.ncontrol + c) * 3;
        var p = new THREE.Vector3(run.targets[o], run.targets[o + 1], run.targets[o + 2]);
        if (!isFinite(p.x) || !isFinite(p.y) || !isFinite(p.z)) continue;
        if (pts.length && p.distanceTo(pts[0]) > 1e-9) moved = true;
        if (!pts.length || p.distanceTo(pts[pts.length - 1]) > 1e-9) pts.push(p);
      }
      if (!moved) continue;
      var line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts), mat);
      line.computeLineDistances();
      line.frustumCulled = false;
      group.add(line);
    }
    return group;
  }

  // The rig's bounds at every run's first frame, with every target and the corners of every box
  // obstacle: what the camera frames.
  function initialBounds(v) {
    var runs = v.runs, box = new THREE.Box3(), p = new THREE.Vector3(), maxRadius = 0;
    sceneBoxes(v).forEach(function (b) {
      var q = new THREE.Quaternion().fromArray(b.quaternion).normalize();
      for (var k = 0; k < 8; k++) {
        p.set(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1).multiply(
            new THREE.Vector3().fromArray(b.half_extents));
        box.expandByPoint(p.applyQuaternion(q).add(new THREE.Vector3().fromArray(b.center)));
      }
    });
    runs.forEach(function (r) {
      for (var k = 0; k < 2 * r.nbone; k++) {
        box.expandByPoint(p.fromArray(r.positions, 3 * k));
      }
      r.raw.bones.radii.forEach(function (x) { maxRadius = Math.max(maxRadius, x); });
      for (var i = 0; i + 2 < r.targets.length; i += 3) {
        p.fromArray(r.targets, i);
        if (isFinite(p.x) && isFinite(p.y) && isFinite(p.z)) box.expandByPoint(p);
      }
      var bt = r.raw.bone_targets;
      if (bt) {
        bt.aims.concat(bt.pins).forEach(function (t) { box.expandByPoint(p.fromArray(t.point)); });
      }
    });
    box.expandByScalar(maxRadius);
    return box;
  }

  // the ground plane of the first run whose scene has one: a translucent square through the
  // plane's point nearest the rig's centre, facing along the plane's normal
  function buildGround(v) {
    var g = null;
    v.runs.forEach(function(r) {
      if (!g && r.raw.ground) g = r.raw.ground;
    });
    if (!g) return;
    var n = new THREE.Vector3().fromArray(g.normal).normalize();
    var floor = new THREE.Mesh(
        new THREE.PlaneBufferGeometry(2 * v.extent, 2 * v.extent), new THREE.MeshLambertMaterial({
          color: 0x8d96a3,
          transparent: true,
          opacity: 0.45,
          side: THREE.DoubleSide,
          depthWrite: false
        }));
    floor.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
    var off = n.dot(v.center) - g.height;
    floor.position.copy(v.center).addScaledVector(n, -off);
    v.scene.add(floor);
    // the grid lies in the ground's plane (a scene without a ground has none: no floor to show)
    var grid = new THREE.GridHelper(2 * v.extent, 20, 0xb8bcc6, 0xd6d9e0);
    grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), n);  // the grid's plane is XZ
    grid.position.copy(floor.position);
    v.grid = grid;
    v.scene.add(grid);
  }

  // each box obstacle in its own frame: a box of its full sides along its axes, turned by its
  // rotation and moved to its centre (world frame, rig units)
  function buildBoxes(v) {
    v.boxGroup = new THREE.Group();
    var faces = new THREE.MeshLambertMaterial({ color: BOX_COLOR, transparent: true,
                                               opacity: BOX_OPACITY, depthWrite: false });
    var edges = new THREE.LineBasicMaterial({ color: BOX_EDGE_COLOR });
    sceneBoxes(v).forEach(function (b) {
      var h = b.half_extents, q = b.quaternion;
      var geo = new THREE.BoxBufferGeometry(2 * h[0], 2 * h[1], 2 * h[2]);
      var box = new THREE.Group();
      box.add(new THREE.Mesh(geo, faces));
      box.add(new THREE.LineSegments(new THREE.EdgesGeometry(geo), edges));
      box.position.fromArray(b.center);
      box.quaternion.set(q[0], q[1], q[2], q[3]).normalize();
      v.boxGroup.add(box);
    });
    v.scene.add(v.boxGroup);
  }

  function buildScene(v) {
    v.scene = new THREE.Scene();
    v.scene.background = new THREE.Color(0xf4f5f7);
    v.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f99, 0.75));
    var sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(0.4, -1, 1.2);
    v.scene.add(sun);
    var box = initialBounds(v);
    v.center = box.getCenter(new THREE.Vector3());
    v.extent = Math.max(1e-6, box.getSize(new THREE.Vector3()).length());
    buildGround(v);
    buildBoxes(v);
    v.cylinder = new THREE.CylinderBufferGeometry(1, 1, 1, 10, 1, true);
    v.sphere = new THREE.SphereBufferGeometry(1, 10, 7);
    v.runs.forEach(function (run) { buildRunMeshes(v, run); });
  }

  function buildCamera(v, canvas) {
    v.camera = new THREE.PerspectiveCamera(35, 1, v.extent / 1000, v.extent * 100);
    v.camera.up.set(0, 0, 1);
    var dir = new THREE.Vector3(0.35, -1, 0.3).normalize();
    var dist = 0.5 * v.extent / Math.tan(0.5 * 35 * Math.PI / 180);
    v.camera.position.copy(v.center).addScaledVector(dir, dist);
    v.controls = new THREE.OrbitControls(v.camera, canvas);
    v.controls.target.copy(v.center);
    v.controls.update();
    v.controls.addEventListener('change', function () { v.requestRender(); });
  }

  // --- one frame ----------------------------------------------------------------------------

  var tmp = { m: new THREE.Matrix4(), q: new THREE.Quaternion(), one: new THREE.Quaternion(),
              h: new THREE.Vector3(), t: new THREE.Vector3(), mid: new THREE.Vector3(),
              d: new THREE.Vector3(), s: new THREE.Vector3() };

  function hot(run, f, b) {
    return run.excess !== null && run.excess[f * run.nbone + b] > LIMIT_SHOWN_RAD;
  }

  // a bone's head sphere is drawn unless its parent's tail sphere, as large, is already there
  function headShown(run, f, b, r, scale) {
    var p = run.raw.bones.parents[b];
    if (p < 0 || run.raw.bones.radii[p] * scale < r) return true;
    var o = (f * run.nbone + b) * 6, q = (f * run.nbone + p) * 6 + 3, gap = 0;
    for (var k = 0; k < 3; k++) {
      gap = Math.max(gap, Math.abs(run.positions[o + k] - run.positions[q + k]));
    }
    return gap > 1e-6 * r;
  }

  function placeBones(run, f, scale) {
    var ms = run.meshes, n = { cyl: 0, sph: 0, cylRim: 0, sphRim: 0 }, radii = run.raw.bones.radii;
    for (var b = 0; b < run.nbone; b++) {
      var o = (f * run.nbone + b) * 6, r = radii[b] * scale, isHot = hot(run, f, b);
      tmp.h.fromArray(run.positions, o);
      tmp.t.fromArray(run.positions, o + 3);
      tmp.d.subVectors(tmp.t, tmp.h);
      var len = tmp.d.length();
      tmp.q.setFromUnitVectors(Y_AXIS, len > 0 ? tmp.d.divideScalar(len) : Y_AXIS);
      tmp.mid.addVectors(tmp.h, tmp.t).multiplyScalar(0.5);
      ms.cyl.setMatrixAt(n.cyl++, tmp.m.compose(tmp.mid, tmp.q, tmp.s.set(r, len, r)));
      tmp.s.set(r, r, r);
      if (headShown(run, f, b, r, scale)) {
        ms.sph.setMatrixAt(n.sph++, tmp.m.compose(tmp.h, tmp.one, tmp.s));
      }
      ms.sph.setMatrixAt(n.sph++, tmp.m.compose(tmp.t, tmp.one, tmp.s));
      if (!isHot) continue;
      var R = r * OUTLINE_SCALE;
      ms.cylRim.setMatrixAt(n.cylRim++, tmp.m.compose(tmp.mid, tmp.q, tmp.s.set(R, len, R)));
      tmp.s.set(R, R, R);
      ms.sphRim.setMatrixAt(n.sphRim++, tmp.m.compose(tmp.h, tmp.one, tmp.s));
      ms.sphRim.setMatrixAt(n.sphRim++, tmp.m.compose(tmp.t, tmp.one, tmp.s));
    }
    Object.keys(ms).forEach(function (k) {
      ms[k].count = n[k];
      ms[k].visible = n[k] > 0;
      ms[k].instanceMatrix.needsUpdate = true;
    });
  }

  var ax = { q: new THREE.Quaternion(), p: new THREE.Quaternion(), r: new THREE.Quaternion(),
             e: new THREE.Vector3(), u: new THREE.Vector3(), a: new THREE.Vector3(),
             w: new THREE.Vector3(), turn: new THREE.Quaternion() };
  var UNIT = [new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 1, 0), new THREE.Vector3(0, 0, 1)];

  // the axes and fans of frame f (run.axes's segments in buildAxes's order)
  function placeAxes(run, f) {
    if (!run.axes || !run.axes.visible) return;
    var pos = run.axes.geometry.attributes.position, n = 0, bones = run.raw.bones;
    function seg(a, b) {
      pos.setXYZ(n++, a.x, a.y, a.z);
      pos.setXYZ(n++, b.x, b.y, b.z);
    }
    function orientation(b, out) {
      var o = (f * run.nbone + b) * 4;
      return out.set(run.orient[o], run.orient[o + 1], run.orient[o + 2], run.orient[o + 3]);
    }
    for (var b = 0; b < run.nbone; b++) {
      tmp.h.fromArray(run.positions, (f * run.nbone + b) * 6);
      orientation(b, ax.q);
      var len = AXES_LENGTH * bones.lengths[b];
      for (var k = 0; k < 3; k++) {
        ax.e.copy(UNIT[k]).applyQuaternion(ax.q).multiplyScalar(len).add(tmp.h);
        seg(tmp.h, ax.e);
      }
    }
    run.fans.forEach(function (fan) {
      var b = fan.bone, p = bones.parents[b];
      tmp.h.fromArray(run.positions, (f * run.nbone + b) * 6);
      // the frame the parent carries: its orientation times the bone's rest frame in it
      orientation(p, ax.p).multiply(ax.r.fromArray(bones.rest_in_parent[b]));
      var len = (AXES_LENGTH + 0.1) * bones.lengths[b];
      ax.u.copy(fan.axis === 1 ? UNIT[0] : UNIT[1]);  // turned: the bone, or its x for a twist
      var first = null;
      for (var i = 0; i <= ARC_SEGMENTS; i++) {
        var t = fan.min + (fan.max - fan.min) * i / ARC_SEGMENTS;
        ax.turn.setFromAxisAngle(UNIT[fan.axis], t);
        ax.w.copy(ax.u).applyQuaternion(ax.turn).applyQuaternion(ax.p).multiplyScalar(len)
            .add(tmp.h);
        if (i === 0) {
          seg(tmp.h, ax.w);  // the min's radius
          first = ax.a.copy(ax.w);
        } else {
          seg(first, ax.w);
          first.copy(ax.w);
        }
      }
      seg(tmp.h, first);  // the max's radius
    });
    pos.needsUpdate = true;
  }

  function placeTargets(run, f) {
    var springs = run.springs.geometry.attributes.position;
    var cps = run.raw.control_points;
    for (var c = 0; c < run.ncontrol; c++) {
      var o = (f * run.ncontrol + c) * 3, mark = run.targetMarks[c];
      tmp.t.fromArray(run.targets, o);
      var ok = isFinite(tmp.t.x) && isFinite(tmp.t.y) && isFinite(tmp.t.z);
      mark.visible = ok;
      if (ok) mark.position.copy(tmp.t);
      var bo = (f * run.nbone + cps.bones[c]) * 6, a = cps.alphas[c];
      tmp.h.fromArray(run.positions, bo);
      tmp.mid.fromArray(run.positions, bo + 3).sub(tmp.h).multiplyScalar(a).add(tmp.h);
      springs.setXYZ(2 * c, tmp.mid.x, tmp.mid.y, tmp.mid.z);
      var end = ok ? tmp.t : tmp.mid;
      springs.setXYZ(2 * c + 1, end.x, end.y, end.z);
    }
    springs.needsUpdate = true;
  }

  // frame f's triads at the bones' heads and aim lines from them (buildBoneTargets's order)
  function placeBoneTargets(run, f) {
    var bt = run.raw.bone_targets, bones = run.raw.bones;
    if (!bt) return;
    if (run.triads) {
      var pos = run.triads.geometry.attributes.position, n = 0;
      bt.orientations.forEach(function (t) {
        tmp.h.fromArray(run.positions, (f * run.nbone + t.bone) * 6);
        ax.q.fromArray(t.quaternion);
        var len = TARGET_AXES_LENGTH * bones.lengths[t.bone];
        for (var k = 0; k < 3; k++) {
          ax.e.copy(UNIT[k]).applyQuaternion(ax.q).multiplyScalar(len).add(tmp.h);
          pos.setXYZ(n++, tmp.h.x, tmp.h.y, tmp.h.z);
          pos.setXYZ(n++, ax.e.x, ax.e.y, ax.e.z);
        }
      });
      pos.needsUpdate = true;
      run.triads.computeLineDistances();
    }
    if (run.aimLines) {
      var ends = run.aimLines.geometry.attributes.position;
      bt.aims.forEach(function (a, i) {
        tmp.h.fromArray(run.positions, (f * run.nbone + a.bone) * 6);
        ends.setXYZ(2 * i, tmp.h.x, tmp.h.y, tmp.h.z);
        ends.setXYZ(2 * i + 1, a.point[0], a.point[1], a.point[2]);
      });
      ends.needsUpdate = true;
    }
  }

  function placeContacts(run, f) {
    var c = run.contacts;
    if (c === null) return;
    var lines = run.contactLines.geometry, ends = lines.attributes.position, n = 0;
    tmp.s.set(run.contactSize, run.contactSize, run.contactSize);
    for (var k = c.start[f]; k < c.start[f + 1]; k++, n++) {
      var o = 8 * k;
      tmp.h.fromArray(c.values, o);
      tmp.d.fromArray(c.values, o + 3);
      tmp.t.copy(tmp.h).addScaledVector(tmp.d, run.contactLength);
      run.contactDots.setMatrixAt(n, tmp.m.compose(tmp.h, tmp.one, tmp.s));
      ends.setXYZ(2 * n, tmp.h.x, tmp.h.y, tmp.h.z);
      ends.setXYZ(2 * n + 1, tmp.t.x, tmp.t.y, tmp.t.z);
    }
    run.contactDots.count = n;
    run.contactDots.visible = n > 0;
    run.contactDots.instanceMatrix.needsUpdate = true;
    lines.setDrawRange(0, 2 * n);
    run.contactLines.visible = n > 0;
    ends.needsUpdate = true;
  }

  function fmt(x, digits) {
    if (!isFinite(x)) return String(x);
    return Math.abs(x) >= 1e5 || (x !== 0 && Math.abs(x) < 1e-3) ? x.toExponential(digits - 1)
                                                                  : x.toPrecision(digits);
  }

  function limitText(run, f) {
    if (run.excess === null) return 'not recorded';
    var count = 0, worst = -1, most = 0;
    for (var b = 0; b < run.nbone; b++) {
      var e = run.excess[f * run.nbone + b];
      if (e > LIMIT_SHOWN_RAD) count++;
      if (e > most) { most = e; worst = b; }
    }
    if (count === 0) return 'none';
    return count + (count === 1 ? ' bone' : ' bones') + ', most ' +
        fmt(most * 180 / Math.PI, 3) + ' deg (' + run.raw.bones.names[worst] + ')';
  }

  function showReadout(run, f) {
    var cells = run.cells, p = run.maxResidualPoint[f];
    cells[0].textContent = String(run.steps[f]);
    cells[1].textContent = run.times[f].toFixed(3);
    cells[2].textContent = fmt(run.ke[f], 4);
    cells[3].textContent = p < 0 ? '(no control points)'
        : fmt(run.maxResidual[f], 4) + ' (' + (run.raw.control_points.names[p] || '#' + p) + ')';
    cells[4].textContent = limitText(run, f);
    cells[5].textContent = contactText(run, f);
  }

  function contactText(run, f) {
    var c = run.contacts;
    if (c === null) return 'not recorded';
    var n = c.start[f + 1] - c.start[f], most = 0;
    if (n === 0) return 'none';
    for (var k = c.start[f]; k < c.start[f + 1]; k++) most = Math.max(most, c.values[8 * k + 7]);
    return n + ', largest force ' + fmt(most, 3) + ' N';
  }

  // --- the viewer -----------------------------------------------------------------------------

  function Viewer(root, data) {
    this.root = root;
    this.data = data;
    this.runs = data.runs.map(prepareRun);
    this.times = buildTimeline(this.runs);
    this.frame = 0;
    this.playing = false;
    this.renders = 0;  // frames drawn: the tests and benchmarks read it
    root.appendChild(el('h1', 'title', data.title));
    root.appendChild(buildLegend(this));
    var stage = this.stage = root.appendChild(el('div', 'stage'));
    this.renderer = new THREE.WebGLRenderer({ antialias: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    stage.appendChild(this.renderer.domElement);
    buildScene(this);
    buildCamera(this, this.renderer.domElement);
    root.appendChild(buildControls(this));
    root.appendChild(buildReadout(this));
    root.appendChild(buildNotes(this, data));
    var self = this;
    window.addEventListener('resize', function () { self.resize(); });
    this.resize();
    var start = startParams(window.location.search, this.times.length);
    this.setFrame(start.frame);
    if (start.play) this.play();
  }

  // ?frame=N (from 1, or "last") and ?play=1 of the page's URL: the frame index to open at and
  // whether to play; anything else opens at the first frame, paused
  function startParams(search, nframe) {
    var out = { frame: 0, play: false };
    (search || '').replace(/^\?/, '').split('&').forEach(function (pair) {
      var kv = pair.split('=');
      var key = decodeURIComponent(kv[0] || ''), value = decodeURIComponent(kv[1] || '');
      if (key === 'frame') {
        var n = value === 'last' ? nframe : parseInt(value, 10);
        if (n >= 1) out.frame = Math.min(nframe, n) - 1;
      } else if (key === 'play') {
        out.play = value === '' || value === '1' || value === 'true';
      }
    });
    return out;
  }

  // The canvas fills its stage's inner width (the stylesheet's width: 100%, never wider: the
  // stage's border and a scrollbar that appears once the canvas is tall both fit), and the
  // drawing buffer is that width; the page keeps the scrollbar's room (scrollbar-gutter), so the
  // width the canvas was sized for stays the width it has.
  Viewer.prototype.resize = function () {
    var width = Math.max(200, this.stage.clientWidth || 800);
    var height = Math.round(Math.min(width * 0.6, Math.max(240, window.innerHeight * 0.7)));
    this.renderer.setSize(width, height, false);
    this.renderer.domElement.style.height = height + 'px';
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  };

  Viewer.prototype.setFrame = function (i) {
    this.frame = Math.max(0, Math.min(this.times.length - 1, i | 0));
    var self = this;
    this.runs.forEach(function (run) {
      var f = run.frameAt[self.frame];
      placeBones(run, f, self.radiusScale);
      placeAxes(run, f);
      placeTargets(run, f);
      placeBoneTargets(run, f);
      placeContacts(run, f);
      showReadout(run, f);
    });
    this.slider.value = this.frame;
    var steps = this.runs.map(function (r) { return r.steps[r.frameAt[self.frame]]; });
    var same = steps.every(function (s) { return s === steps[0]; });
    this.timeLabel.textContent = 't = ' + this.times[this.frame].toFixed(3) + ' s' +
        (same ? ', step ' + steps[0] : '') + ', frame ' + (this.frame + 1) + '/' +
        this.times.length;
    this.requestRender();
  };

  Viewer.prototype.requestRender = function () {
    if (this.renderQueued) return;
    this.renderQueued = true;
    var self = this;
    requestAnimationFrame(function (now) { self.tick(now); });
  };

  // one animation frame: advance the playback, then draw
  Viewer.prototype.tick = function (now) {
    this.renderQueued = false;
    if (this.playing) {
      if (this.lastTick !== undefined) this.clock += (now - this.lastTick) / 1000 * this.speed;
      this.lastTick = now;
      var i = this.frame;
      while (i + 1 < this.times.length && this.times[i + 1] <= this.clock) i++;
      if (i !== this.frame) this.setFrame(i);
      if (i + 1 >= this.times.length) this.pause();
      else this.requestRender();
    }
    this.renderer.render(this.scene, this.camera);
    this.renders++;
  };

  Viewer.prototype.play = function () {
    if (this.times.length < 2) return;
    if (this.frame + 1 >= this.times.length) this.setFrame(0);
    this.playing = true;
    this.clock = this.times[this.frame];
    this.lastTick = undefined;
    this.playButton.textContent = 'Pause';
    this.requestRender();
  };

  Viewer.prototype.pause = function () {
    this.playing = false;
    this.playButton.textContent = 'Play';
  };

  Viewer.prototype.setTargetsShown = function (on) {
    this.runs.forEach(function (r) { r.targetGroup.visible = on; });
    this.requestRender();
  };

  Viewer.prototype.setAxesShown = function (on) {
    this.runs.forEach(function (r) { if (r.axes) r.axes.visible = on; });
    this.setFrame(this.frame);
  };

  Viewer.prototype.setContactsShown = function (on) {
    this.runs.forEach(function (r) { if (r.contactGroup) r.contactGroup.visible = on; });
    this.requestRender();
  };

  Viewer.prototype.setBoxesShown = function (on) {
    this.boxGroup.visible = on;
    this.requestRender();
  };

  Viewer.prototype.setPathsShown = function (on) {
    this.runs.forEach(function (r) { r.pathGroup.visible = on; });
    this.requestRender();
  };

  function mount(root) {
    var source = document.getElementById(root.getAttribute('data-source'));
    var data = JSON.parse(source.textContent);
    try {
      return new Viewer(root, data);
    } catch (e) {
      root.appendChild(el('p', 'error', 'The viewer could not start: ' + e.message));
      throw e;
    }
  }

  window.PhysikViewer = {
    mount: mount,
    mountAll: function () {
      var roots = document.querySelectorAll('.physik-viewer[data-source]');
      window.physikViewers = Array.prototype.map.call(roots, mount);
    }
  };
})();
