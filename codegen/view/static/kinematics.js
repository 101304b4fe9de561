// codegen view, the arm's forward kinematics (codegen/robot/urdh.py and opw.py; the tests hold this to their fk):
// plain functions of the catalogue's parameters and the joints (deg), row-major 4x4 matrices, as codegenKinematics.
window.codegenKinematics = (function () {
  "use strict";

  const RAD = Math.PI / 180;
  const UR_COS_ALPHA = [0, 1, 1, 0, 0, 1], UR_SIN_ALPHA = [1, 0, 0, 1, -1, 0]; // alpha = 90, 0, 0, 90, -90, 0 deg

  function mul(a, b) { // 4x4 row-major products
    const out = new Array(16);
    for (let r = 0; r < 4; r++) for (let c = 0; c < 4; c++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[4 * r + k] * b[4 * k + c];
      out[4 * r + c] = s;
    }
    return out;
  }
  function origin(m) { return [m[3], m[7], m[11]]; }

  function urChain(p, q) { // UR's DH table: T_i = Rz(q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)
    const a = [0, p.a2, p.a3, 0, 0, 0], d = [p.d1, 0, 0, p.d4, p.d5, p.d6];
    let m = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
    const points = [[0, 0, 0]];
    for (let i = 0; i < 6; i++) {
      const ct = Math.cos(q[i] * RAD), st = Math.sin(q[i] * RAD);
      const ca = UR_COS_ALPHA[i], sa = UR_SIN_ALPHA[i];
      const link = [ct, -st * ca, st * sa, a[i] * ct, st, ct * ca, -ct * sa, a[i] * st, 0, sa, ca, d[i], 0, 0, 0, 1];
      m = mul(m, link);
      points.push(origin(m));
    }
    return { points: points, flange: m, wrist: points[5] };
  }

  function opwChain(p, q) { // Brandstoetter et al.: theta = sign * q + offset; R0e = Rz(t1) Ry(t2 + t3) Rz(t4) Ry(t5) Rz(t6)
    const t = q.map((v, i) => (p.signs[i] * v + p.offsets_deg[i]) * RAD);
    const c1 = Math.cos(t[0]), s1 = Math.sin(t[0]), t23 = t[1] + t[2];
    const turn = (x, y, z) => [x * c1 - y * s1, x * s1 + y * c1, z];
    const elbow = [p.a1 + p.c2 * Math.sin(t[1]), p.c1 + p.c2 * Math.cos(t[1])];
    const offset = [elbow[0] + p.a2 * Math.cos(t23), elbow[1] - p.a2 * Math.sin(t23)];
    const wrist = [offset[0] + p.c3 * Math.sin(t23), offset[1] + p.c3 * Math.cos(t23)];
    const rz = (a) => [Math.cos(a), -Math.sin(a), 0, 0, Math.sin(a), Math.cos(a), 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
    const ry = (a) => [Math.cos(a), 0, Math.sin(a), 0, 0, 1, 0, 0, -Math.sin(a), 0, Math.cos(a), 0, 0, 0, 0, 1];
    let r = mul(mul(rz(t[0]), ry(t23)), mul(mul(rz(t[3]), ry(t[4])), rz(t[5])));
    const w = turn(wrist[0], p.b, wrist[1]);
    r[3] = w[0] + p.c4 * r[2]; r[7] = w[1] + p.c4 * r[6]; r[11] = w[2] + p.c4 * r[10];
    const points = [[0, 0, 0], [0, 0, p.c1], turn(p.a1, 0, p.c1), turn(elbow[0], p.b, elbow[1]),
      turn(offset[0], p.b, offset[1]), w, origin(r)];
    return { points: points, flange: r, wrist: w };
  }

  function chain(arm, q) { return (arm.family === "ur" ? urChain : opwChain)(arm.params, q); }

  return { RAD: RAD, mul: mul, origin: origin, chain: chain };
})();
