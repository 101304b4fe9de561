// codegen view, the timeline of a program's runs: keyframes at each run's start and each move's end (the program's
// clock, a move it gives no time shown MIN_MOVE_S long), and the arm's joints and the TCP's pose between two of them.
window.codegenTimeline = (function () {
  "use strict";

  const MIN_MOVE_S = 0.25; // a move the program clock gives no time is shown this long

  function makeTimeline(view, program) { // keyframes: each run's start, then the end of each of its moves
    const frames = [];
    let time = 0;
    program.runs.forEach((run, r) => {
      const first = run.moves[0];
      frames.push({ run: r, move: -1, joints: run.start || (first && first.joints), pose: run.start ? null : first && first.pose, time: time, clock: 0 });
      let last = 0;
      run.moves.forEach((m, k) => {
        time += Math.max(MIN_MOVE_S, m.t - last);
        last = m.t;
        frames.push({ run: r, move: k, joints: m.joints, pose: m.pose, time: time, clock: m.t });
      });
    });
    return { frames: frames, total: time };
  }

  function frameAt(timeline, time) { // [index of the keyframe before, fraction to the next]
    const f = timeline.frames;
    if (!f.length) return [0, 0];
    let lo = 0, hi = f.length - 1;
    if (time <= f[0].time) return [0, 0];
    if (time >= f[hi].time) return [hi, 0];
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (f[mid].time <= time) lo = mid; else hi = mid; }
    const span = f[hi].time - f[lo].time;
    return [lo, span > 0 ? (time - f[lo].time) / span : 0];
  }

  function interpolate(a, b, s) {
    if (!a || !b || s <= 0) return a || b;
    return a.map((v, i) => v + (b[i] - v) * s);
  }
  function interpolatePose(a, b, s) {
    if (!a || !b || s <= 0) return a || b;
    const ma = new THREE.Matrix4().set(...a), mb = new THREE.Matrix4().set(...b);
    const pa = new THREE.Vector3(), pb = new THREE.Vector3(), qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
    const scale = new THREE.Vector3();
    ma.decompose(pa, qa, scale); mb.decompose(pb, qb, scale);
    const m = new THREE.Matrix4().compose(pa.lerp(pb, s), qa.slerp(qb, s), new THREE.Vector3(1, 1, 1));
    const e = m.elements; // column-major
    return [e[0], e[4], e[8], e[12], e[1], e[5], e[9], e[13], e[2], e[6], e[10], e[14], 0, 0, 0, 1];
  }

  return { makeTimeline: makeTimeline, frameAt: frameAt, interpolate: interpolate, interpolatePose: interpolatePose };
})();
