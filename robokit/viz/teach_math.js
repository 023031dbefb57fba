// robokit teach pendant: the math, with no DOM (usable from the page and from Node).
//
// Everything is computed in double precision from the robot's product-of-exponentials
// parameters (M, the screw axes S_i = (w_i, v_i) in the base frame), written by
// robokit/viz/teach.py:
//   T(q)   = e^[S1]q1 ... e^[Sn]qn M                      (tool pose, Lecture 4)
//   J_s,i  = Ad(e^[S1]q1 ... e^[S(i-1)]q(i-1)) S_i         (space Jacobian column)
//   J      = (w; v + w x p_tool)                            (geometric Jacobian, base axes)
//   object g on joint k: T_g(q) = e^[S1]q1 ... e^[Sk]qk T_g(0)
// 4x4 matrices are row-major arrays of 16 numbers. The Python twin of `readouts` is
// robokit.viz.teach.teach_readouts (Pinocchio); tests/viz/test_teach_math.py checks this file
// against golden values written from it.
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
  var EYE = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

  // e^{[S] t} for a screw S = (w, v): Rodrigues' formula when |w| = 1, a translation when w = 0
  function expScrew(S, t) {
    var w = [S[0], S[1], S[2]], v = [S[3], S[4], S[5]];
    var nw = Math.hypot(w[0], w[1], w[2]);
    if (nw < 1e-12) {
      return [1, 0, 0, v[0] * t, 0, 1, 0, v[1] * t, 0, 0, 1, v[2] * t, 0, 0, 0, 1];
    }
    var s = Math.sin(t), c = 1 - Math.cos(t);
    var K = [0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0];  // [w]
    var K2 = new Array(9);                                      // [w]^2
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

  // partial products P[k] = e^[S1]q1 ... e^[Sk]qk, k = 0..n (P[0] = I); Slist: n screws (6 each)
  function products(Slist, q) {
    var P = [EYE];
    for (var i = 0; i < Slist.length; i++) { P.push(mul4(P[i], expScrew(Slist[i], q[i]))); }
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

  // geometric Jacobian (6 rows (w; v), n columns), v the velocity of the tool origin p = T's
  // translation; P the partial products of `products`
  function jacobian(Slist, P, T) {
    var J = [[], [], [], [], [], []];
    var p = [T[3], T[7], T[11]];
    for (var i = 0; i < Slist.length; i++) {
      var c = adjoint(P[i], Slist[i]);
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

  // All readouts at q for a robot R = {n, M, S, rows, joints: [{lo, hi, limited}],
  // singular_tol, singular_ratio} (the page's data): tool pose, RPY, quaternion, Jacobian,
  // manipulability w = sqrt(det(Jt Jt^T)) = prod sigma_i, condition number, singularity level
  // and lost direction (task-row components, dominant one positive), joint-limit margins.
  function readouts(R, q) {
    var n = R.n;
    var P = products(R.S, q), T = mul4(P[n], flat4(R.M));
    var J = jacobian(R.S, P, T);
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
    return { P: P, T: T, xyz: [T[3], T[7], T[11]], rpy: rpy(T), quat: quaternion(T), J: J,
             w: w, cond: cond, sigmaMin: smin, sigmaMax: smax, ratio: ratio, level: level,
             direction: u, directionRow: kmax, margins: margins, marginJoint: jmin };
  }

  // The joint values of a URL fragment "#q=q1,q2,..." (rad / m) for n joints:
  // {q: n finite numbers or null, given: whether the fragment has a q= part, problem: why it
  // was ignored or ""}. Never throws: bad percent-encoding, a wrong count, NaN, inf, empty
  // entries and non-numbers are reported, not applied.
  function parseFragment(hash, n) {
    var text = String(hash === undefined || hash === null ? "" : hash);
    var m = /(?:^#|&)q=([^&]*)/.exec(text);
    if (!m) { return { q: null, given: false, problem: "" }; }
    var raw = m[1], decoded;
    var shown = raw.length > 60 ? raw.slice(0, 57) + "..." : raw;
    try {
      decoded = decodeURIComponent(raw);
    } catch (e) {
      return { q: null, given: true, problem: "URL #q=: \u201c" + shown + "\u201d is not valid percent-encoding; ignored" };
    }
    var parts = decoded.split(",");
    var values = parts.map(function (s) { return /^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*$/.test(s) ? Number(s) : NaN; });
    if (parts.length !== n || values.some(function (x) { return !isFinite(x); })) {
      return { q: null, given: true,
               problem: "URL #q=: expected " + n + " finite numbers (rad / m), got \u201c" + shown + "\u201d; ignored" };
    }
    return { q: values, given: true, problem: "" };
  }

  return { mul4: mul4, flat4: flat4, EYE: EYE, expScrew: expScrew, products: products, adjoint: adjoint,
           jacobian: jacobian, svdLeft: svdLeft, rpy: rpy, quaternion: quaternion, readouts: readouts,
           parseFragment: parseFragment };
})();
if (typeof module !== "undefined" && module.exports) { module.exports = RKMath; }
