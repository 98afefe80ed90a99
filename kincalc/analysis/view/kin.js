// kincalc view: the kinematics of the page, from the chain kincalc exports.
//
//   T_world_tool(q) = F_0 J_1(q_1 + c_1) F_1 ... J_n(q_n + c_n) F_n
//
// F_i constant 4x4 transforms (metres), J_i a rotation about (revolute) or a translation
// along (prismatic) the local z axis; c_i the joint offsets. Everything here is SI
// (metres, radians); the page converts to the user's units at its edges. Matrices are
// arrays of rows, as in kincalc's JSON. The same definitions as kincalc's Python
// (kincalc/chain.py, fk.py, jacobian.py, spatial/angles.py, spatial/rotations.py,
// analysis/reports.py, analysis/plot/geometry.py); the browser tests check that the two
// agree to 1e-9.
"use strict";

const Kin = (() => {
  const EPS = 2.220446049250313e-16;
  const GIMBAL_TOL = 1e-9; // kincalc.tolerances.GIMBAL_TOL

  function matmul(A, B) {
    const n = A.length, m = B[0].length, k = B.length;
    const C = [];
    for (let i = 0; i < n; i++) {
      const row = new Array(m).fill(0);
      for (let j = 0; j < m; j++) {
        let s = 0;
        for (let t = 0; t < k; t++) s += A[i][t] * B[t][j];
        row[j] = s;
      }
      C.push(row);
    }
    return C;
  }

  // J_i(x): Rz(x) for a revolute joint, Tz(x) for a prismatic one
  function jointMotion(revolute, x) {
    if (revolute) {
      const c = Math.cos(x), s = Math.sin(x);
      return [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]];
    }
    return [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, x], [0, 0, 0, 1]];
  }

  // The world poses along the chain for joints q (n): before[i] = F_0 J_1 ... F_{i-1}
  // (z: joint i's axis, origin on it, before its motion), after[i] = before[i] J_i,
  // and the tool pose T_world_tool.
  function frames(chain, q) {
    const n = chain.revolute.length;
    if (q.length !== n) throw new Error(`expected ${n} joint values, got ${q.length}`);
    const before = [], after = [];
    let T = chain.fixed[0];
    for (let i = 0; i < n; i++) {
      before.push(T);
      T = matmul(T, jointMotion(chain.revolute[i], q[i] + chain.offset[i]));
      after.push(T);
      T = matmul(T, chain.fixed[i + 1]);
    }
    return { before, after, tool: T };
  }

  function fk(chain, q) {
    return frames(chain, q).tool;
  }

  const column = (T, j) => [T[0][j], T[1][j], T[2][j]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
    a[0] * b[1] - a[1] * b[0]];
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

  // The geometric Jacobian in the base (world) frame, 6 x n, rows vx vy vz wx wy wz:
  // a revolute column is [z_i x (p - o_i); z_i], a prismatic one [z_i; 0].
  function jacobian(chain, q) {
    const f = frames(chain, q);
    const p = column(f.tool, 3);
    const J = [[], [], [], [], [], []];
    f.before.forEach((F, i) => {
      const z = column(F, 2), o = column(F, 3);
      const v = chain.revolute[i] ? cross(z, sub(p, o)) : z;
      const w = chain.revolute[i] ? z : [0, 0, 0];
      for (let r = 0; r < 3; r++) { J[r].push(v[r]); J[r + 3].push(w[r]); }
    });
    return J;
  }

  // Singular values of an m x n matrix, largest first (min(m, n) of them): one-sided
  // Jacobi (Hestenes) on the columns, which keeps small singular values accurate to the
  // rounding of the matrix (what the singularity test needs), unlike the eigenvalues of
  // J J^T, whose square roots lose half the digits.
  function singularValues(A) {
    const m = A.length, n = A[0].length;
    const cols = [];
    for (let j = 0; j < n; j++) cols.push(A.map((row) => row[j]));
    for (let sweep = 0; sweep < 60; sweep++) {
      let rotated = false;
      for (let i = 0; i < n - 1; i++) {
        for (let j = i + 1; j < n; j++) {
          const a = dotN(cols[i], cols[i]), b = dotN(cols[j], cols[j]);
          const g = dotN(cols[i], cols[j]);
          if (Math.abs(g) <= EPS * Math.sqrt(a * b) || g === 0) continue;
          rotated = true;
          // the rotation that makes columns i and j orthogonal
          const zeta = (b - a) / (2 * g);
          const t = Math.sign(zeta || 1) / (Math.abs(zeta) + Math.sqrt(1 + zeta * zeta));
          const c = 1 / Math.sqrt(1 + t * t), s = c * t;
          for (let r = 0; r < m; r++) {
            const x = cols[i][r], y = cols[j][r];
            cols[i][r] = c * x - s * y;
            cols[j][r] = s * x + c * y;
          }
        }
      }
      if (!rotated) break;
    }
    const s = cols.map((c) => Math.sqrt(dotN(c, c))).sort((x, y) => y - x);
    return s.slice(0, Math.min(m, n));
  }

  function dotN(a, b) {
    let s = 0;
    for (let k = 0; k < a.length; k++) s += a[k] * b[k];
    return s;
  }

  // atan2(y, x) in (-pi, pi]: a y of rounding size against a negative x counts as +0, so
  // a half turn is +pi whatever the sign of the rounding (kincalc.spatial.angles)
  function turnAngle(y, x) {
    return Math.atan2(x < 0 && Math.abs(y) <= 4 * EPS * -x ? 0 : y + 0, x);
  }

  // Fixed X-Y-Z angles [roll, pitch, yaw] with R = Rz(yaw) Ry(pitch) Rx(roll), on the
  // branch cos(pitch) >= 0; at gimbal lock roll = 0 and the turn goes into yaw.
  function rpy(R) {
    const cp = Math.hypot(R[0][0], R[1][0]);
    let pitch = Math.atan2(-R[2][0], cp);
    if (cp < GIMBAL_TOL) {
      pitch = pitch < 0 || Object.is(pitch, -0) ? -Math.PI / 2 : Math.PI / 2;
      return [0, pitch, turnAngle(-R[0][1], R[1][1])];
    }
    return [turnAngle(R[2][1], R[2][2]), pitch, turnAngle(R[1][0], R[0][0])];
  }

  // Unit quaternion [w, x, y, z] with w >= 0, by Shepperd's method: the largest of the
  // four squared components from the diagonal, the others from off-diagonal sums.
  function quaternion(R) {
    const [m00, m11, m22] = [R[0][0], R[1][1], R[2][2]];
    const trace = m00 + m11 + m22;
    const d21 = R[2][1] - R[1][2], d02 = R[0][2] - R[2][0], d10 = R[1][0] - R[0][1];
    const s01 = R[0][1] + R[1][0], s02 = R[0][2] + R[2][0], s12 = R[1][2] + R[2][1];
    const cands = [trace, m00, m11, m22];
    const pick = cands.indexOf(Math.max(...cands));
    let q, t;
    if (pick === 0) {
      t = Math.sqrt(Math.max(1 + trace, 0)) * 2; // 4w
      q = [t / 4, d21 / t, d02 / t, d10 / t];
    } else if (pick === 1) {
      t = Math.sqrt(Math.max(1 + m00 - m11 - m22, 0)) * 2; // 4x
      q = [d21 / t, t / 4, s01 / t, s02 / t];
    } else if (pick === 2) {
      t = Math.sqrt(Math.max(1 - m00 + m11 - m22, 0)) * 2; // 4y
      q = [d02 / t, s01 / t, t / 4, s12 / t];
    } else {
      t = Math.sqrt(Math.max(1 - m00 - m11 + m22, 0)) * 2; // 4z
      q = [d10 / t, s02 / t, s12 / t, t / 4];
    }
    const norm = Math.hypot(...q);
    const sign = q[0] < 0 ? -1 : 1;
    return q.map((v) => (sign * v) / norm + 0);
  }

  // The Jacobian's measures at q, as kincalc jacobian reports them: the singular values
  // of J with its linear rows in the display length unit (lengthPerM), manipulability
  // their product over the arm's generic rank, and the rank test on J made scale-free
  // (linear rows divided by the robot's size, prismatic columns multiplied by it).
  function measures(chain, q, robot, lengthPerM) {
    const J = jacobian(chain, q);
    const n = q.length, L = robot.size;
    const shown = J.map((row, r) => row.map((v, j) =>
      (r < 3 && chain.revolute[j] ? v * lengthPerM : v)));
    const scaled = J.map((row, r) => row.map((v, j) => {
      const x = r < 3 ? v / L : v;
      return chain.revolute[j] ? x : x * L;
    }));
    const s = singularValues(shown);
    const sn = singularValues(scaled);
    const sp = singularValues(scaled.slice(0, 3));
    const rank = (sv) => sv.filter((x) => x > robot.singular_tol * Math.max(sv[0] || 0, 1)).length;
    const full = robot.generic_rank, fullPos = robot.generic_position_rank;
    let manip = 1;
    s.slice(0, full).forEach((x) => { manip *= x; });
    const r = rank(sn), rp = rank(sp);
    return {
      J, singular_values: s, manipulability: n ? manip : 0,
      rank: r, position_rank: rp, singular: r < full || rp < fullPos,
      // how far from a singularity, scale-free: 0 at one, 1 for an isotropic arm
      inverse_condition: full && sn[0] > 0 ? sn[full - 1] / sn[0] : 0,
    };
  }

  // Where the drawing puts the arm (kincalc.analysis.plot.geometry): joints on their
  // axes (a prismatic joint where its travel starts) and the polyline from the base
  // origin through every joint to the tool point; a link with a component along the
  // previous joint axis is drawn as an L, first along the axis, then across.
  function armPoints(chain, q, base, size) {
    const f = frames(chain, q);
    const joints = f.after.map((F, i) => {
      const travel = chain.revolute[i] ? 0 : q[i] + chain.offset[i];
      const z = column(F, 2), o = column(F, 3);
      return [o[0] - z[0] * travel, o[1] - z[1] * travel, o[2] - z[2] * travel];
    });
    const pts = [column(base, 3)];
    const add = (p, force) => {
      const last = pts[pts.length - 1];
      if (force || Math.hypot(...sub(p, last)) > 1e-9 * size) pts.push(p);
    };
    const leg = (origin, axis, target) => {
      const along = dot(sub(target, origin), axis);
      const corner = [0, 1, 2].map((k) => origin[k] + axis[k] * along);
      const tiny = 1e-6 * size;
      if (Math.hypot(...sub(corner, origin)) > tiny && Math.hypot(...sub(target, corner)) > tiny) {
        add(corner);
      }
      add(target, true);
    };
    let here = column(base, 3), axis = column(base, 2);
    f.after.forEach((F, i) => {
      leg(here, axis, joints[i]);
      here = column(F, 3);
      axis = column(F, 2);
      if (!chain.revolute[i]) add(here);
    });
    leg(here, axis, column(f.tool, 3));
    return { points: pts, joints, axes: f.after.map((F) => column(F, 2)), tool: f.tool };
  }

  return { matmul, frames, fk, jacobian, singularValues, rpy, quaternion, measures, armPoints };
})();

if (typeof module !== "undefined") module.exports = Kin; // node, for the tests
