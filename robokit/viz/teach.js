// robokit teach page: sliders -> the robot's generated C (WebAssembly) -> 3-D view and readouts.
//
// The page's UI. The kinematics (tool pose, Jacobian, the bodies' placements, IK) come from the
// robot's generated C compiled to WebAssembly (#rk-wasm, loaded by teach_wasm.js: KIN); the
// presentation math (SVD, RPY, quaternion, the readouts, the URL fragment's parsing) is RKMath,
// in teach_math.js. Both are inlined before this script. The robot's data is the JSON block
// #rk-robot written by robokit/viz/teach.py.
(function () {
  "use strict";
  var R = JSON.parse(document.getElementById("rk-robot").textContent);
  var n = R.n;
  var DEG = 180 / Math.PI;

  var mul4 = RKMath.mul4, flat4 = RKMath.flat4;

  // the robot's generated C compiled to WebAssembly (#rk-wasm, embedded by robokit teach;
  // teach_wasm.js): the tool pose, the Jacobian, the placements and the IK all come from it
  var KIN = null, kinProblem = "";
  (function () {
    var src = document.getElementById("rk-wasm");
    try {
      if (!src || typeof RKWasm === "undefined") { throw new Error("the page has no module (write it with robokit teach)"); }
      KIN = RKWasm.load(RKWasm.decode(src.textContent.trim()));
      if (KIN.n !== n) { throw new Error("the module has " + KIN.n + " joints, the robot " + n); }
    } catch (err) {
      KIN = null;
      kinProblem = "This page cannot compute: the robot's WebAssembly module did not load (" + err + ")";
    }
  })();

  // The placements of the bodies at joint values qv: n + 1 row-major 4x4, P[0] = I and P[k]
  // the motion of body k from q = 0 (the module's joint poses times their inverse at q = 0), so
  // that anything fixed to body k with pose T(0) at q = 0 is at P[k] T(0). Everything that
  // draws the arm (the arm itself, ghost arms) goes through this one function.
  function placementsAt(qv) { return KIN.placements(qv); }

  // ------------------------------------------------------------------ state and input
  var unit = R.joints.map(function (j) { return j.type === "R" ? DEG : 1; });  // display units per joint
  var q = R.q0.slice();

  function clampJoint(i, v) {
    var j = R.joints[i];
    if (!isFinite(v)) { return 0; }
    if (j.type === "R" && !j.limited) {  // unlimited revolute: wrap into [-pi, pi]
      var two = 2 * Math.PI;
      v = v - two * Math.round(v / two);
    }
    return Math.min(j.hi, Math.max(j.lo, v));
  }

  function fmt(x, d) { return (x >= 0 ? "+" : "\u2212") + Math.abs(x).toFixed(d); }
  function fmtUnit(i, v) { return R.joints[i].type === "R" ? (v * DEG).toFixed(2) + "\u00b0" : (v * 1000).toFixed(1) + " mm"; }
  function el(id) { return document.getElementById(id); }
  function message(text) { el("rk-msg").textContent = text || ""; }

  // ------------------------------------------------------------------ 3-D view (meshcat)
  var viewer = null, visualNodes = [], frameNodes = [], labelNodes = [];
  function startViewer() {
    try {
      var pane = el("meshcat-pane");
      viewer = new MeshCat.Viewer(pane);
      var own = viewer.set_3d_pane_size.bind(viewer);
      viewer.set_3d_pane_size = function (w, h) {  // the pane, not the whole window
        own(w === undefined ? pane.clientWidth : w, h === undefined ? pane.clientHeight : h);
      };
      viewer.set_3d_pane_size();
      RK_SCENE.forEach(function (b64) {  // base64 msgpack, or the command itself (robokit.viz.teach._scene_entry)
        if (typeof b64 !== "string") { viewer.handle_command(b64); return; }
        var bin = atob(b64), bytes = new Uint8Array(bin.length);
        for (var i = 0; i < bin.length; i++) { bytes[i] = bin.charCodeAt(i); }
        viewer.handle_command_bytearray(bytes);
      });
      var split = function (path) { return path.split("/").filter(function (s) { return s.length > 0; }); };
      visualNodes = R.visuals.map(function (v) { return viewer.scene_tree.find(split(v.path)); });
      frameNodes = R.frames.map(function (f) { return viewer.scene_tree.find(split(f.path)); });
      labelNodes = R.labels.map(function (l) { return viewer.scene_tree.find(split(l.path)); });
      obstacleNodes = R.collision ? R.collision.obstacle_paths.map(function (p) { return viewer.scene_tree.find(split(p)); }) : [];
      frameView();
      var size = [pane.clientWidth, pane.clientHeight];
      var refit = function () {
        if (pane.clientWidth === size[0] && pane.clientHeight === size[1]) { return; }
        size = [pane.clientWidth, pane.clientHeight];
        viewer.set_3d_pane_size();
        frameView();
        measureFraming();
      };
      window.addEventListener("resize", refit);
      if (window.ResizeObserver) { new ResizeObserver(refit).observe(pane); }
    } catch (err) {
      viewer = null;
      message("3-D view unavailable (" + err + "); the readouts still work.");
    }
  }

  // The camera: target and distance fitted (RKMath.fitCamera) so that the robot's reach (the
  // frame origins over many configurations, R.camera.points, grown by R.camera.pad; base
  // frame) fills the canvas inside a margin, below meshcat's controls bar. three.js's orbit controls look at the origin of the world (camera.lookAt
  // takes a world point), so the content is shifted by -target and the camera orbits the
  // origin; the camera sits in a frame rotated so that three.js's y is the base's z: a
  // base-frame offset (x, y, z) is (x, z, -y) there.
  var MARGIN = 14;  // px kept free around the robot's reach
  function overlays() {
    var pr = el("meshcat-pane").getBoundingClientRect(), out = [];
    // meshcat's controls (dat.GUI, top right of the view; closed, only its button shows)
    document.querySelectorAll(".dg.main, .dg.main .close-button").forEach(function (g) {
      var r = g.getBoundingClientRect();
      if (r.width > 0 && r.height > 0 && r.bottom > pr.top && r.top < pr.bottom && r.right > pr.left && r.left < pr.right) {
        out.push([r.left, r.top, r.right, r.bottom]);
      }
    });
    return out;
  }
  function frameView() {
    if (!viewer) { return; }
    var pane = el("meshcat-pane"), w = pane.clientWidth, h = pane.clientHeight;
    if (w < 20 || h < 20) { return; }
    var pr = pane.getBoundingClientRect(), top = MARGIN;
    overlays().forEach(function (r) { top = Math.max(top, r[3] - pr.top + 6); });
    top = Math.min(top, 0.4 * h);
    var win = { xlo: -1 + 2 * MARGIN / w, xhi: 1 - 2 * MARGIN / w, ylo: -1 + 2 * MARGIN / h, yhi: 1 - 2 * top / h };
    var fit = RKMath.fitCamera(R.camera.points, R.camera.pad, R.camera.direction, viewer.camera.fov, w / h, win);
    var t = fit.target, c = fit.position;
    var shift = [1, 0, 0, -t[0], 0, 1, 0, -t[1], 0, 0, 1, -t[2], 0, 0, 0, 1];
    ["meshcat/robot", "meshcat/frames", "meshcat/labels", "meshcat/floor", "meshcat/obstacles", "Axes"].forEach(function (p) {
      var node = viewer.scene_tree.find(p.split("/"));
      if (node) { node.set_transform(colMajor(shift)); }
    });
    viewer.camera.position.set(c[0] - t[0], c[2] - t[2], -(c[1] - t[1]));
    viewer.controls.update();
    viewer.set_dirty();
    el("rk-framing").dataset.target = t.map(String).join(",");
  }

  // where the robot is drawn: its bounding box (three.js, at the current joint values)
  // projected by the camera, in page pixels, next to the canvas and the panels (for tests)
  function measureFraming() {
    if (!viewer) { return; }
    var THREE = MeshCat.THREE, node = viewer.scene_tree.find(["meshcat", "robot"]);
    viewer.scene.updateMatrixWorld(true);
    viewer.camera.updateMatrixWorld(true);
    var box = new THREE.Box3().setFromObject(node.object);
    if (box.isEmpty()) { return; }
    var pane = el("meshcat-pane"), pr = pane.getBoundingClientRect();
    var x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (var k = 0; k < 8; k++) {
      var v = new THREE.Vector3((k & 1) ? box.max.x : box.min.x, (k & 2) ? box.max.y : box.min.y,
                                (k & 4) ? box.max.z : box.min.z).project(viewer.camera);
      var px = pr.left + 0.5 * (v.x + 1) * pr.width, py = pr.top + 0.5 * (1 - v.y) * pr.height;
      x0 = Math.min(x0, px); x1 = Math.max(x1, px); y0 = Math.min(y0, py); y1 = Math.max(y1, py);
    }
    var rect = function (id) { var r = el(id).getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom].join(","); };
    var cv = viewer.renderer.domElement;
    setData("rk-framing", { robot: [x0, y0, x1, y1].join(","), view: [pr.left, pr.top, pr.right, pr.bottom].join(","),
                            canvas: [cv.clientWidth, cv.clientHeight].join(","),
                            side: rect("rk-side"), readouts: rect("rk-readouts"),
                            overlays: JSON.stringify(overlays()) });
  }

  // ------------------------------------------------------------------ collision display
  // R.collision (robokit.viz.clearance.clearance_page_data): the robot's capsules, the
  // obstacles and the checked pairs; RKMath.clearance gives the distances. Visuals on a
  // link in contact and obstacles in contact are painted red (their own colours kept in
  // the materials' userData and put back when the contact ends).
  var RED = 0xE0302A, obstacleNodes = [];
  function materials(node, fn) {
    if (!node) { return; }
    node.object.traverse(function (o) {
      (Array.isArray(o.material) ? o.material : (o.material ? [o.material] : [])).forEach(function (m) {
        if (m.color) { fn(m); }
      });
    });
  }
  function paint(node, on) {
    materials(node, function (m) {
      if (m.userData.rkColor === undefined) { m.userData.rkColor = m.color.getHex(); }
      m.color.setHex(on ? RED : m.userData.rkColor);
    });
  }
  function colourOf(node) { var c = null; materials(node, function (m) { if (c === null) { c = m.color.getHex(); } }); return c; }
  function fmtPair(p) { return p[0] + " \u2013 " + p[1]; }
  function updateCollision(P) {
    var C = R.collision, box = el("rk-collision");
    if (!C) { return; }
    if (!C.supported) {
      box.className = "rk-na";
      box.textContent = C.reason;
      setData("rk-collision", { supported: "false" });
      return;
    }
    var c = RKMath.clearance(C, P), hitJ = {}, hitN = {}, red = [];
    c.joints.forEach(function (k) { hitJ[k] = true; });
    c.pairs.forEach(function (p) { hitN[p[0]] = true; hitN[p[1]] = true; });
    R.visuals.forEach(function (v, i) {
      var on = hitJ[v.k] === true;
      if (viewer) { paint(visualNodes[i], on); }
      if (on) { red.push(v.path); }
    });
    C.obstacles_drawn.forEach(function (name, k) {
      var on = hitN[name] === true;
      if (viewer) { paint(obstacleNodes[k], on); }
      if (on) { red.push(C.obstacle_paths[k]); }
    });
    if (c.pairs.length) {
      box.className = "rk-contact";
      box.textContent = "In contact: " + c.pairs.map(fmtPair).join(", ") + " (distance " + c.distance.toFixed(4) + " m)";
    } else if (c.closest) {
      box.className = "rk-free";
      box.textContent = "Minimum distance " + c.distance.toFixed(4) + " m (" + fmtPair(c.closest) + ")";
    } else {
      box.className = "rk-free";
      box.textContent = "No pair to check";
    }
    var colours = {};
    if (viewer) {
      R.visuals.forEach(function (v, i) { colours[v.path] = colourOf(visualNodes[i]); });
      C.obstacle_paths.forEach(function (p, k) { colours[p] = colourOf(obstacleNodes[k]); });
    }
    setData("rk-collision", { supported: "true", distance: String(c.distance), closest: JSON.stringify(c.closest),
                              pairs: JSON.stringify(c.pairs), links: JSON.stringify(c.links), red: JSON.stringify(red),
                              colours: JSON.stringify(colours) });
  }

  // column-major (three.js) copy of a row-major 4x4
  function colMajor(T) {
    return [T[0], T[4], T[8], T[12], T[1], T[5], T[9], T[13], T[2], T[6], T[10], T[14], T[3], T[7], T[11], T[15]];
  }

  var scenePoses = {};
  function placeObjects(P) {
    scenePoses = {};
    R.visuals.forEach(function (v, i) {
      var T = mul4(P[v.k], flat4(v.T));
      scenePoses[v.path] = T;
      if (viewer) { visualNodes[i].set_transform(colMajor(T)); }
    });
    R.frames.forEach(function (f, i) {
      var T = mul4(P[f.k], flat4(f.T));
      scenePoses[f.path] = T;
      if (viewer) { frameNodes[i].set_transform(colMajor(T)); }
    });
    // labels: upright above their frame's origin, by 0.9 label heights plus 1.1 more for each
    // earlier label whose origin is within one height (a stack where origins coincide; as
    // robokit.viz._labels.label_offsets does for the view pages)
    var origins = R.labels.map(function (l) { var T = scenePoses[R.frames[l.frame].path]; return [T[3], T[7], T[11]]; });
    R.labels.forEach(function (l, i) {
      var o = origins[i], below = 0;
      for (var j = 0; j < i; j++) {
        if (Math.hypot(o[0] - origins[j][0], o[1] - origins[j][1], o[2] - origins[j][2]) < l.height) { below++; }
      }
      var z = o[2] + (0.9 + 1.1 * below) * l.height;
      if (viewer) { labelNodes[i].set_transform(colMajor([1, 0, 0, o[0], 0, 1, 0, o[1], 0, 0, 1, z, 0, 0, 0, 1])); }
    });
    if (viewer) { viewer.set_dirty(); }
  }

  // small 3-vector helpers (arrays) for the gizmo's drags, in the base frame
  function v3sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function v3add(a, b, s) { return [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]; }
  function v3dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function v3cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  // the point where the ray o + t d (t >= 0) meets the plane through p with normal nrm (null: none)
  function rayPlane(o, d, p, nrm) {
    var den = v3dot(nrm, d);
    if (Math.abs(den) < 1e-9) { return null; }
    var t = v3dot(nrm, v3sub(p, o)) / den;
    return t < 0 ? null : v3add(o, d, t);
  }
  // the parameter s of the point p + s a (|a| = 1) nearest the line o + t d (|d| = 1; null: parallel)
  function lineParam(p, a, o, d) {
    var b = v3dot(a, d), w = v3sub(p, o), den = 1 - b * b;
    if (den < 1e-9) { return null; }
    return (b * v3dot(d, w) - v3dot(a, w)) / den;
  }
  // the rotation by angle about the unit axis u (Rodrigues), row-major 3x3 as 9 numbers
  function rotAbout(u, angle) {
    var c = Math.cos(angle), s = Math.sin(angle), t = 1 - c, x = u[0], y = u[1], z = u[2];
    return [t * x * x + c, t * x * y - s * z, t * x * z + s * y,
            t * x * y + s * z, t * y * y + c, t * y * z - s * x,
            t * x * z - s * y, t * y * z + s * x, t * z * z + c];
  }

  // ------------------------------------------------------------------ drag the tool (gizmo)
  // A transform gizmo on the tool frame, drawn over the scene: a ball (drag: the position moves in
  // the plane through the tool that faces the pointer), three arrows along the tool's x, y, z
  // (drag: the position moves along that axis) and three rings about them (drag: the tool turns
  // about that axis, its origin kept). Each move makes a target pose T (16 numbers, row-major,
  // base frame) and calls drag(T), which is goToTarget, the entry point of #T= (also
  // window.rkDrag): the arm follows on the IK solution nearest its current joint values. Out of
  // reach the gizmo turns red and the arm stays (an arm of fewer than six joints, which takes only some
  // poses, moves toward the target by damped least squares instead). #rk-gizmo holds its state and where its handles
  // are on the page (px, for tests).
  var gizmo = null, lastT = null, GIZMO_COLOUR = 0xF39C12, AXIS_COLOURS = [0xE74C3C, 0x27AE60, 0x2E86DE];
  var AXES = ["x", "y", "z"];
  function drag(T) { return goToTarget(T, "drag"); }
  function baseRay(clientX, clientY) {  // the pointer's ray in the base frame (and three's raycaster)
    var THREE = MeshCat.THREE, canvas = viewer.renderer.domElement, rc = canvas.getBoundingClientRect();
    var rayc = new THREE.Raycaster();
    viewer.scene.updateMatrixWorld(true);
    rayc.setFromCamera(new THREE.Vector2(2 * (clientX - rc.left) / rc.width - 1, 1 - 2 * (clientY - rc.top) / rc.height),
                       viewer.camera);
    var base = viewer.scene_tree.find(["meshcat", "frames"]).object;
    var inv = new THREE.Matrix4().copy(base.matrixWorld).invert();
    var o = rayc.ray.origin.clone().applyMatrix4(inv), d = rayc.ray.direction.clone().transformDirection(inv);
    return { caster: rayc, o: [o.x, o.y, o.z], d: [d.x, d.y, d.z] };
  }
  function startGizmo() {
    if (!viewer || !KIN) { return; }
    var THREE = MeshCat.THREE, node = viewer.scene_tree.find(["meshcat", "frames"]);
    if (!node) { return; }
    var s = R.scale, group = new THREE.Group(), picks = [], looks = [];
    group.matrixAutoUpdate = false;
    node.object.add(group);  // that node's coordinates are the base frame's (frameView shifts the node)
    function mesh(geom, colour, opacity, list, mode, axis) {
      var m = new THREE.Mesh(geom, new THREE.MeshBasicMaterial({ color: colour, transparent: true, opacity: opacity,
                                                                  depthTest: false, depthWrite: false }));
      m.renderOrder = 1000;
      m.userData = { mode: mode, axis: axis, colour: colour };
      group.add(m);
      list.push(m);
      return m;
    }
    mesh(new THREE.SphereGeometry(0.2 * s, 24, 16), GIZMO_COLOUR, 0.85, looks, "free", -1);
    mesh(new THREE.SphereGeometry(0.24 * s, 12, 8), GIZMO_COLOUR, 0, picks, "free", -1);
    for (var a = 0; a < 3; a++) {
      // built along three's y (arrows) or about its z (rings), then turned onto the tool's axis a
      var onto = new THREE.Matrix4();
      if (a === 0) { onto.makeRotationZ(-Math.PI / 2); } else if (a === 2) { onto.makeRotationX(Math.PI / 2); }
      var ring = new THREE.Matrix4();
      if (a === 0) { ring.makeRotationY(Math.PI / 2); } else if (a === 1) { ring.makeRotationX(Math.PI / 2); }
      var shaft = new THREE.CylinderGeometry(0.03 * s, 0.03 * s, 1.0 * s, 8).translate(0, 0.75 * s, 0).applyMatrix4(onto);
      var tip = new THREE.ConeGeometry(0.09 * s, 0.25 * s, 16).translate(0, 1.375 * s, 0).applyMatrix4(onto);
      mesh(shaft, AXIS_COLOURS[a], 0.9, looks, "move-" + AXES[a], a);
      mesh(tip, AXIS_COLOURS[a], 0.9, looks, "move-" + AXES[a], a);
      mesh(new THREE.CylinderGeometry(0.1 * s, 0.1 * s, 1.3 * s, 8).translate(0, 0.9 * s, 0).applyMatrix4(onto),
           AXIS_COLOURS[a], 0, picks, "move-" + AXES[a], a);
      mesh(new THREE.TorusGeometry(1.0 * s, 0.018 * s, 8, 96).applyMatrix4(ring), AXIS_COLOURS[a], 0.9, looks, "turn-" + AXES[a], a);
      mesh(new THREE.TorusGeometry(1.0 * s, 0.08 * s, 8, 48).applyMatrix4(ring), AXIS_COLOURS[a], 0, picks, "turn-" + AXES[a], a);
    }
    gizmo = { group: group, picks: picks, looks: looks, drag: null, reachable: true, mode: "" };
    var canvas = viewer.renderer.domElement;
    canvas.addEventListener("pointerdown", function (ev) {
      var mode = lastT ? gizmoPick(ev.clientX, ev.clientY) : null;
      if (!mode) { return; }
      var T0 = lastT.slice(), p0 = [T0[3], T0[7], T0[11]], r = baseRay(ev.clientX, ev.clientY), dr = gizmo.drag = { mode: mode.mode, T0: T0, p0: p0 };
      if (mode.axis >= 0) { dr.u = [T0[mode.axis], T0[4 + mode.axis], T0[8 + mode.axis]]; }  // the tool's axis, base frame
      if (mode.mode === "free") { dr.nrm = r.d; dr.hit0 = rayPlane(r.o, r.d, p0, r.d) || p0; }
      if (mode.mode.indexOf("move-") === 0) { dr.s0 = lineParam(p0, dr.u, r.o, r.d); }
      if (mode.mode.indexOf("turn-") === 0) { dr.hit0 = rayPlane(r.o, r.d, p0, dr.u); }
      gizmo.mode = mode.mode;
      viewer.controls.enabled = false;  // the drag moves the tool, not the camera
      try { canvas.setPointerCapture(ev.pointerId); } catch (e) { /* a synthetic pointer */ }
      ev.stopImmediatePropagation();
      ev.preventDefault();
    }, true);
    canvas.addEventListener("pointermove", function (ev) {
      var dr = gizmo.drag;
      if (!dr) { return; }
      ev.stopImmediatePropagation();
      var r = baseRay(ev.clientX, ev.clientY), T = dr.T0.slice();
      if (dr.mode === "free") {
        var hit = rayPlane(r.o, r.d, dr.p0, dr.nrm);
        if (!hit) { return; }
        var p = v3add(dr.p0, v3sub(hit, dr.hit0), 1);
        T[3] = p[0]; T[7] = p[1]; T[11] = p[2];
      } else if (dr.mode.indexOf("move-") === 0) {
        var sv = lineParam(dr.p0, dr.u, r.o, r.d);
        if (sv === null || dr.s0 === null) { return; }
        var pm = v3add(dr.p0, dr.u, sv - dr.s0);
        T[3] = pm[0]; T[7] = pm[1]; T[11] = pm[2];
      } else {
        var h = rayPlane(r.o, r.d, dr.p0, dr.u);
        if (!h || !dr.hit0) { return; }
        var a0 = v3sub(dr.hit0, dr.p0), a1 = v3sub(h, dr.p0);
        var ang = Math.atan2(v3dot(dr.u, v3cross(a0, a1)), v3dot(a0, a1)), Q = rotAbout(dr.u, ang);
        for (var i = 0; i < 3; i++) {
          for (var j = 0; j < 3; j++) {
            T[4 * i + j] = Q[3 * i] * dr.T0[j] + Q[3 * i + 1] * dr.T0[4 + j] + Q[3 * i + 2] * dr.T0[8 + j];
          }
        }
      }
      drag(T);
    }, true);
    var end = function () { if (gizmo.drag) { gizmo.drag = null; viewer.controls.enabled = true; } };
    canvas.addEventListener("pointerup", end, true);
    canvas.addEventListener("pointercancel", end, true);
  }
  // the gizmo handle under the page pixel (x, y): {mode, axis} or null
  function gizmoPick(x, y) {
    if (!gizmo) { return null; }
    var hits = baseRay(x, y).caster.intersectObjects(gizmo.picks, false), ball = hits.filter(function (h) { return h.object.userData.mode === "free"; });
    return ball.length ? ball[0].object.userData : (hits.length ? hits[0].object.userData : null);  // the ball before what crosses it
  }
  function gizmoPaint(reachable) {
    if (!gizmo) { return; }
    gizmo.reachable = reachable;
    gizmo.looks.forEach(function (m) { m.material.color.setHex(reachable ? m.userData.colour : RED); });
  }
  function toPage(p) {  // a base-frame point -> page pixels
    var THREE = MeshCat.THREE, v = new THREE.Vector3(p[0], p[1], p[2]);
    v.applyMatrix4(viewer.scene_tree.find(["meshcat", "frames"]).object.matrixWorld).project(viewer.camera);
    var rc = viewer.renderer.domElement.getBoundingClientRect();
    return [rc.left + 0.5 * (v.x + 1) * rc.width, rc.top + 0.5 * (1 - v.y) * rc.height];
  }
  function placeGizmo(T, reachable) {
    lastT = T;
    if (!gizmo) { return; }
    gizmo.group.matrix.fromArray(colMajor(T));
    gizmo.group.matrixWorldNeedsUpdate = true;
    if (reachable !== undefined) { gizmoPaint(reachable); }
    viewer.scene.updateMatrixWorld(true);
    // where each handle can be grabbed (a point the page's own picking gives to it), for tests
    var p = [T[3], T[7], T[11]], c = toPage(p), s = R.scale, handles = {};
    for (var a = 0; a < 3; a++) {
      var u = [T[a], T[4 + a], T[8 + a]], e1 = [T[(a + 1) % 3], T[4 + (a + 1) % 3], T[8 + (a + 1) % 3]];
      var e2 = [T[(a + 2) % 3], T[4 + (a + 2) % 3], T[8 + (a + 2) % 3]];
      [1.0, 1.3, 0.7, 1.45, 0.5, 0.4].some(function (f) {
        var xy = toPage(v3add(p, u, f * s)), m = gizmoPick(xy[0], xy[1]);
        if (m && m.mode === "move-" + AXES[a]) { handles[m.mode] = xy; return true; }
        return false;
      });
      [1, 3, 5, 7, 0, 2, 4, 6].some(function (k) {
        var ang = k * Math.PI / 4, xy = toPage(v3add(v3add(p, e1, s * Math.cos(ang)), e2, s * Math.sin(ang))), m = gizmoPick(xy[0], xy[1]);
        if (m && m.mode === "turn-" + AXES[a]) { handles[m.mode] = xy; return true; }
        return false;
      });
    }
    setData("rk-gizmo", { x: String(c[0]), y: String(c[1]), reachable: String(gizmo.reachable), mode: gizmo.mode,
                          handles: JSON.stringify(handles) });
    viewer.set_dirty();
  }

  // ------------------------------------------------------------------ ghost arms (every IK branch)
  // Every closed-form solution of the last target is drawn as a faint copy of the arm (the robot's
  // visuals, placed through placementsAt), with its label from the module (ik_analytic's wording):
  // green when within the joint limits and (with obstacles in the page) collision-free, grey
  // outside the limits, red in collision. Clicking a ghost, or its button under the sliders,
  // selects that branch. #rk-ghosts: what is drawn (for tests).
  var ghosts = { group: null, arms: [], sols: [], chosen: -1, shown: true, textures: {} };
  var GHOST_COLOURS = { ok: 0x1E9E55, limits: 0x8A94A6, collision: 0xE0302A };
  function startGhosts() {
    if (!viewer || !KIN || !KIN.hasIk) { return; }
    var node = viewer.scene_tree.find(["meshcat", "frames"]);
    if (!node) { return; }
    ghosts.group = new MeshCat.THREE.Group();
    node.object.add(ghosts.group);
    viewer.controls.addEventListener("change", layoutLabels);
  }
  function labelTexture(text, colour) {  // a canvas with the label, cached by text and colour
    var key = text + "|" + colour;
    if (ghosts.textures[key]) { return ghosts.textures[key]; }
    var cv = document.createElement("canvas"), ctx = cv.getContext("2d"), px = 40, font = "600 " + px + "px system-ui, sans-serif";
    ctx.font = font;
    cv.width = Math.ceil(ctx.measureText(text).width) + 24; cv.height = px + 20;
    ctx.font = font;
    ctx.fillStyle = "rgba(255,255,255,0.88)"; ctx.fillRect(0, 0, cv.width, cv.height);
    ctx.strokeStyle = "#" + ("00000" + colour.toString(16)).slice(-6); ctx.lineWidth = 5; ctx.strokeRect(2, 2, cv.width - 4, cv.height - 4);
    ctx.fillStyle = "#1d2330"; ctx.textBaseline = "middle"; ctx.fillText(text, 12, cv.height / 2 + 1);
    var tex = new MeshCat.THREE.CanvasTexture(cv);
    tex.userData = { aspect: cv.width / cv.height };
    ghosts.textures[key] = tex;
    return tex;
  }
  function ghostArm(k) {  // built on first use, then reused (only placed and coloured)
    if (ghosts.arms[k]) { return ghosts.arms[k]; }
    var THREE = MeshCat.THREE, mat = new THREE.MeshBasicMaterial({ color: GHOST_COLOURS.ok, transparent: true, opacity: 0.22,
                                                                    depthWrite: false });
    var arm = { root: new THREE.Group(), parts: [], mat: mat, text: "" };
    R.visuals.forEach(function (v, i) {
      var o = visualNodes[i] ? visualNodes[i].object.clone(true) : new THREE.Group();
      o.traverse(function (c) {
        if (c.isMesh) { c.material = mat; c.userData = { rkGhost: k }; } else if (c.material) { c.visible = false; }
      });
      arm.root.add(o);
      arm.parts.push(o);
    });
    arm.label = new THREE.Sprite(new THREE.SpriteMaterial({ depthTest: false, depthWrite: false, transparent: true,
                                                            sizeAttenuation: false }));
    arm.label.renderOrder = 900;
    arm.label.userData = { rkGhost: k };
    arm.root.add(arm.label);
    ghosts.group.add(arm.root);
    ghosts.arms[k] = arm;
    return arm;
  }
  function setPose(obj, T) { new MeshCat.THREE.Matrix4().fromArray(colMajor(T)).decompose(obj.position, obj.quaternion, obj.scale); }
  function showGhosts(sols, chosen) {
    ghosts.sols = sols; ghosts.chosen = chosen;
    var status = [], origins = [];
    sols.forEach(function (sol, k) {
      var P = placementsAt(sol.q), st = [];
      if (!sol.withinLimits) { st.push("limits"); }
      if (R.collision && R.collision.supported && RKMath.clearance(R.collision, P).pairs.length) { st.push("collision"); }
      status.push(st.length ? st.join("+") : "ok");
      origins.push((R.frames.length ? R.frames.map(function (f) { return mul4(P[f.k], flat4(f.T)); }) : [KIN.fk(sol.q)])
        .map(function (T) { return [T[3], T[7], T[11]]; }));
      if (!ghosts.group) { return; }
      var arm = ghostArm(k), colour = GHOST_COLOURS[st.length ? st[st.length - 1] : "ok"];
      R.visuals.forEach(function (v, i) { setPose(arm.parts[i], mul4(P[v.k], flat4(v.T))); });
      arm.mat.color.setHex(colour);
      arm.mat.opacity = k === chosen ? 0.12 : 0.25;
      var text = (k + 1) + " " + sol.label + (st.length ? " (" + st.join(", ").replace("limits", "outside limits") + ")" : "");
      var tex = labelTexture(text, colour);
      if (arm.label.material.map !== tex) { arm.label.material.map = tex; arm.label.material.needsUpdate = true; }
      arm.label.material.opacity = k === chosen ? 1.0 : 0.85;
      arm.label.scale.set(LABEL_SCREEN * tex.userData.aspect, LABEL_SCREEN, 1);
    });
    // each label at the frame origin that differs most between the branches (the elbow, say)
    var spread = (origins[0] || []).map(function (_, i) {
      var m = [0, 0, 0], v = 0;
      origins.forEach(function (o) { m = v3add(m, o[i], 1 / origins.length); });
      origins.forEach(function (o) { var e = v3sub(o[i], m); v += v3dot(e, e); });
      return v;
    });
    var at = spread.indexOf(Math.max.apply(null, spread));
    origins.forEach(function (o, k) { if (ghosts.group) { ghosts.arms[k].label.position.set(o[at][0], o[at][1], o[at][2]); } });
    ghosts.arms.forEach(function (arm, k) { arm.root.visible = ghosts.shown && k < sols.length; });
    layoutLabels();
    setData("rk-ghosts", { count: String(ghosts.group ? sols.length : 0), labels: JSON.stringify(sols.map(function (s2) { return s2.label; })),
                           status: JSON.stringify(status), chosen: String(chosen), shown: String(ghosts.shown) });
    branchButtons(sols, chosen, status);
    if (viewer) { viewer.set_dirty(); }
  }
  // labels keep one size on the screen (LABEL_SCREEN: a fraction of the view's height, about) and
  // are moved up, a label height at a time, until none covers another (again when the camera moves)
  var LABEL_SCREEN = 0.045;
  function layoutLabels() {
    if (!ghosts.group) { return; }
    viewer.scene.updateMatrixWorld(true);
    var rc = viewer.renderer.domElement.getBoundingClientRect();
    var px = LABEL_SCREEN * viewer.camera.projectionMatrix.elements[5] * 0.5 * rc.height, placed = [];
    ghosts.arms.slice(0, ghosts.sols.length).forEach(function (arm) {
      var v = new MeshCat.THREE.Vector3().setFromMatrixPosition(arm.label.matrixWorld).project(viewer.camera);
      var x = 0.5 * (v.x + 1) * rc.width, y = 0.5 * (1 - v.y) * rc.height, w = px * arm.label.scale.x / arm.label.scale.y;
      var up = 0.6, box;
      for (var tries = 0; tries < 16; tries++) {
        box = [x - w / 2, y - (up + 0.5) * px, x + w / 2, y - (up - 0.5) * px];
        if (!placed.some(function (b) { return b[0] < box[2] && box[0] < b[2] && b[1] < box[3] && box[1] < b[3]; })) { break; }
        up += 1.1;
      }
      placed.push(box);
      arm.label.center.set(0.5, 0.5 - up);
    });
    viewer.set_dirty();
  }

  // the ghost under the page pixel (x, y), through the page's picking: a ghost's label first
  // (drawn over everything), else the nearest of the ghosts' and the arm's surfaces (the arm is
  // the chosen branch's). -1: none.
  function pickGhost(x, y) {
    if (!ghosts.group || !ghosts.shown || !ghosts.sols.length) { return -1; }
    var caster = baseRay(x, y).caster, live = ghosts.arms.slice(0, ghosts.sols.length);
    var hits = caster.intersectObjects(live.map(function (a) { return a.label; }), false);
    if (hits.length) { return hits[0].object.userData.rkGhost; }
    var robot = viewer.scene_tree.find(["meshcat", "robot"]).object;
    hits = caster.intersectObjects(live.map(function (a) { return a.root; }).concat([robot]), true).filter(function (hh) {
      return hh.object.visible && hh.object.isMesh;
    });
    if (!hits.length) { return -1; }
    var g = hits[0].object.userData.rkGhost;
    return g === undefined ? ghosts.chosen : g;
  }
  // a page pixel where pickGhost gives k (its label's centre, else a point of its surface), for tests
  function ghostPoint(k) {
    var arm = ghosts.arms[k];
    if (!arm || !arm.root.visible) { return null; }
    viewer.scene.updateMatrixWorld(true);
    var rc = viewer.renderer.domElement.getBoundingClientRect(), THREE = MeshCat.THREE, found = null;
    function tryAt(v) {
      v.project(viewer.camera);
      var x = rc.left + 0.5 * (v.x + 1) * rc.width, y = rc.top + 0.5 * (1 - v.y) * rc.height;
      if (x > rc.left && x < rc.right && y > rc.top && y < rc.bottom && pickGhost(x, y) === k) { found = [x, y]; }
      return found !== null;
    }
    if (tryAt(new THREE.Vector3().setFromMatrixPosition(arm.label.matrixWorld))) { return found; }
    arm.root.traverse(function (c) {
      if (found || !c.isMesh || !c.geometry.attributes.position) { return; }
      var pos = c.geometry.attributes.position, step = Math.max(1, Math.floor(pos.count / 64));
      for (var i = 0; i < pos.count && !found; i += step) {
        tryAt(new THREE.Vector3().fromBufferAttribute(pos, i).applyMatrix4(c.matrixWorld));
      }
    });
    return found;
  }
  function startGhostPicking() {
    if (!ghosts.group) { return; }
    var canvas = viewer.renderer.domElement, down = null;
    canvas.addEventListener("pointerdown", function (ev) { down = [ev.clientX, ev.clientY]; }, true);
    canvas.addEventListener("pointerup", function (ev) {
      var d = down;
      down = null;
      if (!d || Math.hypot(ev.clientX - d[0], ev.clientY - d[1]) > 4) { return; }  // a camera drag, not a click
      var k = pickGhost(ev.clientX, ev.clientY);
      if (k >= 0 && k !== ghosts.chosen) { selectBranch(k, "click"); }
    }, true);
  }
  // the branches as buttons under the sliders (the same choice as clicking a ghost), and the
  // switch that shows or hides the ghosts
  function branchButtons(sols, chosen, status) {
    var box = el("rk-branches");
    box.innerHTML = "";
    if (!sols.length) { return; }
    var head = document.createElement("label");
    head.className = "rk-small";
    head.innerHTML = '<input type="checkbox" id="rk-ghosts-shown"> show every branch as a ghost arm (click one to take it)';
    head.querySelector("input").checked = ghosts.shown;
    head.querySelector("input").addEventListener("change", function (ev) { ghosts.shown = ev.target.checked; showGhosts(ghosts.sols, ghosts.chosen); });
    box.appendChild(head);
    sols.forEach(function (s, k) {
      var b = document.createElement("button");
      b.id = "rk-branch-" + k;
      b.className = "rk-branch rk-ghost-" + status[k].split("+").pop() + (k === chosen ? " rk-chosen" : "");
      b.textContent = (k + 1) + " " + s.label;
      b.title = status[k] === "ok" ? "within the limits" + (R.collision && R.collision.supported ? ", collision-free" : "") :
        status[k].replace("limits", "outside the joint limits").replace("+", ", ").replace("collision", "in collision");
      b.addEventListener("click", function () { selectBranch(k, "button"); });
      box.appendChild(b);
    });
  }
  // take branch k of the last target (a click on its ghost or its button)
  function selectBranch(k, why) {
    var s = ghosts.sols[k];
    if (!s) { return -1; }
    var from = branch.label;
    setData("rk-ik", { chosen: String(k), branchChange: "chosen", branchFrom: from || "", branchTo: s.label,
                       branchGap: String(jointGap(q, s.q)) });
    branch.label = s.label;
    ikText(ghosts.sols, k, "chosen");
    moveByIk(s.q, why + " (branch " + (k + 1) + ")");
    showGhosts(ghosts.sols, k);
    return k;
  }

  // ------------------------------------------------------------------ branch tracking
  // The branch shown is the label of the chosen solution; along a drag the nearest solution keeps
  // it, and it changes only where two branches meet (their joint vectors coincide there). A change
  // is recorded (rk-ik data-branch-change, -from, -to, -gap: the largest joint step, rad / m) and
  // shown by the badge over the 3-D view. Moving a joint by hand forgets the branch and the ghosts.
  var branch = { label: null, ik: false, flashUntil: 0 };
  function jointGap(a, b) { var g = 0; for (var i = 0; i < n; i++) { g = Math.max(g, Math.abs(a[i] - b[i])); } return g; }
  function moveByIk(qv, why) { branch.ik = true; try { setQ(qv, why); } finally { branch.ik = false; } }
  function forgetBranch() {  // from update(): a move that is not the IK's
    if (branch.ik) { return; }
    branch.label = null;
    if (ghosts.sols.length) { showGhosts([], -1); }
    badge("", false);
  }
  function badge(text, change) {
    var b = el("rk-branch");
    if (!b) { return; }
    var now = Date.now();
    if (change) { branch.flashUntil = now + 1500; }
    b.hidden = !text;
    b.textContent = text;
    b.className = change || now < branch.flashUntil ? "rk-branch-change" : "";
  }
  function ikText(sols, k, change) {
    var box = el("rk-ik"), s = sols[k], d = el("rk-ik").dataset;
    box.className = "rk-small";
    box.textContent = "IK: " + sols.length + " solution" + (sols.length === 1 ? "" : "s") + "; showing " +
      (change === "chosen" ? "the chosen one, " : "the nearest, ") + (k + 1) + " \u201c" + s.label + "\u201d" +
      (s.withinLimits ? "" : " (outside the joint limits)");
    if (change === "true") {
      box.textContent += "; branch change from \u201c" + d.branchFrom + "\u201d (the branches meet here)";
    }
    badge("branch " + (k + 1) + " of " + sols.length + ": " + s.label +
          (change === "true" ? "  \u2014 changed from " + d.branchFrom + " (branches meet)" : ""), change === "true");
  }

  // ------------------------------------------------------------------ embedded (notebook pendant)
  // In a frame (the notebook pendant's drag view, robokit.viz.teach.teach_widget): every new q is
  // posted to the parent window as {rk: "teach-q", q}; {rk: "teach-set-q", q} from it moves the arm.
  function postQ() {
    if (window.parent === window) { return; }
    try { window.parent.postMessage({ rk: "teach-q", q: q.slice() }, "*"); } catch (e) { /* a closed parent */ }
  }
  window.addEventListener("message", function (ev) {
    if (ev.source !== window.parent || !ev.data || ev.data.rk !== "teach-set-q" || !Array.isArray(ev.data.q) ||
        ev.data.q.length !== n) { return; }
    setQ(ev.data.q.map(Number), "notebook");
  });

  // ------------------------------------------------------------------ page
  var sliders = [], boxes = [], rowsEls = [];
  function buildControls() {
    el("rk-title").textContent = R.name;
    el("rk-coll-card").hidden = !R.collision;
    el("rk-tip").textContent = "(" + R.tip + " in the base frame)";
    el("rk-rows").textContent = "(task rows J\u209c: " + R.rows.map(function (r) { return R.row_symbols[r]; }).join(", ") + ")";
    var poses = el("rk-poses");
    Object.keys(R.poses).forEach(function (name) {
      var b = document.createElement("button");
      b.textContent = name;
      b.id = "rk-pose-" + name;
      b.title = "q = [" + R.poses[name].map(function (v, i) { return fmtUnit(i, v); }).join(", ") + "]";
      b.addEventListener("click", function () { setQ(R.poses[name], "pose " + name); });
      poses.appendChild(b);
    });
    var box = el("rk-sliders");
    R.joints.forEach(function (j, i) {
      var u = unit[i], step = j.type === "R" ? 0.1 : 0.001;
      var div = document.createElement("div");
      div.className = "rk-joint";
      div.innerHTML =
        '<div class="rk-joint-name"></div><input type="range">' +
        '<span class="rk-joint-val"><input type="number"> <span class="rk-small"></span></span>' +
        '<div class="rk-joint-lim"><span></span><span></span></div>';
      div.querySelector(".rk-joint-name").textContent = "q" + (i + 1) + " " + j.name;
      div.querySelector(".rk-joint-name").title = j.name + (j.limited ? "" : " (no limits)");
      div.querySelector(".rk-joint-val .rk-small").textContent = j.type === "R" ? "deg" : "m";
      var r = div.querySelector("input[type=range]"), t = div.querySelector("input[type=number]");
      r.id = "rk-slider-" + i; t.id = "rk-value-" + i;
      [r, t].forEach(function (inp) {
        inp.min = (j.lo * u).toFixed(j.type === "R" ? 1 : 3);
        inp.max = (j.hi * u).toFixed(j.type === "R" ? 1 : 3);
        inp.step = String(step);
      });
      r.min = String(j.lo * u); r.max = String(j.hi * u); r.step = "any";
      var lims = div.querySelectorAll(".rk-joint-lim span");
      lims[0].textContent = fmtUnit(i, j.lo) + (j.limited ? "" : " (free)");
      lims[1].textContent = fmtUnit(i, j.hi);
      r.addEventListener("input", function () { q[i] = clampJoint(i, parseFloat(r.value) / u); update(undefined, i); });
      t.addEventListener("change", function () { q[i] = clampJoint(i, parseFloat(t.value) / u); update(); });
      box.appendChild(div);
      sliders.push(r); boxes.push(t); rowsEls.push(div);
    });
    var tbl = el("rk-jacobian"), head = "<tr><th></th>";
    for (var c = 0; c < n; c++) { head += "<th>q" + (c + 1) + "</th>"; }
    tbl.innerHTML = head + "</tr>";
    for (var rr = 0; rr < 6; rr++) {
      var tr = document.createElement("tr");
      if (R.rows.indexOf(rr) >= 0) { tr.className = "rk-task"; }
      tr.innerHTML = "<th>" + R.row_symbols[rr] + "</th>" + new Array(n + 1).join("<td></td>");
      tbl.appendChild(tr);
    }
  }

  function setQ(values, why) {
    var clamped = [];
    for (var i = 0; i < n; i++) {
      var v = clampJoint(i, values[i]);
      if (v !== values[i]) { clamped.push("q" + (i + 1)); }
      q[i] = v;
    }
    update(clamped.length ? why + ": " + clamped.join(", ") + " clamped to the slider range" : "");
  }

  // the #q= and #T= fragments (#q=...&T=...: start at q, then go to T): applied when valid;
  // otherwise the page says what it ignored and keeps saying it
  function readHash() {
    var f = RKMath.parseFragment(location.hash, n), t = RKMath.parseTarget(location.hash), done = false;
    if (f.q) { setQ(f.q, "URL"); done = true; } else if (f.given) { update(f.problem); done = true; }
    if (t.T) { goToTarget(t.T, "URL #T="); done = true; } else if (t.given) { update(t.problem); done = true; }
    return done;
  }

  // ------------------------------------------------------------------ inverse kinematics (module)
  // An arm without a closed form (a redundant one): damped-least-squares steps in the module from
  // the current q (the course's resolved-rate rule; the steps leave the null space as it is).
  // An arm of fewer than six joints (a planar one) reaches only some poses: where its closed form has no
  // solution (a target dragged off its plane), it too follows by damped least squares, toward the nearest
  // pose it can take; #rk-ik then keeps the closed form's answer (count 0, no solutions) and says so.
  var DLS = { lambda: 0.01, iters: 200, tol: 1e-12 };
  function followByDls(T, why, exactNone) {
    var r = KIN.dls(T, q, DLS.lambda, DLS.iters, DLS.tol), ok = r.steps >= 0, box = el("rk-ik");
    if (exactNone) {
      setData("rk-ik", { status: "dls-no-exact", count: "0", solutions: "[]", labels: "[]", within: "[]", chosen: "-1",
                         steps: String(r.steps), target: T.map(String).join(",") });
    } else {
      setData("rk-ik", { status: ok ? "dls" : "dls-not-converged", count: "1", solutions: JSON.stringify([r.q]),
                         labels: JSON.stringify(["damped least squares"]), within: "[]", chosen: "0",
                         steps: String(r.steps), target: T.map(String).join(",") });
    }
    box.className = ok ? "rk-small" : "rk-small rk-unreachable";
    box.textContent = (exactNone ? "IK: no exact solution (a " + n + "-joint arm takes only some poses); damped least squares "
                       + "(\u03bb = " + DLS.lambda + ") moves the tool toward the target: "
                       : R.name + " has no closed-form IK: damped least squares (\u03bb = " + DLS.lambda + ") ") +
      (ok ? "reached the target in " + r.steps + " steps" : (exactNone ? "as near as it gets in " + DLS.iters + " steps"
       : "did not reach the target in " + DLS.iters + " steps (out of reach or singular)")) +
      (exactNone ? "" : "; the null space is kept");
    showGhosts([], -1);
    setData("rk-ik", { branchChange: "false" });
    moveByIk(r.q, why + " (damped least squares)");
    gizmoPaint(ok);
    return exactNone ? -1 : 0;
  }

  // Every closed-form solution of the tool pose T (16 numbers, row-major, base frame), from the
  // module, in ik_analytic's order; the arm moves to the one nearest the current q (joint-space
  // distance) and #rk-ik records them all. Out of reach: the arm stays and the readout says so (fewer than
  // six joints: see followByDls).
  function goToTarget(T, why) {
    var box = el("rk-ik");
    if (!KIN.hasIk) { return followByDls(T, why); }
    var sols = KIN.ik(T, 0), k = RKWasm.nearest(sols, q);
    if (!sols.length && n < 6) { return followByDls(T, why, true); }
    setData("rk-ik", { status: sols.length ? "ok" : "unreachable", count: String(sols.length),
                       solutions: JSON.stringify(sols.map(function (s) { return s.q; })),
                       labels: JSON.stringify(sols.map(function (s) { return s.label; })),
                       within: JSON.stringify(sols.map(function (s) { return s.withinLimits; })), chosen: String(k),
                       target: T.map(String).join(",") });
    if (k < 0) {
      box.className = "rk-small rk-unreachable";
      box.textContent = "IK: the target is out of reach (no solution); the arm stays";
      setData("rk-ik", { branchChange: "false", branchFrom: branch.label || "", branchTo: "", branchGap: "0" });
      showGhosts([], -1);
      branch.ik = true;  // the arm stays on its branch
      try { update(null); } finally { branch.ik = false; }
      badge("out of reach: the arm stays", true);
      placeGizmo(T, false);  // the gizmo stays under the pointer, red; the arm stays
      return -1;
    }
    var s = sols[k], from = branch.label, change = from !== null && s.label !== from;
    setData("rk-ik", { branchChange: String(change), branchFrom: from || "", branchTo: s.label, branchGap: String(jointGap(q, s.q)) });
    branch.label = s.label;
    ikText(sols, k, String(change));
    moveByIk(s.q, why + " (IK)");
    gizmoPaint(true);
    showGhosts(sols, k);
    return k;
  }

  function setData(id, attrs) { var e = el(id); Object.keys(attrs).forEach(function (k) { e.dataset[k] = attrs[k]; }); return e; }

  // msg: null keeps the current message; skipSlider: the slider being dragged (not rewritten)
  function update(msg, skipSlider) {
    if (msg !== null && msg !== undefined) { message(msg); } else if (msg === undefined) { message(""); }
    for (var i = 0; i < n; i++) {
      if (i !== skipSlider) { sliders[i].value = String(q[i] * unit[i]); }
      boxes[i].value = (q[i] * unit[i]).toFixed(R.joints[i].type === "R" ? 2 : 4);
    }
    var rd = RKMath.readouts(R, q, KIN), P = placementsAt(q), T = rd.T, J = rd.J;
    placeObjects(P);
    updateCollision(P);
    forgetBranch();
    placeGizmo(T, true);

    // pose
    var xyz = rd.xyz, ang = rd.rpy, quat = rd.quat;
    el("rk-xyz").textContent = xyz.map(function (v) { return fmt(v, 4); }).join(" ");
    el("rk-rpy").textContent = ang.map(function (v) { return fmt(v * DEG, 2); }).join(" ");
    el("rk-quat").textContent = quat.map(function (v) { return fmt(v, 4); }).join(" ");
    setData("rk-pose", { source: "wasm", t: T.map(String).join(","), xyz: xyz.map(String).join(","),
                         rpy: ang.map(String).join(","), quat: quat.map(String).join(",") });

    // Jacobian
    var trs = el("rk-jacobian").rows;
    for (var r = 0; r < 6; r++) {
      for (var c = 0; c < n; c++) { trs[r + 1].cells[c + 1].textContent = fmt(J[r][c], 3); }
    }
    setData("rk-jacobian", { j: [].concat.apply([], J).map(String).join(","), rows: 6, cols: n });

    // measures on the task rows
    var w = rd.w, cond = rd.cond, smin = rd.sigmaMin, smax = rd.sigmaMax, ratio = rd.ratio, level = rd.level;
    el("rk-manip").textContent = w.toPrecision(5);
    setData("rk-manip", { value: String(w) });
    el("rk-cond").textContent = isFinite(cond) ? cond.toPrecision(4) : "\u221e";
    setData("rk-cond", { value: String(cond), sigmaMin: String(smin), sigmaMax: String(smax) });
    var u = rd.direction, kmax = rd.directionRow;
    var dirName = R.row_names[kmax] + " (" + u[kmax].toFixed(2) + ")";
    var sing = setData("rk-sing", { singular: level === "singular" ? "true" : "false", level: level,
                                    direction: u.map(String).join(","), name: dirName });
    sing.className = "rk-" + level;
    if (level === "ok") {
      sing.textContent = "No singularity nearby (\u03c3min/\u03c3max = " + ratio.toFixed(3) + ")";
    } else {
      sing.textContent = (level === "singular" ? "Singular: " : "Near a singularity: ") +
        "the arm cannot move along " + dirName + "; lost direction u = [" +
        u.map(function (x) { return fmt(x, 2); }).join(", ") + "] on (" +
        R.rows.map(function (rr) { return R.row_symbols[rr]; }).join(", ") + ")";
    }

    // joint-limit margins
    var margins = rd.margins, jmin = rd.marginJoint;
    for (i = 0; i < n; i++) {
      var j = R.joints[i], mg = margins[i];
      var frac = j.limited ? mg / (j.hi - j.lo) : 1;
      rowsEls[i].className = "rk-joint" + (mg <= 0 ? " rk-atlimit" : (frac < 0.05 ? " rk-near" : ""));
    }
    var me = setData("rk-margin", { value: String(jmin < 0 ? Infinity : margins[jmin]),
                                    joint: jmin < 0 ? "" : R.joints[jmin].name, margins: margins.map(String).join(",") });
    me.textContent = jmin < 0 ? "\u221e (no limits)" :
      fmtUnit(jmin, margins[jmin]) + "  (q" + (jmin + 1) + " " + R.joints[jmin].name + (margins[jmin] <= 0 ? ", AT LIMIT)" : ")");

    var qe = setData("rk-q", { q: q.map(String).join(",") });
    qe.textContent = "q = [" + q.map(function (v) { return v.toFixed(4); }).join(", ") + "] (rad / m)";
    el("rk-scene-poses").dataset.poses = JSON.stringify(scenePoses);
    measureFraming();
    postQ();
    try { history.replaceState(null, "", "#q=" + q.map(function (v) { return String(v); }).join(",")); } catch (e) { /* file:// in some browsers */ }
  }

  var ikBox = document.createElement("div");
  ikBox.id = "rk-ik";
  ikBox.className = "rk-small";
  el("rk-msg").insertAdjacentElement("afterend", ikBox);
  // the entry point of #T= and of the gizmo's drags (rkDrag), a branch choice (as a click on a
  // ghost) and a page pixel where the page's picking finds ghost k (for tests)
  window.RKTeach = { goToTarget: goToTarget, drag: drag, selectBranch: selectBranch, ghostPoint: ghostPoint };
  window.rkDrag = drag;
  var branchesBox = document.createElement("div");
  branchesBox.id = "rk-branches";
  ikBox.insertAdjacentElement("afterend", branchesBox);
  // hidden until used: the branch badge over the view; the data the tests read (ghosts, gizmo, framing, poses)
  [["rk-branch", el("rk-view")], ["rk-ghosts", document.body], ["rk-gizmo", document.body],
   ["rk-framing", document.body], ["rk-scene-poses", document.body]].forEach(function (idParent) {
    var div = document.createElement("div");
    div.id = idParent[0];
    div.hidden = true;
    idParent[1].appendChild(div);
  });

  buildControls();
  if (!KIN) { message(kinProblem); return; }  // no numbers rather than numbers of another implementation
  startViewer();
  startGizmo();
  startGhosts();
  startGhostPicking();
  if (!readHash()) { update(); }
  window.addEventListener("hashchange", function () { readHash(); });
})();
