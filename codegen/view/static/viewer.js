// codegen view: draws a cell and the interpreter's traces of its programs with three.js (the global THREE).
// The data (the <script id="view-data"> JSON) is the trace itself: each move's joints, pose, file line and time.
// Between two moves the arm is drawn at joints interpolated linearly (the trace gives where each move ends).
// Fragment: #target=<name>&program=<n>&m=<moves> (m: 0 = the start, k = the end of move k) or &t=<seconds>.
(function () {
  "use strict";

  const PALETTE = {
    arm: 0xff6a00, joint: 0x3a3a3a, base: 0x505050, tool: 0x4a4a4a, tcp: 0x000000, path: 0x1f77b4,
    reference: 0x00b050, frame: 0x7f7f7f, mark: 0xd62728, taught: 0x9467bd, bench: 0xaab4c0, wood: 0x8c5a2b,
    box: 0xc8a165, label: 0xffffff, sheet: 0xf0ead8, pick: 0x9aa5b1, belt: 0x3c3c3c, window: 0x17becf,
    camera: 0xe377c2, place: 0x9aa5b1, beam: 0xff0000, sensor: 0x2f4f6f, floor: 0xdddddd, solid: 0x8f9aa8,
    nearest: 0xd62728, current: 0xffd000,
  };
  const AXIS_COLOURS = [0xe00000, 0x00a000, 0x0000e0];
  const data = JSON.parse(document.getElementById("view-data").textContent);
  const api = { ready: false, errors: [], data: data };
  window.codegenView = api;
  window.addEventListener("error", (e) => api.errors.push(String(e.message)));

  // ---- forward kinematics (kinematics.js) -------------------------------------------------------------------
  const { RAD, mul, origin, chain } = window.codegenKinematics;
  const { fixed, readable } = window.codegenNumbers;
  const { makeTimeline, interpolate, interpolatePose } = window.codegenTimeline;
  const frameAt = (time) => window.codegenTimeline.frameAt(timeline, time);
  api.fk = function (viewIndex, q) { return chain(data.views[viewIndex].arm, q); };

  // ---- scene -------------------------------------------------------------------------------------------
  const stage = document.getElementById("stage");
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    document.getElementById("nogl").hidden = false;
    api.errors.push("no WebGL: " + e.message);
    return;
  }
  renderer.setPixelRatio(1);
  stage.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xffffff);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x999999, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2);
  sun.position.set(0.4, -0.6, 1.0);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(40, 1, 5, 100000);
  camera.up.set(0, 0, 1);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.addEventListener("change", () => render());

  function matrix(flat16) { const m = new THREE.Matrix4(); m.set(...flat16); return m; }
  function material(role, opacity) {
    const options = { color: PALETTE[role] };
    if (opacity !== undefined && opacity < 1) { options.transparent = true; options.opacity = opacity; }
    return new THREE.MeshLambertMaterial(options);
  }
  function lineObject(points, colour, dashed, width) {
    const geometry = new THREE.BufferGeometry().setFromPoints(points.map((p) => new THREE.Vector3(...p)));
    const mat = dashed ? new THREE.LineDashedMaterial({ color: colour, dashSize: 12, gapSize: 8 })
      : new THREE.LineBasicMaterial({ color: colour, linewidth: width || 1 });
    const out = new THREE.Line(geometry, mat);
    if (dashed) out.computeLineDistances();
    return out;
  }
  function triad(flat16, size) {
    const group = new THREE.Group();
    for (let i = 0; i < 3; i++) {
      const end = [0, 0, 0]; end[i] = size;
      group.add(lineObject([[0, 0, 0], end], AXIS_COLOURS[i]));
    }
    group.applyMatrix4(matrix(flat16));
    return group;
  }
  function sprite(text, at) {
    const canvas = document.createElement("canvas");
    const ctx = canvas.getContext("2d");
    ctx.font = "28px sans-serif";
    canvas.width = Math.ceil(ctx.measureText(text).width) + 12; canvas.height = 40;
    ctx.font = "28px sans-serif"; ctx.fillStyle = "rgba(255,255,255,0.75)"; ctx.fillRect(0, 0, canvas.width, 40);
    ctx.fillStyle = "#222"; ctx.fillText(text, 6, 30);
    const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(canvas), depthTest: false }));
    s.position.set(...at);
    s.userData.aspect = canvas.width / 40;
    s.userData.text = text;
    return s;
  }

  // the scene's size (mm): what is drawn at no size of its own (dots, axes) scales with it
  const extent = new THREE.Box3();
  data.objects.forEach((o) => {
    if (o.pose) extent.expandByPoint(new THREE.Vector3(o.pose[3], o.pose[7], o.pose[11]));
    (o.points || []).forEach((p) => extent.expandByPoint(new THREE.Vector3(...p)));
    if (o.position) extent.expandByPoint(new THREE.Vector3(...o.position));
  });
  const sceneSize = extent.isEmpty() ? 1000 : Math.max(200, extent.getSize(new THREE.Vector3()).length());
  const axisSize = (size) => Math.min(size, sceneSize * 0.05);
  const LABELLED = new Set(["mark", "wood", "pick", "place", "sensor", "belt", "camera", "window", "bench", "solid"]);
  const labels = new THREE.Group();
  const cellGroup = new THREE.Group();
  const meshes = []; // per object: the meshes drawn for it (a box's: its faces and its edges)
  function addObject(o, index) {
    meshes[index] = [];
    if (o.type === "frame") {
      cellGroup.add(triad(o.pose, axisSize(o.size)));
      const dot = new THREE.Mesh(new THREE.SphereGeometry(axisSize(o.size) / 8, 12, 8), material(o.role));
      dot.position.set(o.pose[3], o.pose[7], o.pose[11]);
      cellGroup.add(dot);
    } else if (o.type === "box") {
      const mesh = new THREE.Mesh(new THREE.BoxGeometry(...o.size), material(o.role, o.opacity));
      mesh.applyMatrix4(matrix(o.pose));
      cellGroup.add(mesh);
      meshes[index].push(mesh);
      if (o.role !== "label") {
        const edges = new THREE.LineSegments(new THREE.EdgesGeometry(mesh.geometry),
          new THREE.LineBasicMaterial({ color: 0x000000, transparent: true, opacity: 0.25 }));
        edges.applyMatrix4(matrix(o.pose));
        cellGroup.add(edges);
        meshes[index].push(edges);
      }
    } else if (o.type === "cylinder") {
      const geometry = new THREE.CylinderGeometry(o.radius, o.radius, o.length, 32);
      geometry.rotateX(Math.PI / 2); // three's cylinders stand along y, the cell's along the pose's z
      const mesh = new THREE.Mesh(geometry, material(o.role, o.opacity));
      mesh.applyMatrix4(matrix(o.pose));
      cellGroup.add(mesh);
      meshes[index].push(mesh);
    } else if (o.type === "line") {
      cellGroup.add(lineObject(o.points, PALETTE[o.role], o.dashed));
    } else if (o.type === "point") {
      const dot = new THREE.Mesh(new THREE.SphereGeometry(sceneSize * 0.004, 12, 8), material(o.role));
      dot.position.set(...o.position);
      cellGroup.add(dot);
    }
    if (o.label && LABELLED.has(o.role)) {
      const at = o.pose ? [o.pose[3], o.pose[7], o.pose[11]] : (o.position || o.points[o.points.length - 1]);
      labels.add(sprite(o.label, at));
    }
  }
  data.objects.forEach(addObject);
  scene.add(cellGroup);
  scene.add(labels);

  // ---- the arm (or, without one, the TCP alone) -------------------------------------------------------------
  const armGroup = new THREE.Group();
  scene.add(armGroup);
  const dynamic = new THREE.Group(); // the run's path and reference
  // the move the arm is on: a rod over the faint path (a line is one pixel wide whatever its width says)
  const moving = new THREE.Mesh(new THREE.CylinderGeometry(1, 1, 1, 12), material("current"));
  const movingRadius = sceneSize * 0.002;
  moving.visible = false;
  scene.add(dynamic);
  scene.add(moving);
  let links = [], joints = [], toolMesh = null, tcpTriad = null, tcpDot = null, armScale = 1;
  const UP = new THREE.Vector3(0, 1, 0);

  function placeCylinder(mesh, a, b) {
    const va = new THREE.Vector3(...a), vb = new THREE.Vector3(...b);
    const length = va.distanceTo(vb);
    mesh.visible = length > 1e-6;
    if (!mesh.visible) return;
    mesh.position.copy(va).add(vb).multiplyScalar(0.5);
    mesh.quaternion.setFromUnitVectors(UP, vb.clone().sub(va).normalize());
    mesh.scale.set(1, length, 1);
  }

  function buildArm(view) {
    armGroup.clear();
    links = []; joints = [];
    const arm = view.arm;
    const reach = arm ? armReach(arm) : 300;
    armScale = reach / 1000;
    if (arm) {
      const radius = Math.max(8, reach * 0.035);
      const base = new THREE.Mesh(new THREE.CylinderGeometry(radius * 2.2, radius * 2.6, radius * 1.2, 32), material("base"));
      base.rotation.x = Math.PI / 2; base.position.z = radius * 0.6;
      armGroup.add(base);
      for (let i = 0; i < 6; i++) {
        const link = new THREE.Mesh(new THREE.CylinderGeometry(radius, radius, 1, 20), material("arm"));
        links.push(link); armGroup.add(link);
        const joint = new THREE.Mesh(new THREE.SphereGeometry(radius * 1.25, 20, 14), material("joint"));
        joints.push(joint); armGroup.add(joint);
      }
      toolMesh = new THREE.Mesh(new THREE.CylinderGeometry(radius * 0.45, radius * 0.45, 1, 16), material("tool"));
      armGroup.add(toolMesh);
    } else {
      toolMesh = null;
    }
    const size = Math.max(sceneSize, arm ? reach * 2 : 0);
    armGroup.add(triad([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], size * 0.08)); // the base (= world) frame
    tcpDot = new THREE.Mesh(new THREE.SphereGeometry(size * 0.008, 16, 10), material("tcp"));
    armGroup.add(tcpDot);
    tcpTriad = new THREE.Group();
    for (let i = 0; i < 3; i++) {
      const end = [0, 0, 0]; end[i] = size * 0.04;
      tcpTriad.add(lineObject([[0, 0, 0], end], AXIS_COLOURS[i]));
    }
    tcpTriad.matrixAutoUpdate = false;
    armGroup.add(tcpTriad);
  }
  function armReach(arm) {
    const p = arm.params;
    return arm.family === "ur" ? Math.abs(p.a2) + Math.abs(p.a3) + p.d1
      : p.c1 + p.c2 + Math.hypot(p.a2, p.c3) + p.c4 + Math.abs(p.a1);
  }

  function showBoxes(run, move) { // a box the run places is there from its move on, one it takes up to its move
    const there = new Map();
    if (run) run.boxes.forEach(([index, at, placing]) => there.set(index, placing ? move >= at : move <= at));
    meshes.forEach((list, index) => list.forEach((mesh) => {
      const ghost = there.has(index) && !there.get(index);
      if (mesh.userData.opacity === undefined) mesh.userData.opacity = mesh.material.opacity;
      const transparent = ghost || mesh.userData.opacity < 1;
      if (mesh.material.transparent !== transparent) mesh.material.needsUpdate = true; // the shader's OPAQUE
      mesh.material.transparent = transparent;
      mesh.material.opacity = ghost ? 0.12 : mesh.userData.opacity;
      mesh.material.depthWrite = !ghost;
    }));
  }

  function poseArm(view, q, tcp) {
    if (view.arm && q) {
      const c = chain(view.arm, q);
      for (let i = 0; i < 6; i++) {
        placeCylinder(links[i], c.points[i], c.points[i + 1]);
        joints[i].position.set(...c.points[i + 1]);
      }
      tcp = mul(c.flange, view.arm.tcp2flange);
      placeCylinder(toolMesh, c.points[6], origin(tcp));
    }
    if (tcp) {
      tcpDot.position.set(...origin(tcp));
      tcpTriad.matrix.copy(matrix(tcp));
      tcpTriad.matrixWorldNeedsUpdate = true;
    }
    return tcp;
  }

  // ---- runs and timeline ----------------------------------------------------------------------------------
  const targetSelect = document.getElementById("target"), programSelect = document.getElementById("program");
  const slider = document.getElementById("slider"), playButton = document.getElementById("play");
  const info = document.getElementById("info"), lineBox = document.getElementById("line");
  let current = { view: -1, program: -1, position: 0, time: 0 }, timeline = null, playing = false;

  data.views.forEach((v, i) => targetSelect.add(new Option(v.label, String(i))));

  function selectView(index, programIndex) {
    current.view = index;
    const view = data.views[index];
    targetSelect.value = String(index);
    programSelect.innerHTML = "";
    view.programs.forEach((p, i) => programSelect.add(new Option(p.label, String(i))));
    buildArm(view);
    selectProgram(programIndex || 0);
  }

  function selectProgram(index) {
    const view = data.views[current.view];
    current.program = Math.min(index, Math.max(0, view.programs.length - 1));
    programSelect.value = String(current.program);
    const program = view.programs[current.program];
    dynamic.clear();
    timeline = program ? makeTimeline(view, program) : { frames: [], total: 0 };
    if (program) {
      program.runs.forEach((run) => {
        const points = run.moves.filter((m) => m.pose).map((m) => origin(m.pose));
        if (points.length > 1) { // faint: the move the arm is on stands out over it (moving)
          const line = lineObject(points, PALETTE.path, false, 2);
          line.material.transparent = true; line.material.opacity = 0.35;
          dynamic.add(line);
        }
        points.forEach((p) => {
          const dot = new THREE.Mesh(new THREE.SphereGeometry(sceneSize * 0.0025, 8, 6), material("path"));
          dot.position.set(...p); dynamic.add(dot);
        });
        const near = run.clearance && run.moves[run.clearance.move];
        if (near && near.pose) { // the move that comes nearest a solid (or the arm itself): a red ball at its end
          const ring = new THREE.Mesh(new THREE.SphereGeometry(sceneSize * 0.008, 16, 12), material("nearest", 0.7));
          ring.position.set(...origin(near.pose)); dynamic.add(ring);
        }
        (run.reference || []).forEach((pose, k) => {
          if (!pose) return;
          dynamic.add(triad(pose, axisSize(30)));
          const dot = new THREE.Mesh(new THREE.SphereGeometry(sceneSize * 0.005, 12, 8), material("reference", 0.6));
          dot.position.set(...origin(pose)); dynamic.add(dot);
        });
      });
    }
    slider.max = String(Math.max(0.01, timeline.total));
    fitCamera();
    setTime(0);
  }

  function setTime(time) {
    time = Math.max(0, Math.min(time, timeline.total));
    const [index, s] = frameAt(time);
    const f = timeline.frames;
    current.time = time;
    if (!f.length) { current.position = 0; showInfo(null, null, null); render(); return; }
    const a = f[index], b = f[Math.min(index + 1, f.length - 1)];
    const sameRun = b.run === a.run;
    const q = interpolate(a.joints, sameRun ? b.joints : a.joints, s);
    const pose = interpolatePose(a.pose, sameRun ? b.pose : a.pose, s);
    const view = data.views[current.view];
    const tcp = poseArm(view, q, pose);
    current.position = index + s;
    showBoxes(data.views[current.view].programs[current.program].runs[a.run], a.move);
    // the move the arm is on (between two keyframes of a run), else the one it has just ended
    const before = f[Math.max(index - 1, 0)];
    current.segment = s > 0 && sameRun ? [a.pose, b.pose] : (before.run === a.run ? [before.pose, a.pose] : [null, null]);
    const [from, to] = current.segment.map((m) => m && new THREE.Vector3(...origin(m)));
    moving.visible = Boolean(from && to && from.distanceTo(to) > 1e-6);
    if (moving.visible) {
      moving.position.copy(from).lerp(to, 0.5);
      moving.scale.set(movingRadius, from.distanceTo(to), movingRadius);
      moving.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), to.clone().sub(from).normalize());
    }
    current.joints = q;
    current.tcp = tcp;
    slider.value = String(time);
    showInfo(a, b, s);
    render();
  }

  function setPosition(position) { // position in keyframes: k = the k-th keyframe (0: the first run's start)
    const f = timeline.frames;
    if (!f.length) return setTime(0);
    const k = Math.max(0, Math.min(Math.floor(position), f.length - 1)), s = position - k;
    const next = f[Math.min(k + 1, f.length - 1)];
    setTime(f[k].time + (next.time - f[k].time) * s);
  }

  function showInfo(a, b, s) {
    info.innerHTML = "";
    lineBox.textContent = "";
    const view = data.views[current.view], program = view.programs[current.program];
    const add = (term, value) => {
      const dt = document.createElement("dt"), dd = document.createElement("dd");
      dt.textContent = term; dd.textContent = value; info.append(dt, dd);
    };
    if (!program) { add("program", "none"); return; }
    if (program.problem) add("note", program.problem);
    if (!a) return;
    const frame = s > 0 && b.run === a.run ? b : a; // the move under way (or just ended)
    const run = program.runs[frame.run];
    add("run", `${frame.run + 1} of ${program.runs.length}: ${readable(run.what)}`);
    if (frame.move < 0) {
      add("move", `start (${run.moves.length} moves)`);
    } else {
      const m = run.moves[frame.move];
      add("move", `${frame.move + 1} of ${run.moves.length}${s > 0 ? " (under way)" : ""}: ${m.kind}`);
      add("where", `${program.file}:${m.line}`);
      add("clock", `${m.t.toFixed(3)} s (program)`);
      lineBox.textContent = program.source[String(m.line)] || "";
      const outputs = run.outputs.filter((o) => o.after <= frame.move + 1);
      if (outputs.length) { const o = outputs[outputs.length - 1]; add("output", `${o.name} = ${o.value ? "on" : "off"}`); }
    }
    if (current.joints) add("joints", current.joints.map((v) => fixed(v, 2)).join(", ") + " deg");
    if (current.tcp) add("TCP", origin(current.tcp).map((v) => fixed(v, 2)).join(", ") + " mm");
    if (frame.move === run.moves.length - 1 && run.halt) add("stop", run.halt);
    if (run.clearance) {
      const c = run.clearance, here = frame.move === c.move ? " (this move)" : "";
      add("least clearance", `${c.distance.toFixed(1)} mm, ${c.body} - ${c.other}, move ${c.move + 1}: the ` +
        `${c.what}${here}; the cell's clearance ${c.clearance} mm`);
    }
  }

  // ---- camera ---------------------------------------------------------------------------------------------
  function fitCamera() {
    const box = new THREE.Box3().setFromObject(cellGroup); // every object whole (a fence to its ends), not its centre
    const points = [];
    data.objects.forEach((o) => {
      if (o.pose) points.push([o.pose[3], o.pose[7], o.pose[11]]);
      if (o.points) points.push(...o.points);
      if (o.position) points.push(o.position);
    });
    timeline.frames.forEach((f) => { if (f.pose) points.push(origin(f.pose)); });
    const view = data.views[current.view];
    if (view.arm) { const r = armReach(view.arm) * 0.8; points.push([-r * 0.3, -r * 0.3, 0], [r * 0.3, r * 0.3, r]); }
    points.forEach((p) => box.expandByPoint(new THREE.Vector3(...p)));
    if (box.isEmpty()) box.expandByPoint(new THREE.Vector3(0, 0, 0));
    const centre = box.getCenter(new THREE.Vector3()), size = box.getSize(new THREE.Vector3()).length();
    // the box's diagonal across the narrower of the two fields of view, at the box's centre: every object on the screen
    const half = Math.min(camera.fov * RAD, 2 * Math.atan(Math.tan((camera.fov * RAD) / 2) * camera.aspect)) / 2;
    const distance = (Math.max(300, size) / 2) / Math.tan(half);
    const direction = new THREE.Vector3(1.0, -1.5, 1.0).normalize();
    camera.position.copy(centre).addScaledVector(direction, distance);
    camera.near = distance / 100; camera.far = distance * 20;
    camera.updateProjectionMatrix();
    controls.target.copy(centre);
    controls.update();
    labels.children.forEach((s) => { const h = distance * 0.018; s.scale.set(h * s.userData.aspect, h, 1); });
    floor.position.set(centre.x, centre.y, Math.min(0, box.min.z) - 1);
    floor.scale.setScalar(Math.max(500, size) / 1000);
  }
  const floor = new THREE.GridHelper(1000, 20, PALETTE.floor, PALETTE.floor);
  floor.rotation.x = Math.PI / 2;
  scene.add(floor);

  function resize() {
    // the viewer fills the window below the page's header (at least its CSS min-height); the report follows below
    const header = document.querySelector("header"), viewer = document.getElementById("viewer");
    viewer.style.height = Math.max(0, window.innerHeight - (header ? header.offsetHeight : 0)) + "px";
    const w = stage.clientWidth, h = stage.clientHeight;
    renderer.setSize(w, h);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
    render();
  }
  function declutter() { // overlapping labels: the first shown, the others hidden (labels.js)
    const w = renderer.domElement.clientWidth, h = renderer.domElement.clientHeight;
    const rects = labels.children.map((s) => window.codegenLabels.rect(s, camera, w, h));
    window.codegenLabels.shown(rects).forEach((shown, i) => {
      labels.children[i].visible = shown;
      labels.children[i].userData.rect = rects[i];
    });
  }
  function render() {
    if (labels.visible) declutter();
    renderer.render(scene, camera);
  }

  api.project = function (xyz) { // page pixels of a point (mm, base frame) as drawn now
    const v = new THREE.Vector3(...xyz).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return [r.left + ((v.x + 1) / 2) * r.width, r.top + ((1 - v.y) / 2) * r.height, v.z];
  };
  api.state = function () {
    const f = timeline.frames, k = Math.floor(current.position);
    return { view: current.view, program: current.program, position: current.position, time: current.time,
      total: timeline.total, frames: f.length, joints: current.joints || null, tcp: current.tcp || null,
      run: f.length ? f[k].run : null, move: f.length ? f[k].move : null,
      segment: moving.visible ? current.segment.map(origin) : null };
  };
  api.labels = function () { // each label: its text, whether it is shown, its rectangle on the page (pixels)
    const r = renderer.domElement.getBoundingClientRect();
    return labels.children.map((s) => ({ text: s.userData.text, shown: labels.visible && s.visible,
      rect: s.userData.rect ? [s.userData.rect[0] + r.left, s.userData.rect[1] + r.top,
        s.userData.rect[2] + r.left, s.userData.rect[3] + r.top] : null }));
  };
  api.select = function (view, program) { selectView(view, program); };
  api.setPosition = setPosition;
  api.setTime = setTime;

  // ---- controls -------------------------------------------------------------------------------------------
  targetSelect.addEventListener("change", () => selectView(Number(targetSelect.value), 0));
  programSelect.addEventListener("change", () => selectProgram(Number(programSelect.value)));
  slider.addEventListener("input", () => { playing = false; playButton.textContent = "play"; setTime(Number(slider.value)); });
  document.getElementById("labels").addEventListener("change", (e) => { labels.visible = e.target.checked; render(); });
  let last = null;
  function tick(now) {
    if (!playing) { last = null; return; }
    if (last !== null) {
      const speed = Number(document.getElementById("speed").value);
      const next = current.time + ((now - last) / 1000) * speed;
      setTime(next >= timeline.total ? 0 : next);
    }
    last = now;
    requestAnimationFrame(tick);
  }
  playButton.addEventListener("click", () => {
    playing = !playing;
    playButton.textContent = playing ? "pause" : "play";
    if (playing) requestAnimationFrame(tick);
  });

  const legend = document.getElementById("legend");
  [["arm", "arm"], ["path", "path (trace)"], ["current", "the move now"], ["reference", "reference"],
    ["taught", "taught"], ["box", "box"]]
    .forEach(([role, text]) => {
      const swatch = document.createElement("span");
      swatch.className = "swatch";
      swatch.style.background = "#" + PALETTE[role].toString(16).padStart(6, "0");
      legend.append(swatch, document.createTextNode(text));
    });

  function fromHash() {
    const params = new URLSearchParams(location.hash.replace(/^#/, ""));
    let view = data.views.findIndex((v) => v.target === params.get("target"));
    if (view < 0) view = Math.max(0, current.view);
    const program = params.has("program") ? Number(params.get("program")) : (view === current.view ? current.program : 0);
    if (view !== current.view) selectView(view, program);
    else if (program !== current.program) selectProgram(program);
    if (params.has("m")) setPosition(Number(params.get("m")));
    else if (params.has("t")) setTime(Number(params.get("t")));
    if (params.get("labels") === "0") { document.getElementById("labels").checked = false; labels.visible = false; render(); }
  }
  window.addEventListener("hashchange", fromHash);
  window.addEventListener("resize", resize);
  resize();
  if (data.views.length) fromHash();
  else { timeline = { frames: [], total: 0 }; document.getElementById("viewer").hidden = true; }
  resize();
  api.ready = true;
})();
