// robokit teach page: sliders -> product of exponentials -> 3-D view and readouts.
//
// Everything is computed here, in double precision, from the robot's PoE parameters
// (M, the screw axes S_i = (w_i, v_i) in the base frame), written by robokit/viz/teach.py:
//   T(q)   = e^[S1]q1 ... e^[Sn]qn M                      (tool pose)
//   J_s,i  = Ad(e^[S1]q1 ... e^[S(i-1)]q(i-1)) S_i         (space Jacobian column)
//   J      = (w; v + w x p_tool)                            (geometric Jacobian, base axes)
//   object g on joint k: T_g(q) = e^[S1]q1 ... e^[Sk]qk T_g(0)
// 4x4 matrices are row-major arrays of 16 numbers.
(function () {
  "use strict";
  var R = JSON.parse(document.getElementById("rk-robot").textContent);
  var n = R.n;
  var DEG = 180 / Math.PI;

  // ------------------------------------------------------------------ small linear algebra
  function mul4(A, B) {
    var C = new Array(16);
    for (var i = 0; i < 4; i++) {
      for (var j = 0; j < 4; j++) {
        C[4 * i + j] = A[4 * i] * B[j] + A[4 * i + 1] * B[4 + j] + A[4 * i + 2] * B[8 + j] + A[4 * i + 3] * B[12 + j];
      }
    }
    return C;
  }
  function flat4(M) { return [].concat(M[0], M[1], M[2], M[3]); }
  var EYE = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

  // e^{[S] t} for a screw S = (w, v): Rodrigues' formula when |w| = 1, a translation when w = 0
  function expScrew(S, t) {
    var w = [S[0], S[1], S[2]], v = [S[3], S[4], S[5]];
    var nw = Math.hypot(w[0], w[1], w[2]);
    if (nw < 1e-12) {
      return [1, 0, 0, v[0] * t, 0, 1, 0, v[1] * t, 0, 0, 1, v[2] * t, 0, 0, 0, 1];
    }
    var s = Math.sin(t), c = 1 - Math.cos(t);
    // K = [w], K2 = [w]^2
    var K = [0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0];
    var K2 = new Array(9);
    for (var i = 0; i < 3; i++) {
      for (var j = 0; j < 3; j++) {
        K2[3 * i + j] = K[3 * i] * K[j] + K[3 * i + 1] * K[3 + j] + K[3 * i + 2] * K[6 + j];
      }
    }
    var Rm = new Array(9), G = new Array(9);
    for (var k = 0; k < 9; k++) {
      var I = (k % 4 === 0) ? 1 : 0;
      Rm[k] = I + s * K[k] + c * K2[k];
      G[k] = I * t + c * K[k] + (t - s) * K2[k];  // (I t + (1 - cos t)[w] + (t - sin t)[w]^2)
    }
    var p = [0, 0, 0];
    for (var r = 0; r < 3; r++) { p[r] = G[3 * r] * v[0] + G[3 * r + 1] * v[1] + G[3 * r + 2] * v[2]; }
    return [Rm[0], Rm[1], Rm[2], p[0], Rm[3], Rm[4], Rm[5], p[1], Rm[6], Rm[7], Rm[8], p[2], 0, 0, 0, 1];
  }

  // partial products P[k] = e^[S1]q1 ... e^[Sk]qk, k = 0..n (P[0] = I)
  function products(q) {
    var P = [EYE];
    for (var i = 0; i < n; i++) { P.push(mul4(P[i], expScrew(R.S[i], q[i]))); }
    return P;
  }

  // Ad_T S = (R w, p x (R w) + R v)
  function adjoint(T, S) {
    var w = [0, 0, 0], v = [0, 0, 0];
    for (var r = 0; r < 3; r++) {
      w[r] = T[4 * r] * S[0] + T[4 * r + 1] * S[1] + T[4 * r + 2] * S[2];
      v[r] = T[4 * r] * S[3] + T[4 * r + 1] * S[4] + T[4 * r + 2] * S[5];
    }
    var p = [T[3], T[7], T[11]];
    return [w[0], w[1], w[2],
            p[1] * w[2] - p[2] * w[1] + v[0],
            p[2] * w[0] - p[0] * w[2] + v[1],
            p[0] * w[1] - p[1] * w[0] + v[2]];
  }

  // geometric Jacobian (6 rows (w; v), n columns), v the velocity of the tool origin p
  function jacobian(P, T) {
    var J = [[], [], [], [], [], []];
    var p = [T[3], T[7], T[11]];
    for (var i = 0; i < n; i++) {
      var c = adjoint(P[i], R.S[i]);
      var w = [c[0], c[1], c[2]];
      var col = [w[0], w[1], w[2],
                 c[3] + w[1] * p[2] - w[2] * p[1],
                 c[4] + w[2] * p[0] - w[0] * p[2],
                 c[5] + w[0] * p[1] - w[1] * p[0]];
      for (var r = 0; r < 6; r++) { J[r].push(col[r]); }
    }
    return J;
  }

  // Singular values and left singular vectors of A (m x n) by one-sided Jacobi on the
  // columns of B = A^T: rotations V make B V's columns orthogonal; then sigma_i = |(B V)_i|
  // and A = V diag(sigma) (...)^T, so V's columns are A's left singular vectors.
  function svdLeft(A) {
    var m = A.length, nc = A[0].length;
    var B = [], V = [];
    for (var i = 0; i < m; i++) {
      B.push(A[i].slice());
      var e = new Array(m).fill(0); e[i] = 1; V.push(e);  // V[i] is column i of V
    }
    for (var sweep = 0; sweep < 60; sweep++) {
      var rotated = false;
      for (var a = 0; a < m - 1; a++) {
        for (var b = a + 1; b < m; b++) {
          var alpha = 0, beta = 0, gamma = 0;
          for (var k = 0; k < nc; k++) {
            alpha += B[a][k] * B[a][k]; beta += B[b][k] * B[b][k]; gamma += B[a][k] * B[b][k];
          }
          if (Math.abs(gamma) <= 1e-15 * Math.sqrt(alpha * beta) || gamma === 0) { continue; }
          rotated = true;
          var zeta = (beta - alpha) / (2 * gamma);
          var t = (zeta >= 0 ? 1 : -1) / (Math.abs(zeta) + Math.sqrt(1 + zeta * zeta));
          var cs = 1 / Math.sqrt(1 + t * t), sn = cs * t;
          for (k = 0; k < nc; k++) {
            var x = B[a][k], y = B[b][k];
            B[a][k] = cs * x - sn * y; B[b][k] = sn * x + cs * y;
          }
          for (k = 0; k < m; k++) {
            var u = V[a][k], z = V[b][k];
            V[a][k] = cs * u - sn * z; V[b][k] = sn * u + cs * z;
          }
        }
      }
      if (!rotated) { break; }
    }
    var out = [];
    for (i = 0; i < m; i++) {
      var s2 = 0;
      for (k = 0; k < nc; k++) { s2 += B[i][k] * B[i][k]; }
      out.push({ s: Math.sqrt(s2), u: V[i] });
    }
    out.sort(function (p, q) { return q.s - p.s; });
    return out;
  }

  // R = Rz(yaw) Ry(pitch) Rx(roll) -> (roll, pitch, yaw)
  function rpy(T) {
    var r20 = Math.max(-1, Math.min(1, T[8]));
    return [Math.atan2(T[9], T[10]), Math.atan2(-r20, Math.hypot(T[0], T[4])), Math.atan2(T[4], T[0])];
  }

  // unit quaternion (w, x, y, z) of R, w >= 0 (Shepperd's method: the largest of 4 candidates)
  function quaternion(T) {
    var m00 = T[0], m01 = T[1], m02 = T[2], m10 = T[4], m11 = T[5], m12 = T[6], m20 = T[8], m21 = T[9], m22 = T[10];
    var tr = m00 + m11 + m22, w, x, y, z, s;
    if (tr >= m00 && tr >= m11 && tr >= m22) {
      s = 2 * Math.sqrt(1 + tr); w = s / 4; x = (m21 - m12) / s; y = (m02 - m20) / s; z = (m10 - m01) / s;
    } else if (m00 >= m11 && m00 >= m22) {
      s = 2 * Math.sqrt(1 + m00 - m11 - m22); x = s / 4; w = (m21 - m12) / s; y = (m01 + m10) / s; z = (m02 + m20) / s;
    } else if (m11 >= m22) {
      s = 2 * Math.sqrt(1 + m11 - m00 - m22); y = s / 4; w = (m02 - m20) / s; x = (m01 + m10) / s; z = (m12 + m21) / s;
    } else {
      s = 2 * Math.sqrt(1 + m22 - m00 - m11); z = s / 4; w = (m10 - m01) / s; x = (m02 + m20) / s; y = (m12 + m21) / s;
    }
    var nq = Math.hypot(w, x, y, z);
    var sign = w < 0 ? -1 : 1;
    return [sign * w / nq, sign * x / nq, sign * y / nq, sign * z / nq];
  }

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
  var viewer = null, visualNodes = [], frameNodes = [];
  function startViewer() {
    try {
      var pane = el("meshcat-pane");
      viewer = new MeshCat.Viewer(pane);
      var own = viewer.set_3d_pane_size.bind(viewer);
      viewer.set_3d_pane_size = function (w, h) {  // the pane, not the whole window
        own(w === undefined ? pane.clientWidth : w, h === undefined ? pane.clientHeight : h);
      };
      viewer.set_3d_pane_size();
      RK_SCENE.forEach(function (b64) {
        var bin = atob(b64), bytes = new Uint8Array(bin.length);
        for (var i = 0; i < bin.length; i++) { bytes[i] = bin.charCodeAt(i); }
        viewer.handle_command_bytearray(bytes);
      });
      var split = function (path) { return path.split("/").filter(function (s) { return s.length > 0; }); };
      visualNodes = R.visuals.map(function (v) { return viewer.scene_tree.find(split(v.path)); });
      frameNodes = R.frames.map(function (f) { return viewer.scene_tree.find(split(f.path)); });
      // camera: three.js's orbit controls look at the origin of the world (camera.lookAt
      // takes a world point), so the content is shifted by -centre and the camera orbits the
      // origin; the camera sits in a frame rotated so that three.js's y is the base's z: a
      // base-frame offset (x, y, z) is (x, z, -y) there
      var t = R.camera.target, c = R.camera.position;
      var shift = [1, 0, 0, -t[0], 0, 1, 0, -t[1], 0, 0, 1, -t[2], 0, 0, 0, 1];
      ["meshcat/robot", "meshcat/frames", "meshcat/floor", "Axes"].forEach(function (p) {
        viewer.scene_tree.find(split(p)).set_transform(colMajor(shift));
      });
      viewer.camera.position.set(c[0] - t[0], c[2] - t[2], -(c[1] - t[1]));
      viewer.controls.update();
    } catch (err) {
      viewer = null;
      message("3-D view unavailable (" + err + "); the readouts still work.");
    }
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
    if (viewer) { viewer.set_dirty(); }
  }

  // ------------------------------------------------------------------ page
  var sliders = [], boxes = [], rowsEls = [];
  function buildControls() {
    el("rk-title").textContent = R.name;
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
        '<div class="rk-joint-head"><span class="rk-joint-name"></span>' +
        '<span><input type="number"> <span class="rk-small"></span></span></div>' +
        '<input type="range"><div class="rk-joint-lim"><span></span><span></span></div>';
      div.querySelector(".rk-joint-name").textContent = "q" + (i + 1) + " " + j.name;
      div.querySelector(".rk-joint-name").title = j.name + (j.limited ? "" : " (no limits)");
      div.querySelector(".rk-joint-head .rk-small").textContent = j.type === "R" ? "deg" : "m";
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

  function readHash() {
    var m = /(?:^#|&)q=([^&]*)/.exec(location.hash);
    if (!m) { return false; }
    var parts = decodeURIComponent(m[1]).split(",").map(function (s) { return parseFloat(s); });
    if (parts.length !== n || parts.some(function (x) { return !isFinite(x); })) {
      message("URL #q=: expected " + n + " numbers (rad / m), got \u201c" + m[1] + "\u201d; ignored");
      return false;
    }
    setQ(parts, "URL");
    return true;
  }

  function setData(id, attrs) { var e = el(id); Object.keys(attrs).forEach(function (k) { e.dataset[k] = attrs[k]; }); return e; }

  // msg: null keeps the current message; skipSlider: the slider being dragged (not rewritten)
  function update(msg, skipSlider) {
    if (msg !== null && msg !== undefined) { message(msg); } else if (msg === undefined) { message(""); }
    for (var i = 0; i < n; i++) {
      if (i !== skipSlider) { sliders[i].value = String(q[i] * unit[i]); }
      boxes[i].value = (q[i] * unit[i]).toFixed(R.joints[i].type === "R" ? 2 : 4);
    }
    var P = products(q), T = mul4(P[n], flat4(R.M));
    placeObjects(P);
    var J = jacobian(P, T);

    // pose
    var xyz = [T[3], T[7], T[11]], ang = rpy(T), quat = quaternion(T);
    el("rk-xyz").textContent = xyz.map(function (v) { return fmt(v, 4); }).join(" ");
    el("rk-rpy").textContent = ang.map(function (v) { return fmt(v * DEG, 2); }).join(" ");
    el("rk-quat").textContent = quat.map(function (v) { return fmt(v, 4); }).join(" ");
    setData("rk-pose", { t: T.map(String).join(","), xyz: xyz.map(String).join(","),
                         rpy: ang.map(String).join(","), quat: quat.map(String).join(",") });

    // Jacobian
    var trs = el("rk-jacobian").rows;
    for (var r = 0; r < 6; r++) {
      for (var c = 0; c < n; c++) { trs[r + 1].cells[c + 1].textContent = fmt(J[r][c], 3); }
    }
    setData("rk-jacobian", { j: [].concat.apply([], J).map(String).join(","), rows: 6, cols: n });

    // measures on the task rows
    var Jt = R.rows.map(function (rr) { return J[rr]; });
    var m = Jt.length, sv = svdLeft(Jt);
    var smax = sv[0].s, smin = sv[m - 1].s;
    var w = 0;
    if (n >= m) { w = 1; for (var k = 0; k < m; k++) { w *= sv[k].s; } }
    var cond = (smin >= R.singular_tol && n >= m) ? smax / smin : Infinity;  // singular: infinite
    el("rk-manip").textContent = w.toPrecision(5);
    setData("rk-manip", { value: String(w) });
    el("rk-cond").textContent = isFinite(cond) ? cond.toPrecision(4) : "\u221e";
    setData("rk-cond", { value: String(cond), sigmaMin: String(smin), sigmaMax: String(smax) });
    var ratio = smax > 0 ? smin / smax : 0;
    var level = smin < R.singular_tol ? "singular" : (ratio < R.singular_ratio ? "near" : "ok");
    var u = sv[m - 1].u.slice(), kmax = 0;
    for (k = 1; k < m; k++) { if (Math.abs(u[k]) > Math.abs(u[kmax])) { kmax = k; } }
    if (u[kmax] < 0) { u = u.map(function (x) { return -x; }); }
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
    var margins = [], jmin = -1;
    for (i = 0; i < n; i++) {
      var j = R.joints[i];
      var mg = j.limited ? Math.min(q[i] - j.lo, j.hi - q[i]) : Infinity;
      margins.push(mg);
      if (j.limited && (jmin < 0 || mg < margins[jmin])) { jmin = i; }
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
    try { history.replaceState(null, "", "#q=" + q.map(function (v) { return String(v); }).join(",")); } catch (e) { /* file:// in some browsers */ }
  }

  var hidden = document.createElement("div");
  hidden.id = "rk-scene-poses";
  hidden.hidden = true;
  document.body.appendChild(hidden);

  buildControls();
  startViewer();
  if (!readHash()) { update(); }
  window.addEventListener("hashchange", function () { readHash(); });
})();
