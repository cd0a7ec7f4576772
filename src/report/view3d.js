// semvox report.html: the 3D view. Compiled into the binary and inlined after three.js by
// src/report/view3d.cc, which also writes the switches and the packed voxels (<script id="v3-data">).
//
// Drawing: every shown voxel is a cube on the view's grid; only faces between a shown voxel and an empty or
// hidden cell become quads (positions in half cells, uint16), coloured per quad and shaded by face direction
// (top faces keep the exact colour). Picking walks the ray through the grid (Amanatides & Woo, "A fast voxel
// traversal algorithm for ray tracing", Eurographics 1987) to the first shown voxel.
//
// URL fragment: #3d fills the window; parameters after '&' set the view, e.g.
//   report.html#3d&view=top&colour=room&hide=wall,ceiling&show=ceiling&hide_rooms=2&pick=0.5,0.5
// (classes by NYU40 name or id, rooms by id, pick = a click at that fraction of the canvas).
// The section's data-state says how far the script got: loading, ready or unavailable; it writes nothing to
// the console.
(function () {
  'use strict';
  var section = document.getElementById('view3d');
  if (!section) return;

  function fail(reason) {
    section.setAttribute('data-state', 'unavailable');
    var body = section.querySelector('.v3-body');
    var line = document.createElement('p');
    line.className = 'na';
    line.id = 'view3d-absent';
    line.textContent = '3D view not available: ' + reason;
    if (body) body.parentNode.replaceChild(line, body);
    else section.appendChild(line);
  }

  var data;
  try {
    data = JSON.parse(document.getElementById('v3-data').textContent);
  } catch (e) {
    fail('the embedded voxel data is damaged');
    return;
  }
  if (typeof THREE === 'undefined') {
    fail('three.js did not load');
    return;
  }
  var hasWebGl = false;
  try {
    var probe = document.createElement('canvas');
    hasWebGl = !!(window.WebGLRenderingContext && (probe.getContext('webgl') || probe.getContext('experimental-webgl')));
  } catch (e) {
    hasWebGl = false;
  }
  if (!hasWebGl) {
    fail('this browser offers no WebGL');
    return;
  }

  // ---- the packed voxels ----
  function bytes(b64) {
    var s = atob(b64), out = new Uint8Array(s.length);
    for (var i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
    return out;
  }
  function uint16(b64) {
    var b = bytes(b64), out = new Uint16Array(b.length >> 1);
    for (var i = 0; i < out.length; ++i) out[i] = b[2 * i] | (b[2 * i + 1] << 8);
    return out;
  }
  var n = data.count, X = data.dims[0], Y = data.dims[1], Z = data.dims[2], XY = X * Y;
  var size = data.voxel_size_m, origin = data.origin;
  var cells = uint16(data.cells), labels = uint16(data.labels);
  var confidence = data.confidence ? bytes(data.confidence) : null;
  var rooms = data.rooms ? uint16(data.rooms) : null;  // voxels.ply's room (0: outside every room).
  var roomGroups = data.room_groups ? uint16(data.room_groups) : null;  // The room a voxel switches with.
  var completedBits = data.completed ? bytes(data.completed) : null;
  function isCompleted(v) { return completedBits ? (completedBits[v >> 3] >> (v & 7)) & 1 : 0; }
  var keys = new Float64Array(n);  // Ascending: the voxels come sorted by (z, y, x).
  for (var v = 0; v < n; ++v) keys[v] = cells[3 * v] + X * (cells[3 * v + 1] + Y * cells[3 * v + 2]);
  function voxelAt(key) {
    var lo = 0, hi = n - 1;
    while (lo <= hi) {
      var mid = (lo + hi) >> 1;
      if (keys[mid] === key) return mid;
      if (keys[mid] < key) lo = mid + 1; else hi = mid - 1;
    }
    return -1;
  }
  var classById = {}, roomById = {};
  data.classes.forEach(function (c) { classById[c.id] = c; });
  data.room_list.forEach(function (r) { roomById[r.id] = r; });

  // ---- switches ----
  var classShown = {}, roomShown = {};
  var classBoxes = section.querySelectorAll('input[data-class]'), roomBoxes = section.querySelectorAll('input[data-room]');
  // Reads the switches; their `checked` attributes follow, so that the DOM shows the state.
  function readSwitches() {
    Array.prototype.forEach.call(classBoxes, function (b) {
      classShown[+b.getAttribute('data-class')] = b.checked;
      b.toggleAttribute('checked', b.checked);
    });
    Array.prototype.forEach.call(roomBoxes, function (b) {
      roomShown[+b.getAttribute('data-room')] = b.checked;
      b.toggleAttribute('checked', b.checked);
    });
  }
  readSwitches();
  function isShown(v) { return classShown[labels[v]] === true && (!roomGroups || roomShown[roomGroups[v]] === true); }

  // ---- colours ----
  var mode = 'class';
  var VIRIDIS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  var COMPLETED = data.completed_colour, SEEN = data.seen_colour;
  // Shade per face direction +x, -x, +y, -y, +z, -z: top faces keep the colour, the others are darker.
  var SHADE = [0.80, 0.70, 0.62, 0.88, 1.0, 0.45];
  function baseColour(v, out) {
    var c;
    if (mode === 'room' && rooms) c = roomById[rooms[v]] ? roomById[rooms[v]].colour : data.no_room_colour;
    else if (mode === 'confidence' && confidence) {
      var t = confidence[v] / 255 * (VIRIDIS.length - 1), i = Math.min(VIRIDIS.length - 2, Math.floor(t)), f = t - i;
      out[0] = VIRIDIS[i][0] + (VIRIDIS[i + 1][0] - VIRIDIS[i][0]) * f;
      out[1] = VIRIDIS[i][1] + (VIRIDIS[i + 1][1] - VIRIDIS[i][1]) * f;
      out[2] = VIRIDIS[i][2] + (VIRIDIS[i + 1][2] - VIRIDIS[i][2]) * f;
      return;
    } else if (mode === 'completed' && completedBits) c = isCompleted(v) ? COMPLETED : SEEN;
    else c = classById[labels[v]].colour;
    out[0] = c[0], out[1] = c[1], out[2] = c[2];
  }
  var legend = document.getElementById('v3-legend');
  function swatch(c) {
    return '<span class="swatch" style="background:rgb(' + c[0] + ',' + c[1] + ',' + c[2] + ')"></span> ';
  }
  function updateLegend() {
    if (mode === 'confidence') legend.innerHTML = '0 <span class="v3-ramp"></span> 1';
    else if (mode === 'completed') legend.innerHTML = swatch(SEEN) + 'seen &nbsp;' + swatch(COMPLETED) + 'completed (never seen, inferred)';
    else if (mode === 'room') legend.innerHTML = 'colours of the room table';
    else legend.innerHTML = '';
  }

  // ---- geometry: exposed faces of the shown voxels ----
  var grid = new Uint8Array(X * Y * Z);
  // Per direction: the neighbour's step and the 4 corners (half cells from the cell's centre), counter-clockwise
  // seen from outside.
  var DIRS = [
    [1, 0, 0, [1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1]],
    [-1, 0, 0, [-1, -1, -1, -1, -1, 1, -1, 1, 1, -1, 1, -1]],
    [0, 1, 0, [-1, 1, -1, -1, 1, 1, 1, 1, 1, 1, 1, -1]],
    [0, -1, 0, [-1, -1, -1, 1, -1, -1, 1, -1, 1, -1, -1, 1]],
    [0, 0, 1, [-1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1]],
    [0, 0, -1, [-1, -1, -1, -1, 1, -1, 1, 1, -1, 1, -1, -1]]
  ];
  function exposed(i, j, k, d) {
    var a = i + DIRS[d][0], b = j + DIRS[d][1], c = k + DIRS[d][2];
    if (a < 0 || b < 0 || c < 0 || a >= X || b >= Y || c >= Z) return true;
    return grid[a + X * b + XY * c] === 0;
  }
  var scene = new THREE.Scene();
  var material = new THREE.MeshBasicMaterial({vertexColors: THREE.VertexColors !== undefined ? THREE.VertexColors : true});
  var mesh = null, quadVoxel = null, quadDir = null, colours = null, colourAttribute = null, shownCount = 0;
  function rebuild() {
    grid.fill(0);
    shownCount = 0;
    var box = {lo: [X, Y, Z], hi: [-1, -1, -1]};
    for (var v = 0; v < n; ++v) {
      if (!isShown(v)) continue;
      grid[keys[v]] = 1;
      ++shownCount;
      for (var a = 0; a < 3; ++a) {
        box.lo[a] = Math.min(box.lo[a], cells[3 * v + a]);
        box.hi[a] = Math.max(box.hi[a], cells[3 * v + a]);
      }
    }
    shownBox = shownCount > 0 ? box : null;
    var quads = 0, d;
    for (v = 0; v < n; ++v) {
      if (grid[keys[v]] === 0) continue;
      for (d = 0; d < 6; ++d) if (exposed(cells[3 * v], cells[3 * v + 1], cells[3 * v + 2], d)) ++quads;
    }
    var positions = new Uint16Array(quads * 12), index = quads * 4 > 65535 ? new Uint32Array(quads * 6) : new Uint16Array(quads * 6);
    quadVoxel = new Uint32Array(quads);
    quadDir = new Uint8Array(quads);
    colours = new Uint8Array(quads * 12);
    var q = 0;
    for (v = 0; v < n; ++v) {
      if (grid[keys[v]] === 0) continue;
      var i = cells[3 * v], j = cells[3 * v + 1], k = cells[3 * v + 2];
      for (d = 0; d < 6; ++d) {
        if (!exposed(i, j, k, d)) continue;
        var corners = DIRS[d][3];
        for (var c = 0; c < 4; ++c) {
          positions[12 * q + 3 * c] = 2 * i + 1 + corners[3 * c];
          positions[12 * q + 3 * c + 1] = 2 * j + 1 + corners[3 * c + 1];
          positions[12 * q + 3 * c + 2] = 2 * k + 1 + corners[3 * c + 2];
        }
        var base = 4 * q;
        index[6 * q] = base, index[6 * q + 1] = base + 1, index[6 * q + 2] = base + 2;
        index[6 * q + 3] = base, index[6 * q + 4] = base + 2, index[6 * q + 5] = base + 3;
        quadVoxel[q] = v;
        quadDir[q] = d;
        ++q;
      }
    }
    if (mesh) {
      scene.remove(mesh);
      mesh.geometry.dispose();
    }
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    colourAttribute = new THREE.BufferAttribute(colours, 3, true);
    geometry.setAttribute('color', colourAttribute);
    geometry.setIndex(new THREE.BufferAttribute(index, 1));
    mesh = new THREE.Mesh(geometry, material);
    // Half cells to metres: corner h sits at origin - size / 2 + h * size / 2.
    mesh.scale.set(size / 2, size / 2, size / 2);
    mesh.position.set(origin[0] - size / 2, origin[1] - size / 2, origin[2] - size / 2);
    mesh.frustumCulled = false;
    scene.add(mesh);
    section.setAttribute('data-shown', String(shownCount));
    section.setAttribute('data-faces', String(quads));
    recolour();
    if (picked >= 0 && grid[keys[picked]] === 0) clearPick();
  }
  function recolour() {
    var c = [0, 0, 0];
    for (var q = 0; q < quadVoxel.length; ++q) {
      baseColour(quadVoxel[q], c);
      var s = SHADE[quadDir[q]];
      var r = Math.round(c[0] * s), g = Math.round(c[1] * s), b = Math.round(c[2] * s);
      for (var k = 0; k < 4; ++k) colours[12 * q + 3 * k] = r, colours[12 * q + 3 * k + 1] = g, colours[12 * q + 3 * k + 2] = b;
    }
    colourAttribute.needsUpdate = true;
    updateLegend();
    requestRender();
  }

  // ---- renderer and camera ----
  var canvas = document.getElementById('v3-canvas'), stage = document.getElementById('v3-stage');
  var info = document.getElementById('v3-info');
  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: false, preserveDrawingBuffer: true});
  } catch (e) {
    fail('WebGL could not start');
    return;
  }
  var bg = data.background;
  renderer.setClearColor(new THREE.Color(bg[0] / 255, bg[1] / 255, bg[2] / 255), 1);
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  var camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
  camera.up.set(0, 0, 1);
  var shownBox = null;
  var view = {target: new THREE.Vector3(), az: 0, el: 0, dist: 1};
  var HOME = {az: -Math.PI / 2 + 0.6, el: 0.9}, TOP = {az: -Math.PI / 2, el: Math.PI / 2 - 1e-3};
  var MAX_EL = Math.PI / 2 - 1e-3;
  var span = Math.sqrt(X * X + Y * Y + Z * Z) * size;  // Diagonal of the whole map, metres.

  var renderPending = false;
  function render() {
    renderPending = false;
    renderer.render(scene, camera);
  }
  function requestRender() {
    if (renderPending) return;
    renderPending = true;
    window.requestAnimationFrame(render);
  }
  function place() {
    var ce = Math.cos(view.el);
    camera.position.set(view.target.x + view.dist * ce * Math.cos(view.az), view.target.y + view.dist * ce * Math.sin(view.az),
                        view.target.z + view.dist * Math.sin(view.el));
    camera.near = Math.max(view.dist / 500, size / 20);
    camera.far = view.dist + 2 * span + size;
    camera.lookAt(view.target);
    camera.updateProjectionMatrix();
    camera.updateMatrixWorld();
    requestRender();
  }
  // Resizing the canvas clears it: draw again at once (not at the next frame) so that no blank frame shows.
  var canvasSize = [0, 0];
  function resize() {
    var w = Math.max(1, stage.clientWidth), h = Math.max(1, stage.clientHeight);
    if (w === canvasSize[0] && h === canvasSize[1]) return;
    canvasSize = [w, h];
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    if (mesh) render();
  }
  // Looks from the direction `angles` at the shown voxels' bounding box (all voxels when none is shown), so that
  // the box fills the view.
  function fit(angles) {
    var lo = shownBox ? shownBox.lo : [0, 0, 0], hi = shownBox ? shownBox.hi : [X - 1, Y - 1, Z - 1];
    var min = [], max = [];
    for (var a = 0; a < 3; ++a) {
      min.push(origin[a] + (lo[a] - 0.5) * size);
      max.push(origin[a] + (hi[a] + 0.5) * size);
    }
    view.target.set((min[0] + max[0]) / 2, (min[1] + max[1]) / 2, (min[2] + max[2]) / 2);
    view.az = angles.az;
    view.el = angles.el;
    var tanV = Math.tan(camera.fov * Math.PI / 360), tanH = tanV * camera.aspect;
    if (angles === TOP) {
      // The top face of the box fills the window.
      view.dist = 1.04 * Math.max((max[0] - min[0]) / 2 / tanH, (max[1] - min[1]) / 2 / tanV) + (max[2] - min[2]) / 2;
    } else {
      var r = 0.5 * Math.sqrt(Math.pow(max[0] - min[0], 2) + Math.pow(max[1] - min[1], 2) + Math.pow(max[2] - min[2], 2));
      view.dist = 1.02 * r / Math.sin(Math.atan(Math.min(tanV, tanH)));
    }
    place();
  }

  // ---- picking ----
  var picked = -1, highlight = null;
  var raycaster = new THREE.Raycaster();
  // The first shown voxel along the ray (world coordinates), or -1.
  function castRay(o, d) {
    var p = [], dir = [d.x, d.y, d.z], dims = [X, Y, Z], t0 = 0, t1 = Infinity, a;
    var from = [o.x, o.y, o.z];
    for (a = 0; a < 3; ++a) p.push((from[a] - (origin[a] - size / 2)) / size);
    for (a = 0; a < 3; ++a) {
      if (Math.abs(dir[a]) < 1e-12) {
        if (p[a] < 0 || p[a] > dims[a]) return -1;
        continue;
      }
      var ta = -p[a] / dir[a], tb = (dims[a] - p[a]) / dir[a];
      t0 = Math.max(t0, Math.min(ta, tb));
      t1 = Math.min(t1, Math.max(ta, tb));
    }
    if (t0 > t1) return -1;
    var cell = [], step = [], tMax = [], tDelta = [];
    for (a = 0; a < 3; ++a) {
      cell.push(Math.min(dims[a] - 1, Math.max(0, Math.floor(p[a] + dir[a] * t0))));
      step.push(dir[a] > 0 ? 1 : -1);
      tMax.push(Math.abs(dir[a]) < 1e-12 ? Infinity : (cell[a] + (dir[a] > 0 ? 1 : 0) - p[a]) / dir[a]);
      tDelta.push(Math.abs(dir[a]) < 1e-12 ? Infinity : 1 / Math.abs(dir[a]));
    }
    for (var steps = X + Y + Z + 3; steps > 0; --steps) {
      var key = cell[0] + X * cell[1] + XY * cell[2];
      if (grid[key] === 1) return voxelAt(key);
      a = tMax[0] < tMax[1] ? (tMax[0] < tMax[2] ? 0 : 2) : (tMax[1] < tMax[2] ? 1 : 2);
      cell[a] += step[a];
      if (cell[a] < 0 || cell[a] >= dims[a]) return -1;
      tMax[a] += tDelta[a];
    }
    return -1;
  }
  function describe(v) {
    var c = classById[labels[v]], parts = [c.name + ' (NYU40 ' + c.id + ')'];
    if (confidence) parts.push('confidence ' + (confidence[v] / 255).toFixed(2));
    if (rooms) {
      parts.push(rooms[v] > 0 ? 'room ' + (roomById[rooms[v]] ? roomById[rooms[v]].name : rooms[v]) : 'outside every room');
      if (roomGroups[v] !== rooms[v] && roomGroups[v] > 0) parts.push('switches with room ' + roomGroups[v]);
    }
    if (completedBits) parts.push(isCompleted(v) ? 'completed (never seen, inferred)' : 'seen');
    var at = [];
    for (var a = 0; a < 3; ++a) at.push((origin[a] + cells[3 * v + a] * size).toFixed(2));
    parts.push('at (' + at.join(', ') + ') m');
    return parts.join(' \u00b7 ');
  }
  function clearPick() {
    picked = -1;
    if (highlight) scene.remove(highlight);
    highlight = null;
    info.textContent = 'click a voxel for its class, confidence and room';
    section.removeAttribute('data-picked');
    requestRender();
  }
  function pickAt(x, y) {
    raycaster.setFromCamera(new THREE.Vector2(2 * x / canvas.clientWidth - 1, 1 - 2 * y / canvas.clientHeight), camera);
    var v = castRay(raycaster.ray.origin, raycaster.ray.direction);
    if (v < 0) {
      clearPick();
      info.textContent = 'no voxel there';
      return;
    }
    picked = v;
    info.textContent = describe(v);
    section.setAttribute('data-picked', String(v));
    if (highlight) scene.remove(highlight);
    var e = size * 0.52, c = [], corners = [];
    for (var a = 0; a < 3; ++a) c.push(origin[a] + cells[3 * v + a] * size);
    for (var k = 0; k < 8; ++k) corners.push([c[0] + (k & 1 ? e : -e), c[1] + (k & 2 ? e : -e), c[2] + (k & 4 ? e : -e)]);
    var edges = [0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7], lines = new Float32Array(edges.length * 3);
    for (k = 0; k < edges.length; ++k) for (a = 0; a < 3; ++a) lines[3 * k + a] = corners[edges[k]][a];
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(lines, 3));
    highlight = new THREE.LineSegments(g, new THREE.LineBasicMaterial({color: 0x000000}));
    scene.add(highlight);
    requestRender();
  }

  // ---- orbit, pan, zoom (mouse, pen and touch through pointer events) ----
  var pointers = {}, dragMode = null, moved = 0, pinch = null;
  function pointerList() { return Object.keys(pointers).map(function (id) { return pointers[id]; }); }
  function pan(dx, dy) {
    var perPixel = 2 * view.dist * Math.tan(camera.fov * Math.PI / 360) / Math.max(1, canvas.clientHeight);
    var right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
    var up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
    view.target.addScaledVector(right, -dx * perPixel).addScaledVector(up, dy * perPixel);
  }
  function zoom(factor) {
    view.dist = Math.min(Math.max(view.dist * factor, size), 20 * span + size);
  }
  function pinchState() {
    var p = pointerList();
    return {x: (p[0].x + p[1].x) / 2, y: (p[0].y + p[1].y) / 2, d: Math.max(1, Math.hypot(p[0].x - p[1].x, p[0].y - p[1].y))};
  }
  canvas.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  canvas.addEventListener('pointerdown', function (e) {
    try {
      canvas.setPointerCapture(e.pointerId);  // Drags continue outside the canvas; not every pointer can be captured.
    } catch (err) {
      // Without capture the drag ends at the canvas border.
    }
    pointers[e.pointerId] = {x: e.clientX, y: e.clientY};
    var count = pointerList().length;
    if (count === 1) {
      dragMode = e.button === 2 || e.button === 1 || e.shiftKey || e.ctrlKey ? 'pan' : 'rotate';
      moved = 0;
    } else if (count === 2) {
      dragMode = 'pinch';
      pinch = pinchState();
      moved = Infinity;
    }
  });
  canvas.addEventListener('pointermove', function (e) {
    var p = pointers[e.pointerId];
    if (!p) return;
    var dx = e.clientX - p.x, dy = e.clientY - p.y;
    p.x = e.clientX, p.y = e.clientY;
    moved += Math.abs(dx) + Math.abs(dy);
    if (dragMode === 'rotate') {
      view.az -= dx * 2 * Math.PI / Math.max(1, canvas.clientWidth);
      view.el = Math.min(MAX_EL, Math.max(-MAX_EL, view.el + dy * Math.PI / Math.max(1, canvas.clientHeight)));
    } else if (dragMode === 'pan') {
      pan(dx, dy);
    } else if (dragMode === 'pinch' && pointerList().length === 2) {
      var now = pinchState();
      zoom(pinch.d / now.d);
      pan(now.x - pinch.x, now.y - pinch.y);
      pinch = now;
    }
    place();
  });
  function pointerEnd(e) {
    if (!pointers[e.pointerId]) return;
    delete pointers[e.pointerId];
    if (e.type === 'pointerup' && dragMode !== 'pinch' && moved < 4) {
      var rect = canvas.getBoundingClientRect();
      pickAt(e.clientX - rect.left, e.clientY - rect.top);
    }
    var count = pointerList().length;
    dragMode = count === 1 && dragMode === 'pinch' ? null : count === 0 ? null : dragMode;
  }
  canvas.addEventListener('pointerup', pointerEnd);
  canvas.addEventListener('pointercancel', pointerEnd);
  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    var delta = e.deltaY * (e.deltaMode === 1 ? 33 : e.deltaMode === 2 ? 400 : 1);
    zoom(Math.exp(delta * 0.0015));
    place();
  }, {passive: false});

  // ---- controls of the bar and the side panel ----
  var colourSelect = document.getElementById('v3-colour');
  var MODES = ['class', 'room', 'confidence', 'completed'];
  function setMode(m) {
    if (MODES.indexOf(m) < 0) return;
    var option = colourSelect.querySelector('option[value="' + m + '"]');
    if (!option || option.disabled) return;
    colourSelect.value = m;
    mode = m;
    recolour();
  }
  colourSelect.addEventListener('change', function () { setMode(colourSelect.value); });
  document.getElementById('v3-top').addEventListener('click', function () { fit(TOP); });
  document.getElementById('v3-reset').addEventListener('click', function () { fit(HOME); });
  Array.prototype.forEach.call(section.querySelectorAll('input[data-class],input[data-room]'), function (b) {
    b.addEventListener('change', function () { readSwitches(); rebuild(); });
  });
  Array.prototype.forEach.call(section.querySelectorAll('button[data-all],button[data-none]'), function (b) {
    b.addEventListener('click', function () {
      var kind = b.getAttribute('data-all') || b.getAttribute('data-none'), on = b.hasAttribute('data-all');
      Array.prototype.forEach.call(kind === 'class' ? classBoxes : roomBoxes, function (box) { box.checked = on; });
      readSwitches();
      rebuild();
    });
  });
  if (window.ResizeObserver) new ResizeObserver(resize).observe(stage);
  else window.addEventListener('resize', resize);

  // ---- the URL fragment ----
  function classIdOf(token) {
    if (/^\d+$/.test(token)) return +token;
    var name = token.toLowerCase().replace(/_/g, ' ');
    for (var i = 0; i < data.classes.length; ++i) if (data.classes[i].name.toLowerCase() === name) return data.classes[i].id;
    return -1;
  }
  function setBoxes(boxes, attribute, tokens, on, idOf) {
    tokens.split(',').forEach(function (t) {
      var id = idOf(t.trim());
      Array.prototype.forEach.call(boxes, function (b) { if (+b.getAttribute(attribute) === id) b.checked = on; });
    });
  }
  function applyFragment(initial) {
    var text = location.hash.replace(/^#/, '');
    try {
      text = decodeURIComponent(text);
    } catch (e) {
      // Left as typed.
    }
    var parts = text.split('&'), options = {};
    parts.forEach(function (p) {
      var eq = p.indexOf('=');
      if (eq > 0) options[p.slice(0, eq)] = p.slice(eq + 1);
    });
    document.body.classList.toggle('v3-full', parts[0] === '3d');
    resize();
    var byId = function (t) { return /^\d+$/.test(t) ? +t : -1; };
    if (options.hide) setBoxes(classBoxes, 'data-class', options.hide, false, classIdOf);
    if (options.show) setBoxes(classBoxes, 'data-class', options.show, true, classIdOf);
    if (options.hide_rooms) setBoxes(roomBoxes, 'data-room', options.hide_rooms, false, byId);
    if (options.show_rooms) setBoxes(roomBoxes, 'data-room', options.show_rooms, true, byId);
    readSwitches();
    if (initial) mode = 'class';
    rebuild();
    var colour = options.colour || options.color;
    if (colour) setMode(colour);
    if (options.view === 'top') fit(TOP);
    else if (initial || options.view === 'home') fit(HOME);
    if (options.pick) {
      var xy = options.pick.split(','), fx = parseFloat(xy[0]), fy = parseFloat(xy[1]);
      if (isFinite(fx) && isFinite(fy)) pickAt(fx * canvas.clientWidth, fy * canvas.clientHeight);
    }
  }
  window.addEventListener('hashchange', function () { applyFragment(false); });
  applyFragment(true);
  render();
  section.setAttribute('data-state', 'ready');
})();
