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

  // ------------------------------------------------------------------ drag the tool
  // A handle (orange ball) at the tool origin, with the module: dragging it moves the target's
  // position in the plane through the tool facing the camera (the orientation kept) and calls the
  // same entry point as #T= (goToTarget), so the arm follows on the nearest IK branch. It turns
  // red when the target is out of reach. #rk-gizmo holds its position on the page (px, for tests).
  var gizmo = null, lastT = null, GIZMO_COLOUR = 0xF39C12;
  function startGizmo() {
    if (!viewer || !KIN) { return; }
    var THREE = MeshCat.THREE, node = viewer.scene_tree.find(["meshcat", "frames"]);
    if (!node) { return; }
    var mat = new THREE.MeshBasicMaterial({ color: GIZMO_COLOUR, transparent: true, opacity: 0.8, depthTest: false });
    var mesh = new THREE.Mesh(new THREE.SphereGeometry(0.3 * R.scale, 24, 16), mat);
    mesh.renderOrder = 1000;
    node.object.add(mesh);  // that node's coordinates are the base frame's (frameView shifts the node)
    gizmo = { mesh: mesh, parent: node.object, drag: null };
    var canvas = viewer.renderer.domElement, ray = new THREE.Raycaster();
    function pick(ev) {
      var rc = canvas.getBoundingClientRect();
      ray.setFromCamera(new THREE.Vector2(2 * (ev.clientX - rc.left) / rc.width - 1, 1 - 2 * (ev.clientY - rc.top) / rc.height),
                        viewer.camera);
      return ray;
    }
    canvas.addEventListener("pointerdown", function (ev) {
      viewer.scene.updateMatrixWorld(true);
      if (!lastT || !pick(ev).intersectObject(mesh).length) { return; }
      var p = new THREE.Vector3(), nrm = new THREE.Vector3();
      mesh.getWorldPosition(p);
      viewer.camera.getWorldDirection(nrm);
      gizmo.drag = { plane: new THREE.Plane().setFromNormalAndCoplanarPoint(nrm, p), T0: lastT.slice() };
      viewer.controls.enabled = false;  // the drag moves the tool, not the camera
      try { canvas.setPointerCapture(ev.pointerId); } catch (e) { /* a synthetic pointer */ }
      ev.stopImmediatePropagation();
      ev.preventDefault();
    }, true);
    canvas.addEventListener("pointermove", function (ev) {
      if (!gizmo.drag) { return; }
      var hit = new THREE.Vector3();
      if (!pick(ev).ray.intersectPlane(gizmo.drag.plane, hit)) { return; }
      gizmo.parent.worldToLocal(hit);
      var T = gizmo.drag.T0.slice();
      T[3] = hit.x; T[7] = hit.y; T[11] = hit.z;
      goToTarget(T, "drag");
      ev.stopImmediatePropagation();
    }, true);
    var end = function () { if (gizmo.drag) { gizmo.drag = null; viewer.controls.enabled = true; } };
    canvas.addEventListener("pointerup", end, true);
    canvas.addEventListener("pointercancel", end, true);
  }
  function placeGizmo(T, reachable) {
    lastT = T;
    if (!gizmo) { return; }
    gizmo.mesh.position.set(T[3], T[7], T[11]);
    if (reachable !== undefined) { gizmo.mesh.material.color.setHex(reachable ? GIZMO_COLOUR : RED); }
    viewer.scene.updateMatrixWorld(true);
    var v = new MeshCat.THREE.Vector3();
    gizmo.mesh.getWorldPosition(v);
    v.project(viewer.camera);
    var rc = viewer.renderer.domElement.getBoundingClientRect();
    setData("rk-gizmo", { x: String(rc.left + 0.5 * (v.x + 1) * rc.width), y: String(rc.top + 0.5 * (1 - v.y) * rc.height),
                          reachable: String(gizmo.mesh.material.color.getHex() !== RED) });
    viewer.set_dirty();
  }

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
  var DLS = { lambda: 0.01, iters: 200, tol: 1e-12 };
  function followByDls(T, why) {
    var r = KIN.dls(T, q, DLS.lambda, DLS.iters, DLS.tol), ok = r.steps >= 0, box = el("rk-ik");
    setData("rk-ik", { status: ok ? "dls" : "dls-not-converged", count: "1", solutions: JSON.stringify([r.q]),
                       labels: JSON.stringify(["damped least squares"]), within: "[]", chosen: "0",
                       steps: String(r.steps), target: T.map(String).join(",") });
    box.className = ok ? "rk-small" : "rk-small rk-unreachable";
    box.textContent = R.name + " has no closed-form IK: damped least squares (\u03bb = " + DLS.lambda + ") " +
      (ok ? "reached the target in " + r.steps + " steps" : "did not reach the target in " + DLS.iters + " steps (out of reach or singular)") +
      "; the null space is kept";
    setQ(r.q, why + " (damped least squares)");
    return 0;
  }

  // Every closed-form solution of the tool pose T (16 numbers, row-major, base frame), from the
  // module, in ik_analytic's order; the arm moves to the one nearest the current q (joint-space
  // distance) and #rk-ik records them all. Out of reach: the arm stays and the readout says so.
  function goToTarget(T, why) {
    var box = el("rk-ik");
    if (!KIN.hasIk) { return followByDls(T, why); }
    var sols = KIN.ik(T, 0), k = RKWasm.nearest(sols, q);
    setData("rk-ik", { status: sols.length ? "ok" : "unreachable", count: String(sols.length),
                       solutions: JSON.stringify(sols.map(function (s) { return s.q; })),
                       labels: JSON.stringify(sols.map(function (s) { return s.label; })),
                       within: JSON.stringify(sols.map(function (s) { return s.withinLimits; })), chosen: String(k),
                       target: T.map(String).join(",") });
    if (k < 0) {
      box.className = "rk-small rk-unreachable";
      box.textContent = "IK: the target is out of reach (no solution); the arm stays";
      update(null);
      placeGizmo(T, false);  // the handle stays under the pointer, red; the arm stays
      return -1;
    }
    var s = sols[k];
    if (gizmo) { gizmo.mesh.material.color.setHex(GIZMO_COLOUR); }
    box.className = "rk-small";
    box.textContent = "IK: " + sols.length + " solution" + (sols.length === 1 ? "" : "s") + "; showing the nearest, " +
      (k + 1) + " \u201c" + s.label + "\u201d" + (s.withinLimits ? "" : " (outside the joint limits)");
    setQ(s.q, why + " (IK)");
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
    placeGizmo(T);

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
    try { history.replaceState(null, "", "#q=" + q.map(function (v) { return String(v); }).join(",")); } catch (e) { /* file:// in some browsers */ }
  }

  var ikBox = document.createElement("div");
  ikBox.id = "rk-ik";
  ikBox.className = "rk-small";
  el("rk-msg").insertAdjacentElement("afterend", ikBox);
  window.RKTeach = { goToTarget: goToTarget };  // the entry point of #T= (and of a drag)

  var gizmoData = document.createElement("div");
  gizmoData.id = "rk-gizmo";
  gizmoData.hidden = true;
  document.body.appendChild(gizmoData);

  var framing = document.createElement("div");
  framing.id = "rk-framing";
  framing.hidden = true;
  document.body.appendChild(framing);
  var hidden = document.createElement("div");
  hidden.id = "rk-scene-poses";
  hidden.hidden = true;
  document.body.appendChild(hidden);

  buildControls();
  if (!KIN) { message(kinProblem); return; }  // no numbers rather than numbers of another implementation
  startViewer();
  startGizmo();
  if (!readHash()) { update(); }
  window.addEventListener("hashchange", function () { readHash(); });
})();
