// kincalc view: the page. Reads the robot kincalc embedded (the JSON document in
// #kincalc-data), builds the controls, and on every change computes the pose, the
// Jacobian's measures and the drawing from the chain (Kin, Scene).
//
// Units: the document is SI (m, rad) except the IK document, which is kincalc ik's JSON
// in the user's units; the joints are kept in SI and converted at the edges (the
// sliders, the boxes, the read-outs), as kincalc does. Names from the robot file are
// text: they go into the page with textContent only.
"use strict";

(() => {
  const data = JSON.parse(document.getElementById("kincalc-data").textContent);
  const chain = data.chain;
  const n = chain.revolute.length;
  const units = data.units;
  const style = data.style;
  const $ = (id) => document.getElementById(id);

  // --- units at the edges ---------------------------------------------------------

  const perSI = (i) => (chain.revolute[i] ? units.per_rad : units.per_m);
  const toUser = (i, v) => v * perSI(i);
  const toSI = (i, v) => v / perSI(i);
  const lengthName = units.length === "unitless" ? "" : units.length;
  const angleName = units.angle === "deg" ? "\u00b0" : " rad";
  const jointUnit = (i) => (chain.revolute[i] ? angleName : (lengthName ? " " + lengthName : ""));
  const DECIMALS = { deg: 2, rad: 4, m: 4, cm: 2, mm: 1, in: 3, unitless: 4 };

  function fmt(v, decimals) {
    const s = v.toFixed(decimals);
    return /^-0\.?0*$/.test(s) ? s.slice(1) : s;
  }
  const fmtAngle = (rad) => fmt(rad * units.per_rad, DECIMALS[units.angle]);
  const fmtLength = (m) => fmt(m * units.per_m, DECIMALS[units.length]);
  // a joint's value already in the user's unit, and one in SI
  const fmtUser = (i, v) => fmt(v, DECIMALS[chain.revolute[i] ? units.angle : units.length]);
  const fmtJoint = (i, v) => fmtUser(i, toUser(i, v));

  function el(tag, text, cls) {
    const e = document.createElement(tag);
    if (text !== undefined) e.textContent = text;
    if (cls) e.className = cls;
    return e;
  }

  // --- the state: joints in SI --------------------------------------------------------

  let q = data.q.slice();
  const rows = []; // per joint: {slider, box, row}

  function sliderRange(i) {
    const j = data.joints[i];
    if (j.limits) return j.limits;
    return chain.revolute[i] ? [-Math.PI, Math.PI] : [-data.size, data.size];
  }

  function withinLimits(i, v) {
    const lim = data.joints[i].limits;
    const tol = data.limit_tol * (chain.revolute[i] ? 1 : data.size);
    return !lim || (v >= lim[0] - tol && v <= lim[1] + tol);
  }

  // --- the page's parts ---------------------------------------------------------------

  function buildHeader() {
    const r = data.robot;
    document.title = `${r.name} - kincalc view`;
    $("robot-name").textContent = r.name;
    $("robot-title").textContent = r.title;
    const kinds = chain.revolute.map((rev) => (rev ? "R" : "P")).join("");
    const lengths = lengthName ? `lengths in ${lengthName}` : "unitless lengths";
    $("robot-meta").textContent =
      `${n} joints (${kinds}), ${data.convention_name}; angles in ${units.angle}, ${lengths}`;
    $("robot-source").textContent = r.source ? `Source: ${r.source}` : "";
    $("footer-text").textContent = `Written by kincalc ${data.kincalc} (${data.command}). ` +
      "The pose, the Jacobian and the drawing are computed in this page from the robot's " +
      "chain; kincalc fk and kincalc jacobian give the same numbers.";
  }

  function buildJoints() {
    const table = $("joints");
    data.joints.forEach((j, i) => {
      const [lo, hi] = sliderRange(i).map((v) => toUser(i, v));
      const tr = el("tr");
      tr.append(nameCell(j.name));
      const slider = el("input");
      Object.assign(slider, { type: "range", min: lo, max: hi, step: sliderStep(i, hi - lo) });
      slider.setAttribute("aria-label", `${j.name} slider`);
      const box = el("input");
      Object.assign(box, { type: "number", min: lo, max: hi, step: "any" });
      box.setAttribute("aria-label", `${j.name} value`);
      const short = (v) => String(Number(fmtJoint(i, v)));
      const limits = j.limits ? `[${short(j.limits[0])}, ${short(j.limits[1])}]` : "no limits";
      const cells = [slider, box, el("span", jointUnit(i).trim(), "unit"),
        el("span", limits, "limits")];
      cells.forEach((c, k) => {
        const td = el("td", undefined, k ? undefined : "slider");
        td.append(c);
        tr.append(td);
      });
      table.append(tr);
      slider.addEventListener("input", () => {
        q[i] = toSI(i, Number(slider.value));
        box.value = slider.value;
        fitBox(box);
        update();
      });
      box.addEventListener("input", () => fitBox(box));
      box.addEventListener("change", () => {
        const v = Number(box.value);
        if (box.value === "" || !Number.isFinite(v)) { syncControls(); return; }
        q[i] = toSI(i, Math.min(hi, Math.max(lo, v)));
        syncControls();
        update();
      });
      rows.push({ slider, box, row: tr });
    });
    $("home").addEventListener("click", () => goTo(data.home, false));
    $("zero").addEventListener("click", () => goTo(new Array(n).fill(0), false));
  }

  // a joint's name (text), free to break after "_" when the table wraps
  function nameCell(name) {
    const th = el("th", name);
    th.dataset.name = name;
    return th;
  }

  function breakNames(wrap) {
    $("joints").querySelectorAll("th").forEach((th) => {
      const parts = th.dataset.name.split(/(?<=_)/);
      const text = (part) => document.createTextNode(part);
      th.replaceChildren(...parts.flatMap((part, k) =>
        (wrap && k ? [el("wbr"), text(part)] : [text(part)])));
    });
  }

  // a number box as wide as its value: it cannot wrap, so it grows
  function fitBox(box) {
    const width = `max(86px, calc(${box.value.length}ch + 32px))`;
    if (box.style.width !== width) { box.style.width = width; fitJoints(); }
  }

  // the joints table on one line per joint where that fits the panel, else wrapping
  function fitJoints() {
    const table = $("joints");
    table.classList.remove("wrap");
    breakNames(false);
    const wrap = table.offsetWidth > table.parentElement.clientWidth;
    table.classList.toggle("wrap", wrap);
    if (wrap) breakNames(true);
  }

  function sliderStep(i, span) {
    if (chain.revolute[i]) return units.angle === "deg" ? 0.1 : 0.001;
    const raw = span / 1000;
    return Math.pow(10, Math.floor(Math.log10(raw))); // a power of ten below span / 1000
  }

  function syncControls() {
    rows.forEach(({ slider, box, row }, i) => {
      slider.value = toUser(i, q[i]);
      box.value = fmtJoint(i, q[i]);
      fitBox(box);
      row.classList.toggle("out", !withinLimits(i, q[i]));
    });
  }

  function buildDH() {
    const dh = data.dh;
    $("dh-title").textContent = dh.title;
    const table = $("dh");
    const head = el("tr");
    ["i", ...dh.columns].forEach((c) => head.append(el("th", c)));
    table.append(head);
    dh.rows.forEach((row, i) => {
      const tr = el("tr");
      tr.append(el("td", String(i + 1)));
      // an entry the joint's variable adds to reads "q2 + 90.00°" (or just "q2")
      row.forEach(([value, kind, variable]) => {
        const unit = kind === "angle" ? angleName : ""; // "90.00°", "1.5708 rad"
        const show = (v) => (kind === "angle" ? fmtAngle(v) : fmtLength(v));
        let text = show(value) + unit;
        if (variable !== null) {
          const size = show(Math.abs(value));
          const sign = value < 0 ? "\u2212" : "+";
          text = Number(size) === 0 ? variable : `${variable} ${sign} ${size}${unit}`;
        }
        tr.append(el("td", text, variable !== null ? "variable" : undefined));
      });
      table.append(tr);
    });
    $("dh-note").textContent = dh.note;
  }

  // --- inverse kinematics: kincalc's solutions, one click away -----------------------

  // the solutions' joints, SI (the IK document is in the user's units)
  const solutions = data.ik ? data.ik.solutions.map((s) => s.q.map((v, i) => toSI(i, v))) : [];
  // the IK target T_world_tool, SI
  const target = data.ik ? data.ik.target.T.map((row, r) =>
    row.map((v, c) => (c === 3 && r < 3 ? v / units.per_m : v))) : null;
  let animation = null;

  function buildIK() {
    if (!data.ik) return;
    const ik = data.ik;
    $("ik").hidden = false;
    const p = ik.target.T.slice(0, 3).map((row) => row[3]);
    const R = ik.target.T.slice(0, 3).map((row) => row.slice(0, 3));
    const position = p.map((v) => fmt(v, DECIMALS[units.length])).join(", ");
    let text = `Target position (${position})` + (lengthName ? ` ${lengthName}` : "");
    if (ik.target.orientation_given) {
      text += `, RPY (${Kin.rpy(R).map(fmtAngle).join(", ")})${angleName}`;
    }
    $("ik-target").textContent = text;
    $("ik-method").textContent = `Method: ${ik.method.family} (${ik.method.description})`;
    $("ik-reason").textContent = ik.reason;
    const list = $("solutions");
    ik.solutions.forEach((s, k) => {
      const li = el("li");
      const label = el("label");
      const radio = el("input");
      Object.assign(radio, { type: "radio", name: "solution", value: String(k) });
      radio.addEventListener("change", () => goTo(solutions[k], $("animate").checked));
      label.append(radio, el("span", ` ${k + 1}. ${s.branch}`));
      li.append(label);
      if (!s.within_limits) {
        const by = s.violations.map((v) => {
          const i = data.joints.findIndex((j) => j.name === v.joint);
          return `${v.joint} by ${Number(v.by.toPrecision(3))}${jointUnit(i)}`;
        }).join(", ");
        li.append(el("span", `out of limits (${by})`, "badge out"));
      }
      if (s.singular) {
        li.append(el("span", "singular", "badge singular"));
        if (s.singularity) li.title = s.singularity;
      }
      li.append(el("div", s.q.map((v, i) => fmtUser(i, v)).join("  "), "sol-q"));
      list.append(li);
    });
    if (!ik.solutions.length) list.append(el("li", "No solution.", "none"));
  }

  function markSolution() {
    document.querySelectorAll("#solutions li").forEach((li, k) => {
      const s = solutions[k];
      const here = s && s.every((v, i) => Math.abs(v - q[i]) < 1e-9);
      li.classList.toggle("current", !!here);
      const radio = li.querySelector("input");
      if (radio) radio.checked = !!here;
    });
  }

  // to joints qNew (SI), at once or moving there in joint space
  function goTo(qNew, animate) {
    if (animation !== null) cancelAnimationFrame(animation);
    animation = null;
    if (!animate) { q = qNew.slice(); syncControls(); update(); return; }
    const start = q.slice();
    const t0 = performance.now();
    const step = (now) => {
      const s = Math.min(1, (now - t0) / data.animation_ms);
      const e = s * s * (3 - 2 * s); // smoothstep: starts and stops gently
      q = start.map((a, i) => a + (qNew[i] - a) * e);
      if (s === 1) q = qNew.slice();
      syncControls();
      update();
      animation = s < 1 ? requestAnimationFrame(step) : null;
    };
    animation = requestAnimationFrame(step);
  }

  // --- the read-outs: the text shown, and data-value with every digit -------------

  function setValue(id, text, value) {
    const e = $(id);
    e.textContent = text;
    e.dataset.value = String(value); // full precision, for scripts and the tests
  }

  function showPose(T) {
    const R = T.slice(0, 3).map((row) => row.slice(0, 3));
    ["x", "y", "z"].forEach((c, k) =>
      setValue(`pos-${c}`, fmtLength(T[k][3]), T[k][3] * units.per_m));
    Kin.rpy(R).forEach((v, k) => setValue(`rpy-${k}`, fmtAngle(v), v * units.per_rad));
    Kin.quaternion(R).forEach((v, k) => setValue(`quat-${k}`, fmt(v, 4), v));
    T.forEach((row, r) => row.forEach((v, c) => {
      const shown = c === 3 && r < 3 ? v * units.per_m : v;
      setValue(`T-${r}${c}`, fmt(shown, c === 3 && r < 3 ? DECIMALS[units.length] : 4), shown);
    }));
  }

  function showMeasures(m) {
    setValue("manipulability", m.manipulability.toPrecision(4), m.manipulability);
    setValue("rank", `${m.rank} of ${data.generic_rank}`, m.rank);
    setValue("inverse-condition", m.inverse_condition.toPrecision(3), m.inverse_condition);
    const warn = $("singularity");
    const near = m.inverse_condition < data.near_singular;
    warn.dataset.value = m.singular ? "singular" : near ? "near" : "no";
    if (m.singular) {
      warn.textContent = "Singular: the Jacobian has lost rank; the tool cannot move in every " +
        "direction it can elsewhere.";
    } else if (near) {
      warn.textContent = "Close to a singularity: some tool motions need very fast joints.";
    } else {
      warn.textContent = "Not singular.";
    }
    warn.className = `warning ${warn.dataset.value}`;
  }

  // --- the drawing -------------------------------------------------------------------

  const L = data.size;
  const triadLength = style.triad_fraction * L;
  const ON_TOP = -100; // depth bias (in view radii) of what is drawn over everything
  const UNDER = 100; // and of what everything is drawn over (the grid)

  function unitVector(v) {
    const s = Math.hypot(...v);
    return v.map((x) => x / s);
  }

  // a ring of k points of radius r about axis z through p (a joint's face)
  function ring(p, z, r, k) {
    const helper = Math.abs(z[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    const u = unitVector([z[1] * helper[2] - z[2] * helper[1], z[2] * helper[0] - z[0] * helper[2],
      z[0] * helper[1] - z[1] * helper[0]]);
    const v = [z[1] * u[2] - z[2] * u[1], z[2] * u[0] - z[0] * u[2], z[0] * u[1] - z[1] * u[0]];
    const pts = [];
    for (let t = 0; t < k; t++) {
      const a = (2 * Math.PI * t) / k + (k === 4 ? Math.PI / 4 : 0);
      pts.push([0, 1, 2].map((c) => p[c] + r * (Math.cos(a) * u[c] + Math.sin(a) * v[c])));
    }
    return pts;
  }

  // x, y, z axes of the pose T in red, green, blue, and its name beside the origin
  // (shifted by [dx, dy] pixels, so that base, tool and target do not overprint); a
  // dashed triad (the target's) has no axis letters, the tool's are there already
  function triad(T, length, width, name, shift, dash) {
    const o = [T[0][3], T[1][3], T[2][3]];
    const out = [];
    style.triad_colours.forEach((colour, k) => {
      const tip = [0, 1, 2].map((c) => o[c] + length * T[c][k]);
      out.push({ kind: "line", points: [o, tip], colour, width, dash });
      if (!dash) out.push({ kind: "label", points: [tip], colour, text: "xyz"[k], bias: ON_TOP });
    });
    out.push({ kind: "label", points: [o], colour: style.text, text: name, shift, bias: ON_TOP });
    return out;
  }

  // a target with no orientation: a dashed circle about its point (parallel to the grid)
  function marker(p, r, name, shift) {
    const circle = [];
    for (let t = 0; t < 16; t++) {
      const a = (2 * Math.PI * t) / 16;
      circle.push([p[0] + r * Math.cos(a), p[1] + r * Math.sin(a), p[2]]);
    }
    return [
      { kind: "polygon", points: circle, fill: "rgba(0,0,0,0)", colour: style.text, width: 2,
        dash: [4, 3] },
      { kind: "label", points: [p], colour: style.text, text: name, shift, bias: ON_TOP },
    ];
  }

  function grid() {
    const out = [];
    const z = data.base[2][3];
    const step = data.grid.step, half = data.grid.half;
    const [cx, cy] = [data.base[0][3], data.base[1][3]];
    for (let v = -half; v <= half + 1e-9 * half; v += step) {
      const line = (a, b) => ({ kind: "line", points: [a, b], colour: style.grid, width: 1,
        bias: UNDER });
      out.push(line([cx + v, cy - half, z], [cx + v, cy + half, z]),
        line([cx - half, cy + v, z], [cx + half, cy + v, z]));
    }
    return out;
  }

  function armPrimitives(arm) {
    const out = grid();
    const pts = arm.points;
    for (let k = 0; k + 1 < pts.length; k++) {
      out.push({ kind: "line", points: [pts[k], pts[k + 1]], colour: style.link, width: 7 });
    }
    const r = style.joint_fraction * L;
    arm.joints.forEach((p, i) => {
      const z = arm.axes[i];
      const a = [0, 1, 2].map((c) => p[c] - 1.8 * r * z[c]);
      const b = [0, 1, 2].map((c) => p[c] + 1.8 * r * z[c]);
      out.push({ kind: "line", points: [a, b], colour: style.axis, width: 2, bias: -0.01 });
      out.push({
        kind: "polygon", points: chain.revolute[i] ? ring(p, z, r, 24) : ring(p, z, 1.4 * r, 4),
        fill: chain.revolute[i] ? style.revolute : style.prismatic, colour: style.edge,
        width: 1.5, bias: -0.02,
      });
    });
    out.push(...triad(data.base, triadLength, 2.5, "base", [8, 16]));
    out.push(...triad(arm.tool, triadLength, 3, "tool", [8, -8]));
    if (target && data.ik.target.orientation_given) {
      out.push(...triad(target, 1.2 * triadLength, 2, "target", [-52, 18], [5, 4]));
    } else if (target) {
      const p = [target[0][3], target[1][3], target[2][3]];
      out.push(...marker(p, 0.5 * triadLength, "target", [-52, 18]));
    }
    return out;
  }

  let scene = null;

  function setUpScene() {
    // frame the first configuration, the base and the target
    const arm = Kin.armPoints(chain, q, data.base, L);
    const pts = [...arm.points, ...arm.joints];
    if (target) pts.push([target[0][3], target[1][3], target[2][3]]);
    const lo = [0, 1, 2].map((c) => Math.min(...pts.map((p) => p[c])));
    const hi = [0, 1, 2].map((c) => Math.max(...pts.map((p) => p[c])));
    const centre = lo.map((v, c) => (v + hi[c]) / 2);
    const diagonal = Math.hypot(...hi.map((v, c) => v - lo[c]));
    const radius = Math.max(0.55 * diagonal, 0.3 * L) + triadLength;
    scene = Scene.create($("scene"), { centre, radius });
    document.querySelectorAll("input[name=projection]").forEach((r) =>
      r.addEventListener("change", () => scene.setProjection(r.value)));
    $("reset-view").addEventListener("click", () => scene.reset());
    window.addEventListener("resize", () => { fitJoints(); scene.draw(); });
  }

  let lastArm = null;

  function update() {
    lastArm = Kin.armPoints(chain, q, data.base, L);
    showPose(lastArm.tool);
    showMeasures(Kin.measures(chain, q, data, units.per_m));
    markSolution();
    scene.draw(armPrimitives(lastArm));
  }

  // --- for the browser's console and the tests: the state, to read ---------------

  window.kincalcView = {
    data,
    joints: () => q.slice(), // SI
    arm: () => lastArm, // the drawing's points, joints and tool pose, SI
    project: (p) => scene.project(p), // world point (m) -> [x, y, depth], canvas pixels
    animating: () => animation !== null,
  };

  buildHeader();
  buildJoints();
  buildDH();
  buildIK();
  setUpScene();
  syncControls();
  update();
  document.body.dataset.ready = "yes";
})();
