// robokit teach page: the robot's generated C (robokit codegen), compiled to WebAssembly by
// robokit/viz/wasm.py, called from JavaScript. No DOM: usable from the page and from Node.
//
// RKWasm.load(bytes) -> a kinematics object over the module's robot-independent entry points
// (rk_fk, rk_jacobian, rk_gravity, rk_ik on static buffers in the module's memory):
//   fk(q)        -> T, the tool pose in the base frame (16 numbers, row-major)
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
    var hasIk = x.rk_has_ik() === 1, labels = [];
    for (var k = 0; k < x.rk_label_count(); k++) { labels.push(cstr(x.rk_label(k))); }
    return {
      n: n,
      hasIk: hasIk,
      labels: labels,
      maxSolutions: x.rk_max_solutions(),
      fk: function (q) { setQ(q); x.rk_fk(); return copy(f64(x.rk_T(), 16), 0, 16); },
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
