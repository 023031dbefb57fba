// robokit teach page: the robot's generated C (robokit codegen), compiled to WebAssembly by
// robokit/viz/wasm.py, called from JavaScript. No DOM: usable from the page and from Node.
//
// RKWasm.load(bytes) -> a kinematics object over the module's robot-independent entry points
// (rk_fk, rk_joint_poses, rk_jacobian, rk_gravity, rk_ik on static buffers in the module's memory):
//   fk(q)        -> T, the tool pose in the base frame (16 numbers, row-major)
//   jointPoses(q) -> n poses (16 numbers each): joint k's frame in the base frame (Pinocchio's oMi[k])
//   placements(q) -> n + 1 poses P[0] = I, P[k] = oMi[k](q) oMi[k](0)^-1 = e^[S1]q1 ... e^[Sk]qk:
//                   what carries anything fixed to body k from its pose at q = 0 to its pose at q
//   jacobian(q)  -> J, 6 rows (w; v) of n numbers, v of the tool origin, base axes
//   gravity(q)   -> tau (n numbers, N m or N)
//   ik(T, ref)   -> [{q, label, withinLimits, degenerate}] every closed-form solution, in
//                   ik_analytic's order and wording (null when the robot has no closed form)
//   dls(T, q, lambda, iters, tol) -> {q, steps}: damped-least-squares steps from q toward T
//                   (steps -1: the pose error is still above tol)
// The module imports nothing (wasm32-wasi reactor without system calls); a reactor's
// _initialize (static constructors) is called once.
var RKWasm = (function () {
  "use strict";

  function decode(b64) {
    if (typeof atob === "function") {
      var bin = atob(b64), bytes = new Uint8Array(bin.length);
      for (var i = 0; i < bin.length; i++) { bytes[i] = bin.charCodeAt(i); }
      return bytes;
    }
    return new Uint8Array(Buffer.from(b64, "base64"));  // Node
  }

  function load(bytes) {
    var inst = new WebAssembly.Instance(new WebAssembly.Module(bytes), {});
    var x = inst.exports;
    if (x._initialize) { x._initialize(); }
    var n = x.rk_n();
    function f64(ptr, len) { return new Float64Array(x.memory.buffer, ptr, len); }  // views die when memory grows
    function cstr(ptr) {
      var mem = new Uint8Array(x.memory.buffer), s = "";
      for (var i = ptr; mem[i] !== 0; i++) { s += String.fromCharCode(mem[i]); }
      try { return decodeURIComponent(escape(s)); } catch (e) { return s; }  // UTF-8
    }
    function copy(view, from, to) {  // a plain array (Array.prototype.slice on a typed array is slow)
      var out = new Array(to - from);
      for (var i = from; i < to; i++) { out[i - from] = view[i]; }
      return out;
    }
    function setQ(q) {
      var b = f64(x.rk_q(), n);
      for (var i = 0; i < n; i++) { b[i] = q[i]; }
    }
    function jointPoses(q) {
      setQ(q); x.rk_joint_poses();
      var flat = f64(x.rk_P(), 16 * n), out = [];
      for (var k = 0; k < n; k++) { out.push(copy(flat, 16 * k, 16 * k + 16)); }
      return out;
    }
    // oMi[k](0)^-1 = [R^T | -R^T p], once: the constant that turns a joint pose into a placement
    var homeInv = jointPoses(new Array(n).fill(0)).map(function (H) {
      var Ri = [H[0], H[4], H[8], H[1], H[5], H[9], H[2], H[6], H[10]], p = [H[3], H[7], H[11]], out = [];
      for (var r = 0; r < 3; r++) {
        out.push(Ri[3 * r], Ri[3 * r + 1], Ri[3 * r + 2], -(Ri[3 * r] * p[0] + Ri[3 * r + 1] * p[1] + Ri[3 * r + 2] * p[2]));
      }
      return out.concat([0, 0, 0, 1]);
    });
    function placements(q) {
      var P = [[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]], O = jointPoses(q);
      for (var k = 0; k < n; k++) {
        var A = O[k], B = homeInv[k], C = new Array(16);
        for (var i = 0; i < 3; i++) {
          for (var j = 0; j < 4; j++) {
            C[4 * i + j] = A[4 * i] * B[j] + A[4 * i + 1] * B[4 + j] + A[4 * i + 2] * B[8 + j] + (j === 3 ? A[4 * i + 3] : 0);
          }
        }
        C[12] = 0; C[13] = 0; C[14] = 0; C[15] = 1;
        P.push(C);
      }
      return P;
    }
    var hasIk = x.rk_has_ik() === 1, labels = [];
    for (var k = 0; k < x.rk_label_count(); k++) { labels.push(cstr(x.rk_label(k))); }
    return {
      n: n,
      hasIk: hasIk,
      labels: labels,
      maxSolutions: x.rk_max_solutions(),
      fk: function (q) { setQ(q); x.rk_fk(); return copy(f64(x.rk_T(), 16), 0, 16); },
      jointPoses: jointPoses,
      placements: placements,
      jacobian: function (q) {
        setQ(q); x.rk_jacobian();
        var flat = f64(x.rk_J(), 6 * n), J = [];
        for (var r = 0; r < 6; r++) { J.push(copy(flat, r * n, (r + 1) * n)); }
        return J;
      },
      gravity: function (q) { setQ(q); x.rk_gravity(); return copy(f64(x.rk_tau(), n), 0, n); },
      // damped least squares from q toward T: {q, steps (-1: not converged)}
      dls: function (T, q, lambda, iters, tol) {
        setQ(q);
        var t = f64(x.rk_T(), 16);
        for (var i = 0; i < 16; i++) { t[i] = T[i]; }
        var steps = x.rk_dls(lambda, iters, tol);
        return { q: copy(f64(x.rk_q(), n), 0, n), steps: steps };
      },
      ik: function (T, wristRef) {
        if (!hasIk) { return null; }
        var t = f64(x.rk_T(), 16);
        for (var i = 0; i < 16; i++) { t[i] = T[i]; }
        var count = x.rk_ik(wristRef || 0), sol = f64(x.rk_sol(), count * n);
        var info = new Int32Array(x.memory.buffer, x.rk_info(), 4 * count), out = [];
        for (var s = 0; s < count; s++) {
          var rep = info[4 * s + 1];
          out.push({ q: copy(sol, s * n, (s + 1) * n),
                     label: labels[info[4 * s]] + (rep > 1 ? " #" + rep : ""),
                     withinLimits: info[4 * s + 2] === 1, degenerate: info[4 * s + 3] === 1 });
        }
        return out;
      }
    };
  }

  // the solution nearest q (Euclidean in joint space; revolute differences wrapped to (-pi, pi]
  // when `wrap[i]`), as an index into sols, or -1 when there is none
  function nearest(sols, q, wrap) {
    var best = -1, bestD = Infinity;
    sols.forEach(function (s, k) {
      var d = 0;
      for (var i = 0; i < q.length; i++) {
        var e = s.q[i] - q[i];
        if (wrap && wrap[i]) { e -= 2 * Math.PI * Math.round(e / (2 * Math.PI)); }
        d += e * e;
      }
      if (d < bestD) { bestD = d; best = k; }
    });
    return best;
  }

  return { decode: decode, load: load, nearest: nearest };
})();
if (typeof module !== "undefined" && module.exports) { module.exports = RKWasm; }
