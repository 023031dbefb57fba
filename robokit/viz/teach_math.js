// robokit teach pendant: the page's presentation math, with no DOM (usable from the page and from Node).
//
// The kinematics (tool pose, Jacobian, the placements of the bodies, IK) are not here: they come
// from the robot's generated C compiled to WebAssembly (teach_wasm.js, the `kin` argument). What
// is here turns them into readouts: singular values (manipulability, condition number, the lost
// direction), roll-pitch-yaw, the quaternion, joint-limit margins; plus the URL fragment's
// parsing, the collision distances of the capsule models and the camera framing. 4x4 matrices
// are row-major arrays of 16 numbers. tests/viz/test_teach_math.py checks each function against
// numpy / Pinocchio (robokit.viz.teach.teach_readouts is the Python twin of `readouts`).
var RKMath = (function () {
  "use strict";

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

  // Singular values and left singular vectors of A (m x n) by one-sided Jacobi on the
  // columns of B = A^T: rotations V make B V's columns orthogonal; then sigma_i = |(B V)_i|
  // and A = V diag(sigma) (...)^T, so V's columns are A's left singular vectors.
  // Returns [{s, u}] sorted by decreasing s.
  function svdLeft(A) {
    var m = A.length, nc = A[0].length;
    var B = [], V = [], i, k;
    for (i = 0; i < m; i++) {
      B.push(A[i].slice());
      var e = new Array(m).fill(0); e[i] = 1; V.push(e);  // V[i] is column i of V
    }
    for (var sweep = 0; sweep < 60; sweep++) {
      var rotated = false;
      for (var a = 0; a < m - 1; a++) {
        for (var b = a + 1; b < m; b++) {
          var alpha = 0, beta = 0, gamma = 0;
          for (k = 0; k < nc; k++) {
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

  // R = Rz(yaw) Ry(pitch) Rx(roll) -> (roll, pitch, yaw): yaw first, then pitch and roll from
  // Rz(yaw)^T R, so that near the gimbal lock (pitch -> +-90 deg, where yaw and roll are no longer
  // separate) the three angles still rebuild R to round-off
  function rpy(T) {
    var y = Math.atan2(T[4], T[0]), c = Math.cos(y), s = Math.sin(y);
    return [Math.atan2(s * T[2] - c * T[6], c * T[5] - s * T[1]), Math.atan2(-T[8], c * T[0] + s * T[4]), y];
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

  // All readouts at q for a robot R = {n, rows, joints: [{lo, hi, limited}], singular_tol,
  // singular_ratio} (the page's data), with kin the robot's module (teach_wasm.js: fk, jacobian):
  // tool pose, RPY, quaternion, Jacobian, manipulability w = sqrt(det(Jt Jt^T)) = prod sigma_i,
  // condition number, singularity level and lost direction (task-row components, dominant one
  // positive), joint-limit margins.
  function readouts(R, q, kin) {
    var n = R.n;
    var T = kin.fk(q), J = kin.jacobian(q);
    var Jt = R.rows.map(function (r) { return J[r]; });
    var m = Jt.length, sv = svdLeft(Jt);
    var smax = sv[0].s, smin = sv[m - 1].s;
    var w = 0, k;
    if (n >= m) { w = 1; for (k = 0; k < m; k++) { w *= sv[k].s; } }
    var cond = (smin >= R.singular_tol && n >= m) ? smax / smin : Infinity;
    var ratio = smax > 0 ? smin / smax : 0;
    var level = smin < R.singular_tol ? "singular" : (ratio < R.singular_ratio ? "near" : "ok");
    var u = sv[m - 1].u.slice(), kmax = 0;
    for (k = 1; k < m; k++) { if (Math.abs(u[k]) > Math.abs(u[kmax])) { kmax = k; } }
    if (u[kmax] < 0) { u = u.map(function (x) { return -x; }); }
    var margins = [], jmin = -1;
    for (var i = 0; i < n; i++) {
      var j = R.joints[i];
      var mg = j.limited ? Math.min(q[i] - j.lo, j.hi - q[i]) : Infinity;
      margins.push(mg);
      if (j.limited && (jmin < 0 || mg < margins[jmin])) { jmin = i; }
    }
    return { T: T, xyz: [T[3], T[7], T[11]], rpy: rpy(T), quat: quaternion(T), J: J,
             w: w, cond: cond, sigmaMin: smin, sigmaMax: smax, ratio: ratio, level: level,
             direction: u, directionRow: kmax, margins: margins, marginJoint: jmin };
  }

  // The joint values of a URL fragment "#q=q1,q2,..." (rad / m) for n joints:
  // {q: n finite numbers or null, given: whether the fragment has a q= part, problem: why it
  // was ignored or ""}. Never throws: bad percent-encoding, a wrong count, NaN, inf, empty
  // entries and non-numbers are reported, not applied.
  function parseFragment(hash, n) {
    var f = parseList(hash, "q", n, n + " finite numbers (rad / m)");
    return { q: f.values, given: f.given, problem: f.problem };
  }

  // The target pose of a URL fragment "#T=t11,t12,...,t44" (16 numbers, row-major, the tool
  // pose in the base frame): {T: 16 finite numbers or null, given, problem}, as parseFragment.
  // 16 numbers that are not a pose (a scaled, sheared or mirrored rotation, a last row other
  // than 0 0 0 1: farther than POSE_TOL from SE(3)) are ignored too: no IK solution reaches them
  // (robokit.ik_analytic refuses such a T). A pose rounded for a link (6 decimals) is well within.
  var POSE_TOL = 1e-3;  // Modern Robotics' test_if_SE3
  function parseTarget(hash) {
    var f = parseList(hash, "T", 16, "16 finite numbers (a 4x4 pose, row-major, m)");
    if (f.values) {
      var d = distanceToSE3(f.values);
      if (!(d <= POSE_TOL)) {
        return { T: null, given: true,
                 problem: "URL #T=: not a pose (distance to SE(3) " + (d >= 1e9 ? "\u221e: det R \u2264 0" : d.toPrecision(3)) +
                          " > " + POSE_TOL + ": the top-left 3x3 must be a rotation, the last row 0 0 0 1); ignored" };
      }
    }
    return { T: f.values, given: f.given, problem: f.problem };
  }

  // Modern Robotics' distance of a row-major 4x4 matrix to SE(3): with R its top-left block,
  // ||[[R^T R, 0], [last row]] - I||_F when det R > 0 (the position column does not count), else 1e9
  function distanceToSE3(T) {
    var det = T[0] * (T[5] * T[10] - T[6] * T[9]) - T[1] * (T[4] * T[10] - T[6] * T[8]) +
              T[2] * (T[4] * T[9] - T[5] * T[8]);
    if (!(det > 0)) { return 1e9; }
    var s = 0, i, j, k;
    for (i = 0; i < 3; i++) {
      for (j = 0; j < 3; j++) {
        var rtr = 0;
        for (k = 0; k < 3; k++) { rtr += T[4 * k + i] * T[4 * k + j]; }
        s += (rtr - (i === j ? 1 : 0)) * (rtr - (i === j ? 1 : 0));
      }
    }
    for (j = 0; j < 4; j++) { s += (T[12 + j] - (j === 3 ? 1 : 0)) * (T[12 + j] - (j === 3 ? 1 : 0)); }
    return Math.sqrt(s);
  }

  // "key=v1,v2,..." of a fragment: {values: count finite numbers or null, given, problem}
  function parseList(hash, key, count, expected) {
    var text = String(hash === undefined || hash === null ? "" : hash);
    var m = new RegExp("(?:^#|&)" + key + "=([^&]*)").exec(text);
    if (!m) { return { values: null, given: false, problem: "" }; }
    var raw = m[1], decoded;
    var shown = raw.length > 60 ? raw.slice(0, 57) + "..." : raw;
    try {
      decoded = decodeURIComponent(raw);
    } catch (e) {
      return { values: null, given: true, problem: "URL #" + key + "=: \u201c" + shown + "\u201d is not valid percent-encoding; ignored" };
    }
    var parts = decoded.split(",");
    var values = parts.map(function (s) { return /^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$/.test(s) ? Number(s) : NaN; });
    if (parts.length !== count || values.some(function (x) { return !isFinite(x); })) {
      return { values: null, given: true,
               problem: "URL #" + key + "=: expected " + expected + ", got \u201c" + shown + "\u201d; ignored" };
    }
    return { values: values, given: true, problem: "" };
  }

  // ------------------------------------------------------------------ collision (capsule models)
  // The robot's links are capsules (segment [a, b], radius r) and the obstacles boxes,
  // spheres and cylinders, as robokit.viz.clearance.clearance_page_data writes them:
  //   capsule-capsule   min_s min_t |p1(s) - p2(t)| - r1 - r2
  //   capsule-shape     min_t sdf(p(t)) - r      (sdf: the shape's exact signed distance)
  // Inner point-segment distances are closed form; the outer minima are of convex functions
  // of one parameter on [0, 1] (a distance to a convex set, or a convex set's signed distance,
  // along a segment), found by ternary search.
  function sub3(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function dot3(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function pointSegment(p, a, b) {
    var ab = sub3(b, a), ap = sub3(p, a), L2 = dot3(ab, ab);
    var t = L2 > 0 ? Math.max(0, Math.min(1, dot3(ap, ab) / L2)) : 0;
    return Math.hypot(ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]);
  }
  function minOnSegment(f) {
    var lo = 0, hi = 1;
    for (var it = 0; it < 100; it++) {
      var m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (f(m1) <= f(m2)) { hi = m2; } else { lo = m1; }
    }
    return Math.min(f(0), f(1), f(0.5 * (lo + hi)));
  }
  // signed distance of a point x (in the shape's frame) to a box (half sizes h), a sphere
  // (radius r) or a cylinder (radius r, half-length h, axis z), centred on the origin
  function sdf(g, x) {
    if (g.type === "sphere") { return Math.hypot(x[0], x[1], x[2]) - g.radius; }
    var q;
    if (g.type === "box") { q = [Math.abs(x[0]) - g.half[0], Math.abs(x[1]) - g.half[1], Math.abs(x[2]) - g.half[2]]; }
    else { q = [Math.hypot(x[0], x[1]) - g.radius, Math.abs(x[2]) - g.half]; }
    var out = 0, inside = -Infinity;
    for (var i = 0; i < q.length; i++) { out += Math.max(q[i], 0) * Math.max(q[i], 0); inside = Math.max(inside, q[i]); }
    return Math.sqrt(out) + Math.min(inside, 0);
  }
  // segment ends (base frame) of a capsule with pose T (row-major 4x4, axis z, half-length h)
  function segmentOf(T, h) {
    var c = [T[3], T[7], T[11]], z = [T[2], T[6], T[10]];
    return [[c[0] - h * z[0], c[1] - h * z[1], c[2] - h * z[2]], [c[0] + h * z[0], c[1] + h * z[1], c[2] + h * z[2]]];
  }
  function toLocal(T, p) {
    var v = [p[0] - T[3], p[1] - T[7], p[2] - T[11]];
    return [T[0] * v[0] + T[4] * v[1] + T[8] * v[2], T[1] * v[0] + T[5] * v[1] + T[9] * v[2],
            T[2] * v[0] + T[6] * v[1] + T[10] * v[2]];
  }
  function lerp3(a, b, t) { return [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])]; }

  // The collision state at the placements P (KIN.placements: P[k] carries body k from q = 0) for the page's data C:
  // {distance (min over the pairs, m), closest: [name, name], pairs: [[name, name]] in contact
  // (distance <= 0, each once), links: robot link names in contact, joints: their joint
  // counts k, d: per-pair distances}. Distances are those of the padded geometry (margins).
  function clearance(C, P) {
    var segs = C.geoms.map(function (g) {
      if (g.type) { return null; }
      var T = mul4(P[g.k], flat4(g.T));
      return segmentOf(T, g.half);
    });
    var poses = C.geoms.map(function (g) { return g.type ? flat4(g.T) : null; });
    var d = [], best = Infinity, kbest = -1, pairs = [], seen = {}, links = {}, joints = {};
    for (var k = 0; k < C.pairs.length; k++) {
      var i = C.pairs[k][0], j = C.pairs[k][1];
      if (C.geoms[i].type) { var tmp = i; i = j; j = tmp; }  // the robot's capsule first
      var gi = C.geoms[i], gj = C.geoms[j], si = segs[i], dist;
      if (!gj.type) {
        var sj = segs[j];
        dist = minOnSegment(function (s) { return pointSegment(lerp3(si[0], si[1], s), sj[0], sj[1]); }) - gi.radius - gj.radius;
      } else {
        var Tj = poses[j];
        dist = minOnSegment(function (t) { return sdf(gj, toLocal(Tj, lerp3(si[0], si[1], t))); }) - gi.radius;
      }
      dist -= C.margins[k];
      d.push(dist);
      if (dist < best) { best = dist; kbest = k; }
      if (dist <= 0) {
        var a = C.geoms[C.pairs[k][0]].name, b = C.geoms[C.pairs[k][1]].name, key = JSON.stringify([a, b]);
        if (!seen[key]) { seen[key] = true; pairs.push([a, b]); }
        [gi, gj].forEach(function (g) { if (!g.type) { links[g.name] = true; joints[g.k] = true; } });
      }
    }
    var closest = kbest < 0 ? null : [C.geoms[C.pairs[kbest][0]].name, C.geoms[C.pairs[kbest][1]].name];
    return { distance: best, closest: closest, pairs: pairs, links: Object.keys(links).sort(),
             joints: Object.keys(joints).map(Number).sort(function (x, y) { return x - y; }), d: d };
  }

  // ------------------------------------------------------------------ camera framing
  // A perspective camera looking along -dir at a target t from the distance D sees a point p
  // at  x = (p - t).right,  y = (p - t).up,  depth = D - (p - t).dir,  and draws it at the
  // normalised device coordinates (x / (depth tan(fx/2)), y / (depth tan(fy/2))), fy the
  // vertical field of view and tan(fx/2) = aspect tan(fy/2). For every point, grown by pad
  // sideways, to land inside the window win = {xlo, xhi, ylo, yhi} (NDC, xlo < 0 < xhi) the
  // distance must be at least  s + X / (xhi tx)  (X = x + pad - a > 0; (x - pad - a) / (xlo tx)
  // on the other side), and likewise in y, s = (p - c).dir + pad, c the points' bounding-box
  // centre and t = c + a right + b up. Each bound is convex in its shift (a or b): ternary
  // searches find the shifts that let the camera come closest.
  // points: [[x, y, z], ...] (base frame, m). Returns {target, position, distance}.
  function fitCamera(points, pad, dir, fovYDeg, aspect, win) {
    var nd = Math.hypot(dir[0], dir[1], dir[2]);
    var d = [dir[0] / nd, dir[1] / nd, dir[2] / nd];
    var right = [-d[1], d[0], 0];  // (-d) x z
    var nr = Math.hypot(right[0], right[1]);
    right = nr > 1e-9 ? [right[0] / nr, right[1] / nr, 0] : [1, 0, 0];
    var up = [d[1] * right[2] - d[2] * right[1], d[2] * right[0] - d[0] * right[2], d[0] * right[1] - d[1] * right[0]];
    var ty = Math.tan(0.5 * fovYDeg * Math.PI / 180), tx = ty * aspect;
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity], i, k;
    for (i = 0; i < points.length; i++) {
      for (k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], points[i][k]); hi[k] = Math.max(hi[k], points[i][k]); }
    }
    var c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])];
    var rel = [], R = pad;
    for (i = 0; i < points.length; i++) {
      var v = [points[i][0] - c[0], points[i][1] - c[1], points[i][2] - c[2]];
      rel.push([v[0] * right[0] + v[1] * right[1] + v[2] * right[2], v[0] * up[0] + v[1] * up[1] + v[2] * up[2],
                v[0] * d[0] + v[1] * d[1] + v[2] * d[2] + pad]);
      R = Math.max(R, Math.hypot(v[0], v[1], v[2]) + pad);
    }
    // the bound splits: D >= max(Fx(a), Fy(b)), each convex in one shift
    function bound(a, axis, wlo, whi, tn) {
      var D = -Infinity;
      for (var j = 0; j < rel.length; j++) {
        var s = rel[j][2];
        D = Math.max(D, s + (rel[j][axis] + pad - a) / (whi * tn), s + (rel[j][axis] - pad - a) / (wlo * tn));
      }
      return D;
    }
    function argmin(f) {
      var lo1 = -R, hi1 = R;
      for (var it = 0; it < 100; it++) {
        var m1 = lo1 + (hi1 - lo1) / 3, m2 = hi1 - (hi1 - lo1) / 3;
        if (f(m1) <= f(m2)) { hi1 = m2; } else { lo1 = m1; }
      }
      return 0.5 * (lo1 + hi1);
    }
    var a = argmin(function (x) { return bound(x, 0, win.xlo, win.xhi, tx); });
    var b = argmin(function (y) { return bound(y, 1, win.ylo, win.yhi, ty); });
    var D = Math.max(bound(a, 0, win.xlo, win.xhi, tx), bound(b, 1, win.ylo, win.yhi, ty), 1e-3);
    var t = [c[0] + a * right[0] + b * up[0], c[1] + a * right[1] + b * up[1], c[2] + a * right[2] + b * up[2]];
    return { target: t, position: [t[0] + D * d[0], t[1] + D * d[1], t[2] + D * d[2]], distance: D };
  }

  return { fitCamera: fitCamera, clearance: clearance, sdf: sdf, mul4: mul4, flat4: flat4, svdLeft: svdLeft, rpy: rpy,
           quaternion: quaternion, readouts: readouts, parseFragment: parseFragment, parseTarget: parseTarget };
})();
if (typeof module !== "undefined" && module.exports) { module.exports = RKMath; }
